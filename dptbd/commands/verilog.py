"""``dptbd verilog``: write the DP pipeline's top-level Verilog and its manifest.

``--top dp`` (default) converts the DP pipeline (``dptbd_dp``). ``--top seg`` converts the
pipeline with the segmenter (``dptbd_seg``: pixels in, candidate lists out,
:func:`dptbd.hw.flow.segmenter_verilog.generate_segmenter_verilog`). ``--top axi`` converts
the AXI top level ``dptbd_axi`` (AXI4-Stream video in, candidate lists out, AXI4-Lite
registers; ``docs/integration.md``) and writes, beside ``FILE.v`` and ``FILE.json``, the
register header ``dptbd_regs.h``, the ``aclk`` constraints ``FILE.sdc`` / ``FILE.xdc`` at
``--clock-mhz`` (default 100), the IP-XACT component ``component.xml`` (Vivado's block
designs; :mod:`dptbd.hw.flow.ipxact`), the FuseSoC core ``FILE.core``
(:func:`dptbd.hw.flow.axi_package.axi_package`) and the register map's PeakRDL references:
Markdown ``FILE_regs.md``, IP-XACT ``FILE_regs.xml`` and HTML ``FILE_regs_html/``.

Parameters come from options named after the :class:`~dptbd.config.DPConfig` fields, from a
TOML file of those fields (``--config``; unknown keys are refused), or both (options win).
The manifest JSON beside the Verilog lists the parameters, the weight LUT storage
(``lut_style``), derived widths, weight codes, every port with direction and width, the
latency and the payload bit fields (:func:`dptbd.hw.flow.verilog.manifest`). ``--lut-style``
chooses the weight LUT's storage (``auto``, the default: logic for r = 1, block RAM for
r = 2; ``bram``; ``logic``), a synthesis choice that does not change behaviour.
``--family ice40|ecp5`` builds the DPCore of every top with the implementation options the
synthesis flow uses for that family and size (:meth:`~dptbd.hw.flow.family.Family.options_for`, the
ones measured in ``docs/synthesis.md``; every manifest records them under ``core_options``)
and refuses a radius the family cannot build (:meth:`~dptbd.hw.flow.family.Family.check_radius`).
Without ``--family`` every top is built with DPCore's defaults.

``--state-store axi`` builds ``dptbd_dp`` (``--top dp``) or ``dptbd_axi`` (``--top axi``)
with the state in external memory behind an AXI4 manager port ``m_axi_state_*``
(:class:`~dptbd.hw.axi_store.pipeline.DPPipelineAxi`,
:class:`~dptbd.hw.axi_store.top.AXITopStore`; the layout is :meth:`DPConfig.axi_store` of
``--axi-data-bits``, ``--axi-burst-beats``, ``--axi-id-bits``, ``--axi-address-bits``,
``--axi-outstanding`` and ``--state-base``, each refused with its limit when the layout
cannot use it; the manifest records it under ``state_store``; ``dptbd_axi`` adds the
registers ``STATE_BASE``, ``STATE_BASE_ACTIVE``, ``STATE_READ_ERRORS``,
``STATE_WRITE_ERRORS`` and two ERROR bits, and takes at most 32 address bits).
``dptbd_seg`` keeps its state on chip.

The build is :meth:`DPConfig.build_config` of the parameters: B_E narrowed to what K_max
full-scale pixels need and, for a binary weight LUT, F = 0 (the same bits as asked;
``--fractional-lut`` keeps F so fractional weights can be written at run time). ``--top axi``
refuses a configuration whose E can saturate unless ``--allow-saturation``.

``--pixels-per-clock P`` (2 or 4) builds ``dptbd_dp``, ``dptbd_seg`` or ``dptbd_axi`` for P
pixels per clock: input beats of P pixels (``dptbd_axi``: ``s_axis_video`` with P pixels per
beat, pixel 0 in the low bits), output beats of P states (``dptbd_dp``) or the candidate
lists of P = 1 (:mod:`dptbd.hw.wide`; ``docs/gateware.md``, "P pixels per clock"); the
manifest's ``layouts`` are the beats'. ``dptbd_axi`` at P > 1 has no ``--state-output``.
``dptbd_dp`` and ``dptbd_axi`` with ``--state-store axi`` move store words of P states over
the AXI4 port in the same byte layout as at P = 1 (``--axi-data-bits`` must hold P state
slots).
"""

