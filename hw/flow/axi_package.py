"""The HDL user's package of ``dptbd_axi``: Verilog, manifest, register header and a FuseSoC
core description, as texts (the library job behind ``dptbd verilog --top axi``).

:func:`axi_package` returns ``{file name: text}`` for a stem (default ``dptbd_axi``):

- ``<stem>.v``: module ``dptbd_axi`` (:class:`~dptbd.hw.axi_top.AXITop`;
  :class:`~dptbd.hw.wide.axi_top.AXITopWide` at ``pixels_per_clock`` 2 or 4, whose header
  adds ``DPTBD_PIXELS_PER_CLOCK`` and whose core description names P);
- ``<stem>.json``: its manifest: parameters, derived widths, every port, the stream
  conventions, the register constants;
- the register map's PeakRDL renderings (:mod:`dptbd.hw.flow.register_outputs`, from
  ``hw/registers.rdl`` compiled for the build): ``dptbd_regs.h``, the C register header
  (with the candidate word's layout); ``<stem>_regs.md``, the Markdown reference;
  ``<stem>_regs.xml``, the IP-XACT register description; the HTML reference
  ``<stem>_regs_html/`` is a folder, written by :func:`write_html_reference`;
- ``<stem>.sdc`` / ``<stem>.xdc``: timing constraints of the only clock ``aclk``
  (``create_clock``; SDC for Quartus, nextpnr and other SDC readers, XDC for Vivado) at
  ``clock_mhz`` (:func:`clock_constraints`);
- ``component.xml``: the IP-XACT component (IEEE 1685-2009) for Vivado's block designs:
  ports, bus interfaces, the register map, file sets and parameters
  (:mod:`dptbd.hw.flow.ipxact`);
- ``<stem>.core``: a FuseSoC CAPI2 core naming the Verilog (``rtl`` file set), the header
  (``sw``) and the constraints (``sdc``, file type ``SDC``; ``xdc``, file type ``xdc``: the
  file types edalize's tool back ends read), with a ``default`` target (the XDC file when the
  tool is Vivado, the SDC file otherwise) and a ``lint`` target: edalize's ``lint`` flow
  (FuseSoC's flow API) with Verilator and the project's waivers, which the Verilog passes
  with no warning for every build.

With ``state_store`` (an :class:`~dptbd.config.AxiStoreConfig`; ``dptbd verilog --top axi
--state-store axi``) the module is :class:`~dptbd.hw.axi_store.top.AXITopStore`: the state in
external memory behind ``m_axi_state_*``; the manifest records the port and layout under
``state_store``, the header and manifest carry the store's registers, and the core's
description names the port. At ``pixels_per_clock`` 2 or 4 it is the same class on the wide
blocks (``s_axis_video`` of P pixels per beat, store words of P states): the header adds
``DPTBD_PIXELS_PER_CLOCK`` and the core's description names P and the store.
"""

from __future__ import annotations

import json
from typing import Mapping

from amaranth.hdl import Shape
from amaranth.lib import data, wiring

from dptbd.config import DPConfig
from dptbd.errors import ConfigError, check_real
from dptbd.hw.axi_top import AXI_MODULE_NAME, AXITop
from dptbd.hw.candidate_layout import candidate_field_offsets, candidate_layout
from dptbd.hw.flow.ipxact import COMPONENT_FILE, component_xml
from dptbd.hw.flow.register_outputs import HEADER_NAME, c_header, ipxact, markdown, write_html
from dptbd.hw.flow.to_verilog import to_verilog
from dptbd.hw.flow.verilog import VERILATOR_LINT_FLAGS, manifest_header, manifest_state_store
from dptbd.hw.axis_video import STATE_TUSER, video_tdata_layout
from dptbd.hw.layouts import field_offsets, state_word_layout
from dptbd.hw.register_map import register_constants

__all__ = ["HEADER_NAME", "DEFAULT_CLOCK_MHZ", "CLOCK_MHZ_RANGE", "package_file_names",
           "check_clock_mhz", "clock_constraints", "axi_ports", "axi_manifest",
           "core_description", "fusesoc_core",
           "generate_axi_verilog", "generate_axi_state_verilog", "check_no_saturation",
           "axi_package", "html_folder_name", "write_html_reference"]

