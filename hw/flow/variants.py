"""The designs the synthesis flow builds (:func:`~dptbd.hw.flow.synth.synthesize`'s
``variant``): what each variant is and the Verilog of its module ``dptbd_dp``."""

from __future__ import annotations

import pathlib
from typing import Mapping

from dptbd.config import DPConfig

__all__ = ["VARIANTS", "ON_CHIP_STORE", "SEGMENTER_TOPS", "variant_verilog"]

#: ``"core"``: DPCore, state store outside (port ``state_store__*``); ``"top"``: DPPipeline
#: (on-chip store); ``"segmenter"``: DPSegmenter (DPPipeline and Segmenter);
#: ``"core-regio"``: DPCore behind a register on every port
#: (:class:`~dptbd.hw.flow.registered_ports.RegisteredPorts`: its Fmax without the pins'
#: pull on the core's registers; its cells include the port registers);
#: ``"axi-regio"``: the AXI top level (on-chip store) behind a register on every port but
#: ``aclk`` / ``aresetn`` the same way;
#: ``"segmenter-ext"``: DPSegmenter with the state store outside (``state_store__*``);
#: ``"axi"``: the AXI top level (:class:`~dptbd.hw.axi_top.AXITop`, on-chip store);
#: ``"axi-ext"``: AXITop with the state store outside, its ports folded onto two pins
#: (:class:`~dptbd.hw.flow.registered_ports.FoldedPorts`: 221 ports do not fit the HX8K's
#: 206 I/O; its cells include about one flip-flop per port bit).
#: ``"core-folded"``: ``"core"``'s module with its ports folded onto two pins the same way
#: (DPCoreWide's state-store ports at 4 pixels per clock exceed the ECP5 CABGA256's I/O).
#: ``"dp-axi"``: ``dptbd_dp --state-store axi`` (the DP core with its state in external
#: memory behind the AXI4 port, ``cfg.axi_store()``'s defaults: 64-bit, bursts of 16, 4
#: outstanding), its ports folded onto two pins the same way; ``"axi-store"``: ``dptbd_axi
#: --state-store axi`` (:class:`~dptbd.hw.axi_store.top.AXITopStore`, the same store), its
#: ports folded.
VARIANTS = ("core", "top", "segmenter", "core-regio", "segmenter-ext", "axi",
            "axi-ext", "core-folded", "dp-axi", "axi-store", "axi-regio")

#: The variants with the W*H-word state store on chip (checked against the device's block
#: RAM before any tool runs).
ON_CHIP_STORE = ("top", "segmenter", "axi", "axi-regio")

#: The variants of a segmenter top (DPSegmenter, AXITop): the weight LUT's style is automatic.
SEGMENTER_TOPS = ("segmenter", "segmenter-ext", "axi", "axi-ext", "axi-store", "axi-regio")


def variant_verilog(cfg: DPConfig, variant: str, lut_style: str, core_options: Mapping,
                    work: pathlib.Path) -> str:
    """The Verilog text of module ``dptbd_dp`` for ``variant`` (its manifest beside it for
    ``core`` / ``top``)."""
    from dptbd.hw.flow.verilog import MODULE_NAME, build_top, generate_verilog  # on demand
    if variant in ("core-regio", "core-folded"):
        from dptbd.hw.flow.registered_ports import FoldedPorts, RegisteredPorts
        from dptbd.hw.flow.to_verilog import to_verilog
        core = build_top(cfg, external_state_store=True, lut_style=lut_style,
                         core_options=core_options)
        wrap = RegisteredPorts if variant == "core-regio" else FoldedPorts
        return to_verilog(wrap(core), MODULE_NAME)
    if variant == "dp-axi":
        from dptbd.hw.flow.registered_ports import FoldedPorts
        from dptbd.hw.flow.to_verilog import to_verilog
        top = build_top(cfg, lut_style=lut_style, core_options=core_options,
                        state_store=cfg.axi_store())
        return to_verilog(FoldedPorts(top), MODULE_NAME)
    if variant == "axi-store":
        from dptbd.hw.axi_store.top import AXITopStore
        from dptbd.hw.flow.registered_ports import FoldedPorts
        from dptbd.hw.flow.to_verilog import to_verilog
        top = AXITopStore(cfg.axi_store(), core_options=core_options)
        return to_verilog(FoldedPorts(top), MODULE_NAME)
    if variant in ("core", "top"):
        text, _ = generate_verilog(cfg, external_state_store=(variant == "core"),
                                   lut_style=lut_style, core_options=core_options,
                                   manifest_path=work / "dptbd_dp.json")
        return text
    from dptbd.hw.flow.to_verilog import to_verilog
    external = variant.endswith("-ext")
    if variant.startswith("axi"):
        from dptbd.hw.axi_top import AXITop
        from dptbd.hw.flow.registered_ports import FoldedPorts, RegisteredPorts
        top = AXITop(cfg, core_options=core_options, external_state_store=external)
        wrap = (FoldedPorts if external else RegisteredPorts if variant == "axi-regio"
                else None)
        return to_verilog(top if wrap is None else wrap(top), MODULE_NAME)
    from dptbd.hw.dp_segmenter_top import DPSegmenter
    return to_verilog(DPSegmenter(cfg, core_options=core_options,
                                  external_state_store=external), MODULE_NAME)