from __future__ import annotations

import argparse
import json
import pathlib
import warnings

from dptbd.commands.options import add_config_arguments, config_from_args
from dptbd.config import EnergyWidthWarning
from dptbd.output_folder import check_new_files

__all__ = ["TOPS", "add_arguments", "main"]

#: The modules ``--top`` selects: ``dptbd_dp``, ``dptbd_seg``, ``dptbd_axi``.
TOPS = ("dp", "seg", "axi")

#: ``--state-store axi`` options: (option, AxiStoreConfig field).
AXI_STORE_OPTIONS = (("--axi-data-bits", "data_bits"), ("--axi-burst-beats", "burst_beats"),
                     ("--axi-id-bits", "id_bits"), ("--axi-address-bits", "address_bits"),
                     ("--axi-outstanding", "outstanding"), ("--state-base", "base_address"))


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("-o", "--output", type=pathlib.Path, required=True, metavar="FILE.v",
                        help="Verilog file to write; the manifest goes to FILE.json beside it")
    parser.add_argument("--force", action="store_true", help="overwrite existing files")
    parser.add_argument("--top", choices=TOPS, default="dp",
                        help="dp: the DP pipeline dptbd_dp (default); seg: the pipeline and "
                             "the segmenter, dptbd_seg; axi: the AXI top level dptbd_axi with "
                             "its register header and references (Markdown, IP-XACT, HTML), "
                             "IP-XACT component.xml and FuseSoC core")
    parser.add_argument("--external-state-store", action="store_true",
                        help="convert DPCore: the W*H-word state store outside the module")
    parser.add_argument("--lut-style", choices=("auto", "bram", "logic"), default="auto",
                        help="weight LUT storage: auto (default; logic for r = 1, block RAM "
                             "for r = 2), bram (one block RAM per move), logic (flip-flops and "
                             "multiplexers, no block RAM; lets the 64x64 top level fit an "
                             "iCE40-HX8K)")
    parser.add_argument("--pixels-per-clock", type=int, default=None, metavar="P",
                        help="pixels per clock and per input beat, 1 (default), 2 "
                             "or 4 (W a multiple of P; docs/gateware.md, \"P pixels per "
                             "clock\"); overrides the TOML's pixels_per_clock")
    parser.add_argument("--family", choices=("ice40", "ecp5"), default=None,
                        help="every --top: build DPCore with the implementation options measured "
                             "best for this FPGA family (ice40: line buffer in block RAM, side "
                             "band in a block RAM, compact max tree; ecp5: line buffer in LUT "
                             "RAM, side band in registers, max tree split over two stages per "
                             "level, +4 cycles, block RAMs through their output register, the "
                             "segmenter's and dptbd_axi's control from registers of its own) "
                             "and refuse what it cannot build (a radius above "
                             "1 on ice40); default: DPCore's defaults (block RAM, registers, "
                             "compact)")
    parser.add_argument("--clock-mhz", type=float, default=None, metavar="MHZ",
                        help="--top axi: aclk frequency of the shipped SDC/XDC constraints, "
                             "in [1, 1000] (default 100, the synthesis target)")
    parser.add_argument("--state-output", action="store_true",
                        help="--top axi: also bring out the per-pixel (E, d) stream as "
                             "m_axis_state (back-pressure on it stalls the core)")
    parser.add_argument("--fractional-lut", action="store_true",
                        help="keep F fractional weight bits so the LUT can be rewritten with "
                             "fractional weights at run time; by default a binary LUT builds "
                             "with F = 0 and B_E narrowed to what K_max needs (the same bits, "
                             "DPConfig.build_config)")
    parser.add_argument("--allow-saturation", action="store_true",
                        help="--top axi: build even if K_max full-scale pixels can saturate E "
                             "(refused by default)")
    parser.add_argument("--state-store", choices=("chip", "axi"), default="chip",
                        help="--top dp, --top axi: chip (default): the state store in block "
                             "RAM; axi: in external memory behind the AXI4 manager port "
                             "m_axi_state_* "
                             "(docs/integration.md, \"State store in external memory\")")
    axi = parser.add_argument_group("--state-store axi (defaults: AxiStoreConfig's)")
    axi.add_argument("--axi-data-bits", type=int, default=None,
                     help="AXI4 data width: 32, 64 (default) or 128")
    axi.add_argument("--axi-burst-beats", type=int, default=None,
                     help="beats of a full INCR burst, a power of two, at most 4096 bytes "
                          "(default 16)")
    axi.add_argument("--axi-id-bits", type=int, default=None,
                     help="width of the AXI ID signals, in [1, 16] (default 1; ID 0 is used)")
    axi.add_argument("--axi-address-bits", type=int, default=None,
                     help="width of ARADDR / AWADDR, in [12, 64] (default 32)")
    axi.add_argument("--axi-outstanding", type=int, default=None,
                     help="most bursts in flight per direction, in [1, 16] (default 4)")
    axi.add_argument("--state-base", type=lambda text: int(text, 0), default=None,
                     metavar="ADDRESS",
                     help="reset value of the state's base address, a multiple of the burst "
                          "size (default 0; 0x… accepted)")
    add_config_arguments(parser)