#: Default ``aclk`` frequency of the shipped constraints: the synthesis flow's target
#: (``hw/flow/synth.py``, ``target_mhz=100``), which the DP core meets on the iCE40 HX8K
#: and on ECP5 (today's figures: ``docs/synthesis.md``, "Goals").
DEFAULT_CLOCK_MHZ = 100.0

#: Accepted ``aclk`` frequencies of the constraints, MHz (a sanity range, not a promise that
#: the core closes timing there).
CLOCK_MHZ_RANGE = (1.0, 1000.0)


def package_file_names(stem: str) -> list[str]:
    """The names of the files :func:`axi_package` returns, in order."""
    return [f"{stem}.v", f"{stem}.json", HEADER_NAME, f"{stem}.sdc", f"{stem}.xdc",
            COMPONENT_FILE, f"{stem}.core", f"{stem}_regs.md", f"{stem}_regs.xml"]


def html_folder_name(stem: str) -> str:
    """The folder :func:`write_html_reference` writes the HTML register reference into."""
    return f"{stem}_regs_html"


def write_html_reference(parent, cfg: DPConfig, stem: str = AXI_MODULE_NAME,
                         state_store=None) -> None:
    """PeakRDL-html's register reference of the build (:func:`axi_package`'s arguments)
    into ``parent / html_folder_name(stem)`` (``index.html`` and its assets)."""
    import pathlib

    write_html(pathlib.Path(parent) / html_folder_name(stem), cfg, state_store)


def check_clock_mhz(value, name: str = "clock_mhz") -> float:
    """``value`` as a frequency in :data:`CLOCK_MHZ_RANGE` (``name`` is what a message calls it).

    Raises
    ------
    DptbdError
        ``{name} must be a finite real number in [1, 1000], got {value!r}``.
    """
    return check_real(name, value, *CLOCK_MHZ_RANGE)


def clock_constraints(clock_mhz: float, tool: str) -> str:
    """The ``create_clock`` of ``aclk`` at ``clock_mhz`` as an SDC (``tool="sdc"``) or XDC
    (``"xdc"``) file. The reset ``aresetn`` is synchronous to ``aclk``, and every other port
    is timed against ``aclk`` by the surrounding design, so the clock is the only constraint.
    """
    period = 1000.0 / check_clock_mhz(clock_mhz)
    reader = {"sdc": "Quartus, nextpnr and other SDC readers", "xdc": "Vivado"}[tool]
    return "\n".join([
        f"# {AXI_MODULE_NAME}: timing constraints for {reader} "
        f"(generated by dptbd verilog --top axi)",
        f"# the only clock, aclk, at {clock_mhz:g} MHz; aresetn is synchronous to it",
        f"create_clock -name aclk -period {period:.3f} [get_ports aclk]",
        "",
    ])


def axi_ports(top: AXITop) -> list[dict]:
    """Every port of ``dptbd_axi`` with direction and width, in member order."""
    return [{"name": "__".join(map(str, path)),
             "direction": "input" if member.flow == wiring.In else "output",
             "width": Shape.cast(member.shape).width}
            for path, member, _value in top.signature.flatten(top)]


#: What a ``m_axis_state_tuser`` bit means, where its name does not say it all.
STATE_TUSER_MEANING = {"cut": "filler word completing a line cut by a soft reset "
                              "(tdata 0, no other tuser bit)"}


def axi_manifest(cfg: DPConfig, top: AXITop) -> dict:
    """Machine-readable description of ``dptbd_axi`` (JSON-serialisable)."""
    core = top.core
    return {
        **manifest_header(cfg, AXI_MODULE_NAME, top),
        "core_options": core.core_options,
        "clock": {"name": "aclk", "edge": "rising"},
        "reset": {"name": "aresetn", "polarity": "active_low", "kind": "synchronous"},
        "latency": core.latency,
        "dp_latency": core.schedule.latency,
        "scan_cycles": core.scan_cycles,
        "ports": axi_ports(top),
        "streams": {
            "s_axis_video": _video_stream(cfg),
            "m_axis_cand": {"tdata": "candidate word (record or trailer)",
                            "tuser[0]": "first word of a list", "tlast": "trailer",
                            "layout": candidate_field_offsets(cfg),
                            "width": data.Layout.cast(candidate_layout(cfg)).size},
            **({"m_axis_state": {
                "tdata": "E in bits [B_E-1:0], d in the next B_d bits",
                **{f"tuser[{bit}]": STATE_TUSER_MEANING.get(name, name.replace("_", " "))
                   for name, bit in STATE_TUSER.items()},
                "tlast": "end of line",
                "layout": field_offsets(state_word_layout(cfg)),
                "broadcast": "a word leaves the DP pipeline when both m_axis_state and the "
                             "segmenter can take it: back-pressure on either stalls the core",
            }} if top.state_output else {}),
        },
        "registers": register_constants(top.register_map),
        "header": HEADER_NAME,
        **({} if getattr(top, "store", None) is None
           else {"state_store": manifest_state_store(top.store)}),
    }


