"""The tool flow around the gateware: Verilog generation with its manifest
(:mod:`~dptbd.hw.flow.verilog`), synthesis and place-and-route for cost and timing on iCE40 and ECP5
(:mod:`~dptbd.hw.flow.synth`, the flow, over :mod:`~dptbd.hw.flow.family`,
:mod:`~dptbd.hw.flow.tools`, :mod:`~dptbd.hw.flow.variants`, :mod:`~dptbd.hw.flow.yosys` and :mod:`~dptbd.hw.flow.nextpnr`; the options a user passes
through to them, :mod:`~dptbd.hw.flow.passthrough`), and the source hash that
keys every cache built from the gateware (:mod:`~dptbd.hw.flow.source_hash`). The
components themselves are the flat modules of :mod:`dptbd.hw`.
"""
