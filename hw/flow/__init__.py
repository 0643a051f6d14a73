"""The tool flow around the gateware: Verilog generation with its manifest
(:mod:`~dptbd.hw.flow.verilog`), synthesis and place-and-route for cost and timing
(:mod:`~dptbd.hw.flow.synth`), and the source hash that keys every cache built from the
gateware (:mod:`~dptbd.hw.flow.source_hash`). The components themselves are the flat
modules of :mod:`dptbd.hw`.
"""