def _axi_store(args: argparse.Namespace, cfg):
    """The :class:`~dptbd.config.AxiStoreConfig` asked for, or None for the on-chip store."""
    given = [option for option, field in AXI_STORE_OPTIONS
             if getattr(args, field_attr(option)) is not None]
    if args.state_store != "axi":
        if given:
            verb = "applies" if len(given) == 1 else "apply"
            raise ValueError(f"{', '.join(given)} {verb} to --state-store axi only")
        return None
    if args.top == "seg":
        raise ValueError("--state-store axi applies to --top dp and --top axi only; dptbd_seg "
                         "keeps its state store on chip")
    if args.external_state_store:
        raise ValueError("--state-store axi and --external-state-store exclude each other: "
                         "the state store is either behind the AXI4 port or outside the "
                         "module")
    return cfg.axi_store(**{field: getattr(args, field_attr(option))
                            for option, field in AXI_STORE_OPTIONS
                            if getattr(args, field_attr(option)) is not None})


def field_attr(option: str) -> str:
    """The argparse attribute of ``option``: ``--axi-data-bits`` -> ``axi_data_bits``."""
    return option[2:].replace("-", "_")


def _core_options(args: argparse.Namespace, cfg) -> dict | None:
    """The DPCore options of ``--family`` (``None`` without it: DPCore's defaults); refuses a
    radius the family cannot build."""
    if args.family is None:
        return None
    from dptbd.hw.flow.family import get_family
    family = get_family(args.family)
    family.check_radius(cfg)
    return family.options_for(cfg)


def _write_seg(args: argparse.Namespace, cfg, core_options: dict | None) -> int:
    from dptbd.hw.flow.segmenter_verilog import generate_segmenter_verilog

    out = args.output
    manifest = out.with_suffix(".json")
    check_new_files([out, manifest], args.force)
    text, info = generate_segmenter_verilog(cfg, core_options=core_options)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(text)
    manifest.write_text(json.dumps(info, indent=2) + "\n")
    print(f"wrote {out} (module {info['module']}, {info['top']}, {text.count(chr(10))} lines) "
          f"and {manifest}")
    print(f"  {cfg.describe()}; latency {info['latency']} cycles")
    _print_core_options(args, info)
    return 0


def _print_core_options(args: argparse.Namespace, info: dict) -> None:
    print("  core options: " + ", ".join(f"{k}={v}" for k, v in info["core_options"].items())
          + ("" if args.family is None else f" (the {args.family} build)"))


def _write_axi(args: argparse.Namespace, cfg, core_options: dict | None,
               state_store=None) -> int:
    from dptbd.hw.flow.axi_package import (DEFAULT_CLOCK_MHZ, axi_package, check_clock_mhz,
                                           html_folder_name, package_file_names,
                                           write_html_reference)

    clock_mhz = check_clock_mhz(DEFAULT_CLOCK_MHZ if args.clock_mhz is None else args.clock_mhz,
                                "--clock-mhz")
    out = args.output
    check_new_files([out.parent / name for name in
                     (*package_file_names(out.stem), html_folder_name(out.stem))], args.force)
    files = axi_package(cfg, out.stem, clock_mhz, state_output=args.state_output,
                        allow_saturation=args.allow_saturation, core_options=core_options,
                        state_store=state_store)
    out.parent.mkdir(parents=True, exist_ok=True)
    for name, text in files.items():
        (out.parent / name).write_text(text)
    write_html_reference(out.parent, cfg, out.stem, state_store)
    info = json.loads(files[f"{out.stem}.json"])
    names = [*files, f"{html_folder_name(out.stem)}/"]
    print(f"wrote {', '.join(str(out.parent / n) for n in names)} (module {info['module']}, "
          f"{cfg.width}x{cfg.height}, latency {info['latency']} cycles, aclk "
          f"{clock_mhz:g} MHz)")
    _print_core_options(args, info)
    if state_store is not None:
        _print_state_store(state_store)
    return 0