def _video_stream(cfg: DPConfig) -> dict:
    """The manifest's ``s_axis_video`` entry: one pixel per beat, or P at P > 1."""
    if cfg.pixels_per_clock == 1:
        return {"tdata": "pixel in bits [B_in-1:0]", "tuser[0]": "start of frame",
                "tlast": "end of line", "layout": field_offsets(video_tdata_layout(cfg))}
    from dptbd.hw.wide.axis_video import lane_bits, video_tdata_layout_wide
    lane = lane_bits(cfg)
    return {"tdata": f"P = {cfg.pixels_per_clock} pixels per beat, pixel k (column "
                     f"P*g + k of beat g) in bits [{lane}*k + B_in-1:{lane}*k], pixel 0 "
                     f"in the low bits",
            "tuser[0]": "start of frame (the frame's first beat)",
            "tlast": "end of line (the row's last beat)",
            "pixels_per_beat": cfg.pixels_per_clock,
            "layout": field_offsets(video_tdata_layout_wide(cfg))}


def core_description(cfg: DPConfig, state_store=None) -> str:
    """What the core is, one line: the FuseSoC core's ``description`` and
    ``component.xml``'s; with ``state_store`` it names the AXI4 manager port of the state in
    external memory."""
    store = "" if state_store is None else (
        f", state in external memory on the AXI4 manager port m_axi_state_* "
        f"({state_store.data_bits}-bit data, {state_store.address_bits}-bit addresses, "
        f"{state_store.frame_bytes} bytes from STATE_BASE)")
    option = "" if state_store is None else " --state-store axi"
    if cfg.pixels_per_clock > 1:
        store += f", {cfg.pixels_per_clock} pixels per clock"
        option += f" --pixels-per-clock {cfg.pixels_per_clock}"
    return (f"dptbd_axi, DP track-before-detect with AXI4-Stream video and AXI4-Lite "
            f"registers, {cfg.width}x{cfg.height}{store} (generated by dptbd verilog --top "
            f"axi{option})")


def fusesoc_core(cfg: DPConfig, stem: str, version: str, state_store=None) -> str:
    """A FuseSoC CAPI2 core file for the package's files (YAML text); with ``state_store``
    its description names the AXI4 manager port of the state in external memory."""
    lint = ", ".join(f for f in VERILATOR_LINT_FLAGS if f != "--lint-only")
    return "\n".join([
        "CAPI=2:",
        f"name: dptbd:dptbd:{stem}:{version}",
        f"description: {core_description(cfg, state_store)}",
        "",
        "filesets:",
        "  rtl:",
        "    files:",
        f"      - {stem}.v",
        "    file_type: verilogSource",
        "  sw:",
        "    files:",
        f"      - {HEADER_NAME}: {{is_include_file: true}}",
        "    file_type: cSource",
        "  sdc:",
        "    files:",
        f"      - {stem}.sdc",
        "    file_type: SDC",
        "  xdc:",
        "    files:",
        f"      - {stem}.xdc",
        "    file_type: xdc",
        "",
        "targets:",
        "  default:",
        '    filesets: [rtl, sw, "tool_vivado ? (xdc)", "!tool_vivado ? (sdc)"]',
        f"    toplevel: {AXI_MODULE_NAME}",
        "  lint:",
        "    flow: lint",
        "    flow_options:",
        "      tool: verilator",
        f"      verilator_options: [{lint}]",
        "    filesets: [rtl]",
        f"    toplevel: {AXI_MODULE_NAME}",
        "",
    ])


