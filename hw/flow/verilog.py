"""Verilog generation of the DP pipeline, with a JSON manifest for the HDL testbenches.

``generate_verilog(cfg)`` converts :class:`~dptbd.hw.dp_pipeline.DPPipeline` (or, with
``external_state_store=True``, :class:`~dptbd.hw.dp_core.DPCore`; with ``state_store=`` an
:class:`~dptbd.config.AxiStoreConfig`, :class:`~dptbd.hw.axi_store.pipeline.DPPipelineAxi`,
the state in external memory over AXI4) to one Verilog module and
describes it in a manifest: the configuration, the weight LUT's storage (``lut_style``),
the derived widths, every port with its direction and width, the latency, and the bit
fields of the stream payloads. A cocotb
testbench reads the manifest instead of hard-coding any of these.

Command line::

    python -m dptbd.hw.flow.verilog --out build/dptbd_dp.v [--width 128 --height 128 …]
                               [--lut-style {auto,bram,logic}]

writes ``build/dptbd_dp.v`` and ``build/dptbd_dp.json``.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import pathlib
from typing import Mapping

from amaranth.hdl import Shape
from amaranth.lib import wiring

from dptbd.config import AxiStoreConfig, DPConfig
from dptbd.hw.dp_core import DPCore
from dptbd.hw.dp_pipeline import DPPipeline
from dptbd.hw.flow.to_verilog import to_verilog
from dptbd.hw.layouts import field_offsets, pixel_layout, state_layout, state_word_layout
from dptbd.hw.weight_lut import LUT_STYLES

__all__ = ["MODULE_NAME", "VERILATOR_LINT_FLAGS", "build_top", "port_list", "manifest_header",
           "manifest_interface", "manifest", "generate_verilog", "main"]

#: Name of the generated Verilog module.
MODULE_NAME = "dptbd_dp"

#: Verilator options under which the generated Verilog lints clean; each waiver is justified
#: in ``docs/gateware.md`` ("Verilog").
VERILATOR_LINT_FLAGS = (
    "--lint-only", "-Wall",
    "-Wno-WIDTH",          # Yosys' write_verilog extends/truncates operands implicitly
    "-Wno-UNUSEDSIGNAL",   # Amaranth keeps a named wire for every signal/field, used or not
    "-Wno-DECLFILENAME",   # submodules are named dptbd_dp.core, … in the same file
)


def build_top(cfg: DPConfig, *, external_state_store: bool = False, lut_style: str = "auto",
              core_options: Mapping[str, str] | None = None,
              state_store: AxiStoreConfig | None = None):
    """The top-level component: ``DPPipeline(cfg)``, or ``DPCore(cfg)`` without a store, or
    ``DPPipelineAxi(state_store)`` with the store in external memory (``state_store.frame``
    must be ``cfg``); at ``cfg.pixels_per_clock`` 2 or 4 ``DPPipelineWide(cfg)`` or
    ``DPCoreWide(cfg)`` (:mod:`dptbd.hw.wide`), and ``DPPipelineAxi`` around a
    ``DPCoreWide`` with ``state_store``.

    ``lut_style`` (``"auto"``, ``"bram"``, ``"logic"``) is passed on (weight LUT storage),
    and so are ``core_options`` (:data:`~dptbd.hw.dp_core.CORE_OPTIONS`, e.g.
    ``{"line_buffer_style": "lutram"}``; default: DPCore's defaults).
    """
    if state_store is not None:
        if external_state_store:
            raise ValueError("external_state_store and state_store exclude each other: the "
                             "state store is either outside the module or behind its AXI4 "
                             "port")
        if state_store.frame != cfg:
            raise ValueError("state_store was made for another configuration than cfg")
        from dptbd.hw.axi_store.pipeline import DPPipelineAxi
        return DPPipelineAxi(state_store, lut_style=lut_style, **dict(core_options or {}))
    if cfg.pixels_per_clock > 1:        # docs/gateware.md, "P pixels per clock"
        from dptbd.hw.wide import DPCoreWide, DPPipelineWide
        kind = DPCoreWide if external_state_store else DPPipelineWide
        return kind(cfg, lut_style=lut_style, **dict(core_options or {}))
    kind = DPCore if external_state_store else DPPipeline
    return kind(cfg, lut_style=lut_style, **dict(core_options or {}))


def port_list(top: wiring.Component) -> list[dict]:
    """Ports of ``top`` as Verilog sees them: ``clk``, ``rst``, then every member.

    Member paths are joined with ``__`` (``pixels.payload`` becomes ``pixels__payload``),
    which is how :func:`amaranth.back.verilog.convert` names them.
    """
    ports = [
        {"name": "clk", "direction": "input", "width": 1},
        {"name": "rst", "direction": "input", "width": 1},
    ]
    for path, member, _value in top.signature.flatten(top):
        ports.append({
            "name": "__".join(map(str, path)),
            "direction": "input" if member.flow == wiring.In else "output",
            "width": Shape.cast(member.shape).width,
        })
    return ports


def manifest_header(cfg: DPConfig, module: str, top) -> dict:
    """The first entries of every module's manifest: ``module``, ``top`` (the component's
    class) and ``parameters`` (every :class:`~dptbd.config.DPConfig` field but the weights)."""
    return {
        "module": module,
        "top": type(top).__name__,
        "parameters": {f.name: getattr(cfg, f.name) for f in dataclasses.fields(cfg)
                       if f.name != "weights"},
    }


def manifest_interface(cfg: DPConfig) -> dict:
    """The entries every manifest has after its ``derived`` quantities: the initial LUT
    codes, the clock and the reset."""
    return {
        "weight_codes": cfg.weight_codes.tolist(),
        "clock": {"name": "clk", "edge": "rising"},
        "reset": {"name": "rst", "polarity": "active_high", "kind": "synchronous"},
    }


def manifest_state_store(store: AxiStoreConfig) -> dict:
    """The ``state_store`` entry of a build with the state in external memory: its AXI4
    parameters and memory layout (``docs/integration.md``)."""
    names = ("data_bits", "id_bits", "burst_beats", "address_bits", "base_address",
             "outstanding", "slot_bits", "states_per_beat", "beat_bytes", "burst_bytes",
             "frame_bytes")
    return {"kind": "axi4", "prefix": "m_axi_state",
            **{name: getattr(store, name) for name in names}}


def manifest(cfg: DPConfig, top) -> dict:
    """Machine-readable description of the generated module (JSON-serialisable)."""
    schedule = top.schedule
    store = getattr(top, "store", None)
    return {
        **manifest_header(cfg, MODULE_NAME, top),
        "lut_style": top.lut_style,
        "core_options": top.core_options,
        "derived": {
            "n_moves": cfg.n_moves,
            "start_code": cfg.start_code,
            "direction_bits": cfg.direction_bits,
            "weight_bits": cfg.weight_bits,
            "e_max": cfg.e_max,
            "lut_entries": cfg.lut_entries,
        },
        **manifest_interface(cfg),
        "latency": schedule.latency,
        "write_latency": schedule.write_latency,
        "schedule": dataclasses.asdict(schedule),
        "output_fifo_depth": top.output_fifo_depth,
        "ports": port_list(top),
        "layouts": {
            "pixel": field_offsets(_beat_layouts(cfg)[0]),
            "state": field_offsets(_beat_layouts(cfg)[1]),
            "state_word": field_offsets(state_word_layout(cfg)),
        },
        **({} if store is None else {"state_store": manifest_state_store(store)}),
    }


def _beat_layouts(cfg: DPConfig) -> tuple:
    """The ``pixels`` and ``states`` payload layouts of ``dptbd_dp`` for ``cfg``: one pixel at
    P = 1, one beat of P pixels otherwise (:mod:`dptbd.hw.wide`)."""
    if cfg.pixels_per_clock == 1:
        return pixel_layout(cfg), state_layout(cfg)
    from dptbd.hw.wide import wide_pixel_layout, wide_state_layout
    return wide_pixel_layout(cfg), wide_state_layout(cfg)


def generate_verilog(cfg: DPConfig, *, external_state_store: bool = False,
                     lut_style: str = "auto", core_options: Mapping[str, str] | None = None,
                     manifest_path: str | pathlib.Path | None = None,
                     state_store: AxiStoreConfig | None = None) -> tuple[str, dict]:
    """Convert the pipeline for ``cfg`` to Verilog.

    Parameters
    ----------
    cfg : DPConfig
        The configuration (refused if the gateware does not support it).
    external_state_store : bool
        Convert :class:`DPCore` (state-store port on the module boundary) instead of
        :class:`DPPipeline` (on-chip state store).
    lut_style : {"auto", "bram", "logic"}
        Weight LUT storage (:class:`~dptbd.hw.weight_lut.WeightLUT`): ``"logic"`` emits
        ``(* ram_style = "logic" *)`` on the LUT's column memories, ``"bram"`` leaves them
        to RAM inference; ``"auto"`` is logic for r = 1, block RAM for r = 2. The manifest
        records the resolved style under ``lut_style``.
    core_options : Mapping[str, str], optional
        DPCore's storage options (:data:`~dptbd.hw.dp_core.CORE_OPTIONS`: line buffer in
        block RAM or LUT RAM, side band in registers or a block RAM); none changes
        behaviour or latency. The manifest records them under ``core_options``.
    manifest_path : path-like, optional
        Also write the manifest there as JSON.
    state_store : AxiStoreConfig, optional
        Convert :class:`~dptbd.hw.axi_store.pipeline.DPPipelineAxi` (the state in external
        memory behind the ``m_axi_state_*`` AXI4 port, laid out as ``state_store`` says);
        the manifest gets a ``state_store`` entry.

    Returns
    -------
    tuple of (str, dict)
        The Verilog text of module ``dptbd_dp`` and its manifest.
    """
    top = build_top(cfg, external_state_store=external_state_store, lut_style=lut_style,
                    core_options=core_options, state_store=state_store)
    text = to_verilog(top, MODULE_NAME)
    info = manifest(cfg, top)
    if manifest_path is not None:
        pathlib.Path(manifest_path).write_text(json.dumps(info, indent=2) + "\n")
    return text, info


def main(argv=None) -> int:
    """Command-line entry point: write ``<out>.v`` and ``<out>.json``."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", required=True, help="Verilog file to write")
    parser.add_argument("--external-state-store", action="store_true",
                        help="convert DPCore (state store outside the module)")
    parser.add_argument("--lut-style", choices=LUT_STYLES, default="auto",
                        help="weight LUT storage: block RAM, logic, or auto (logic for r = 1, "
                             "block RAM for r = 2; default)")
    defaults = DPConfig()
    for f in dataclasses.fields(DPConfig):
        if f.name in ("weights", "segment_stride"):
            continue
        kind = str if f.name == "rounding" else int
        parser.add_argument("--" + f.name.replace("_", "-"), type=kind,
                            default=getattr(defaults, f.name))
    args = parser.parse_args(argv)
    cfg = DPConfig(**{f.name: getattr(args, f.name) for f in dataclasses.fields(DPConfig)
                      if f.name not in ("weights", "segment_stride")})
    out = pathlib.Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    text, _ = generate_verilog(cfg, external_state_store=args.external_state_store,
                               lut_style=args.lut_style, manifest_path=out.with_suffix(".json"))
    out.write_text(text)
    print(f"wrote {out} and {out.with_suffix('.json')}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