def _check_top_options(args: argparse.Namespace) -> None:
    """Refuse an option the chosen ``--top`` does not take, before anything is built."""
    if args.top != "dp" and (args.external_state_store or args.lut_style != "auto"):
        raise ValueError(f"--external-state-store and --lut-style apply to --top dp only; "
                         f"--top {args.top} keeps the state store on chip with the automatic "
                         f"LUT style")
    if args.top == "axi":
        return
    shipped = {"dp": "dptbd_dp", "seg": "dptbd_seg"}[args.top]
    if args.clock_mhz is not None:
        raise ValueError(f"--clock-mhz applies to --top axi only ({shipped} ships no "
                         f"constraints)")
    if args.allow_saturation:
        raise ValueError("--allow-saturation applies to --top axi only")
    if args.state_output:
        raise ValueError("--state-output applies to --top axi only (dptbd_dp always outputs "
                         "its states)" if args.top == "dp" else
                         "--state-output applies to --top axi only")


def main(args: argparse.Namespace) -> int:
    from dptbd.hw.flow.verilog import generate_verilog

    out = args.output
    if out.suffix == ".json":
        raise ValueError(f"output {out} would collide with its manifest; use a .v name")
    _check_top_options(args)
    manifest = out.with_suffix(".json")
    asked = config_from_args(args)
    if args.pixels_per_clock is not None:
        with warnings.catch_warnings():     # config_from_args printed it already
            warnings.simplefilter("ignore", EnergyWidthWarning)
            asked = asked.replace(pixels_per_clock=args.pixels_per_clock)
    if asked.pixels_per_clock > 1 and args.state_output:
        raise ValueError(f"pixels_per_clock={asked.pixels_per_clock} has no m_axis_state; "
                         f"--state-output takes one pixel per clock")
    cfg = asked.build_config(fractional_lut=args.fractional_lut)
    if cfg != asked:
        print(f"building B_E={cfg.energy_bits}, F={cfg.weight_frac_bits} (asked "
              f"B_E={asked.energy_bits}, F={asked.weight_frac_bits}): the same bits for this LUT "
              f"and K_max={asked.k_max}"
              + ("" if args.fractional_lut or cfg.weight_frac_bits == asked.weight_frac_bits
                 else "; --fractional-lut keeps F"))
    state_store = _axi_store(args, cfg)
    core_options = _core_options(args, cfg)
    if args.top == "axi":
        return _write_axi(args, cfg, core_options, state_store)
    if args.top == "seg":
        return _write_seg(args, cfg, core_options)
    check_new_files([out, manifest], args.force)
    text, info = generate_verilog(cfg, external_state_store=args.external_state_store,
                                  lut_style=args.lut_style, core_options=core_options,
                                  state_store=state_store)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(text)
    manifest.write_text(json.dumps(info, indent=2) + "\n")
    ports = ", ".join(f"{p['name']}[{p['width']}]" for p in info["ports"])
    print(f"wrote {out} (module {info['module']}, {info['top']}, {text.count(chr(10))} lines) "
          f"and {manifest}")
    print(f"  {cfg.describe()}; weight LUT in {info['lut_style']}; latency {info['latency']} cycles")
    _print_core_options(args, info)
    if state_store is not None:
        _print_state_store(state_store)
    print(f"  ports: {ports}")
    return 0


def _print_state_store(store) -> None:
    print(f"  state store: AXI4 {store.data_bits}-bit, {store.states_per_beat} states of "
          f"{store.slot_bits} bits per beat, bursts of {store.burst_beats} beats, "
          f"{store.frame_bytes} bytes per frame from {store.base_address:#x}")