def generate_axi_verilog(cfg: DPConfig, *, state_output: bool = False,
                         core_options: Mapping[str, str] | None = None,
                         state_store=None) -> tuple[str, dict]:
    """Module ``dptbd_axi`` for ``cfg`` (with ``m_axis_state`` if ``state_output``; the DP
    core built with ``core_options``, ``None`` for DPCore's defaults; with the state in
    external memory as ``state_store`` says, an :class:`~dptbd.config.AxiStoreConfig` of
    ``cfg``, at any ``pixels_per_clock``): its Verilog text and its manifest."""
    if state_store is None and cfg.pixels_per_clock > 1:
        from dptbd.hw.wide.axi_top import axi_top
        top = axi_top(cfg, state_output=state_output, core_options=core_options)
    elif state_store is None:
        top = AXITop(cfg, state_output=state_output, core_options=core_options)
    else:
        from dptbd.hw.axi_store.top import AXITopStore
        if state_store.frame != cfg:
            raise ValueError("state_store was made for another configuration than cfg")
        top = AXITopStore(state_store, state_output=state_output, core_options=core_options)
    return to_verilog(top, AXI_MODULE_NAME), axi_manifest(cfg, top)


def generate_axi_state_verilog(cfg: DPConfig) -> tuple[str, dict]:
    """:func:`generate_axi_verilog` with ``m_axis_state`` (the simulation runner's
    ``axi-state`` design)."""
    return generate_axi_verilog(cfg, state_output=True)


def check_no_saturation(cfg: DPConfig) -> None:
    """Refuse a build whose E can saturate: K_max full-scale pixels above E_max.

    A core a user drops into a design should never clip E silently; a build that saturates on
    purpose passes ``allow_saturation`` (its ``SATURATED`` counter then counts the clipped
    words).

    Raises
    ------
    dptbd.errors.ConfigError
        Naming K_max, B_in, B_E and the smallest B_E that never saturates.
    """
    full_scale = cfg.k_max * cfg.pixel_max
    if full_scale > cfg.e_max:
        raise ConfigError(
            f"max_segment_frames: K_max={cfg.k_max} full-scale {cfg.input_bits}-bit pixels sum "
            f"to {full_scale} > E_max={cfg.e_max} of energy_bits={cfg.energy_bits}, so E "
            f"saturates; use energy_bits >= {cfg.energy_bits_needed} or K_max <= "
            f"{cfg.e_max // cfg.pixel_max}, or allow saturation explicitly")


def axi_package(cfg: DPConfig, stem: str = AXI_MODULE_NAME,
                clock_mhz: float = DEFAULT_CLOCK_MHZ, *,
                state_output: bool = False, allow_saturation: bool = False,
                core_options: Mapping[str, str] | None = None,
                state_store=None) -> dict[str, str]:
    """``{file name: text}`` of the package (see the module doc), constraints at
    ``clock_mhz`` (in :data:`CLOCK_MHZ_RANGE`), ``m_axis_state`` if ``state_output``, the DP
    core built with ``core_options`` (``None``: DPCore's defaults; ``dptbd verilog --family``
    passes the family's :meth:`~dptbd.hw.flow.family.Family.options_for`), the state in
    external memory as ``state_store`` says (``None``: on chip).

    A configuration whose E can saturate is refused (:func:`check_no_saturation`) unless
    ``allow_saturation``."""
    from importlib.metadata import version

    if not allow_saturation:
        check_no_saturation(cfg)
    clock_mhz = check_clock_mhz(clock_mhz)
    text, info = generate_axi_verilog(cfg, state_output=state_output,
                                      core_options=core_options, state_store=state_store)
    info["clock"]["frequency_mhz"] = clock_mhz
    info["constraints"] = {"sdc": f"{stem}.sdc", "xdc": f"{stem}.xdc",
                           "period_ns": round(1000.0 / clock_mhz, 3)}
    info["register_references"] = {"markdown": f"{stem}_regs.md", "ipxact": f"{stem}_regs.xml",
                                   "html": f"{html_folder_name(stem)}/index.html"}
    names = package_file_names(stem)
    texts = [text, json.dumps(info, indent=2) + "\n", c_header(cfg, state_store),
             clock_constraints(clock_mhz, "sdc"), clock_constraints(clock_mhz, "xdc"),
             component_xml(cfg, info["ports"], verilog=f"{stem}.v", header=HEADER_NAME,
                           version=version("dptbd"),
                           description=core_description(cfg, state_store),
                           state_store=state_store),
             fusesoc_core(cfg, stem, version("dptbd"), state_store),
             markdown(cfg, state_store), ipxact(cfg, state_store)]
    return dict(zip(names, texts))
