"""PeakRDL's renderings of the register map (``hw/registers.rdl`` compiled for a build by
:func:`dptbd.hw.registers.compile_map`), which ``dptbd verilog --top axi`` writes beside the
Verilog:

- ``dptbd_regs.h`` (:func:`c_header`): PeakRDL-cheader's header (per field
  ``DPTBD_AXI__<GROUP>__<REGISTER>__<FIELD>_bm`` / ``_bp`` / ``_bw`` / ``_reset``, the
  struct ``dptbd_axi_t`` whose members sit at the registers' offsets), followed by what the
  compiled map holds beyond SystemRDL's own properties and what firmware needs besides:
  each range-checked field's ``_min`` / ``_max`` (``_align``), ``DPTBD_LUT_ADDRESS(p, m)``,
  the layout of the candidate word on ``m_axis_cand`` (:func:`candidate_constants`) and the
  weight multiplier's rounding mode;
- ``<stem>_regs.md`` (:func:`markdown`): PeakRDL-markdown's reference, each field table
  with the field's kind and range (``docs/registers.md`` is this for the default build);
- ``<stem>_regs.xml`` (:func:`ipxact`): PeakRDL-ipxact's IP-XACT (IEEE 1685-2014)
  component with the memory map;
- ``<stem>_regs_html/`` (:func:`write_html`): PeakRDL-html's browsable reference.

Command line (regenerates the committed document for the default configuration)::

    python -m dptbd.hw.flow.register_outputs --markdown docs/registers.md
"""

from __future__ import annotations

import argparse
import pathlib
import tempfile

from amaranth.lib import data

from dptbd.config import ROUNDING_MODES, DPConfig
from dptbd.hw.axis_video import byte_padded
from dptbd.hw.candidate_layout import candidate_layout
from dptbd.hw.register_map import field_kind
from dptbd.hw.registers import compile_map

__all__ = ["HEADER_NAME", "ROUNDING_MEANINGS", "IPXACT_VENDOR", "candidate_constants", "c_header",
           "markdown", "ipxact", "write_html", "main"]

#: What each rounding mode of the weight multiplier computes (``docs/arithmetic.md`` §4),
#: written beside its code in ``dptbd_regs.h``; the code of a mode is its index in
#: :data:`~dptbd.config.ROUNDING_MODES`.
ROUNDING_MEANINGS = {
    "truncate": "C = (E*c) >> F, floor",
    "half_up": "C = (E*c + 2^(F-1)) >> F for F >= 1, C = E*c for F = 0",
}

#: The IP-XACT component's VLNV vendor and library (its name is the ``addrmap``'s, its
#: version the package's).
IPXACT_VENDOR, IPXACT_LIBRARY = "dptbd", "dptbd"

#: File name of the register header (what firmware includes; PeakRDL-cheader names its guard
#: after it).
HEADER_NAME = "dptbd_regs.h"

#: A candidate word is held in a ``uint64_t`` by the C header.
_WORD_LIMIT = 64

#: The user-defined properties the renderings show (``hw/registers.rdl`` declares them).
_RANGE = ("range_min", "range_max", "range_align")


def candidate_constants(cfg: DPConfig) -> dict[str, int]:
    """The candidate word of ``m_axis_cand`` and the rounding mode, by name (no prefix).

    ``CAND_BODY_BITS`` (w, the wider of record and trailer), ``CAND_WORD_BITS`` (w + 1,
    with ``end_of_list``), ``CAND_TDATA_BITS`` / ``CAND_TDATA_BYTES`` (the word zero-extended
    to whole bytes: the width of ``m_axis_cand_tdata``); per field ``CAND_<NAME>_SHIFT`` /
    ``_WIDTH`` / ``_MASK`` (mask in place), where ``<NAME>`` is ``<VARIANT>_<FIELD>`` for a
    field of a variant of the body union (``RECORD_ROW``, ``TRAILER_COUNT``, …) and the
    field's own name above the body (``END_OF_LIST``); ``ROUNDING_<MODE>`` for every mode
    and ``ROUNDING``, the build's. Every name and number comes from the layout's field lists.

    Raises
    ------
    ValueError
        ``the candidate word is {n} bits wide; dptbd_regs.h holds a word in a uint64_t (at
        most 64 bits)``.
    """
    payload = candidate_layout(cfg)
    word = payload.size
    if word > _WORD_LIMIT:
        raise ValueError(f"the candidate word is {word} bits wide; dptbd_regs.h holds a word in "
                         f"a uint64_t (at most {_WORD_LIMIT} bits)")
    fields = []                                     # (NAME, offset, width)
    for name, field in payload:
        if isinstance(field.shape, data.UnionLayout):
            body = field
            for variant, part in field.shape:
                fields += [(f"{variant}_{sub}".upper(), field.offset + part.offset + f.offset,
                            f.width) for sub, f in part.shape]
        else:
            fields.append((name.upper(), field.offset, field.width))
    out = {"CAND_BODY_BITS": body.width, "CAND_WORD_BITS": word,
           "CAND_TDATA_BITS": byte_padded(word), "CAND_TDATA_BYTES": byte_padded(word) // 8}
    for name, offset, width in fields:
        out[f"CAND_{name}_SHIFT"] = offset
        out[f"CAND_{name}_WIDTH"] = width
        out[f"CAND_{name}_MASK"] = ((1 << width) - 1) << offset
    for code, mode in enumerate(ROUNDING_MODES):
        out[f"ROUNDING_{mode.upper()}"] = code
    out["ROUNDING"] = ROUNDING_MODES.index(cfg.rounding)
    return out


def _export(write, name: str) -> str:
    """The text an exporter writes to a file called ``name`` (``write(path)``)."""
    with tempfile.TemporaryDirectory() as folder:
        path = pathlib.Path(folder) / name
        write(str(path))
        return path.read_text()


def _fields(top):
    """Every field of the compiled map (a window's once), in address order."""
    from systemrdl.node import FieldNode

    return [node for node in top.descendants(unroll=False) if isinstance(node, FieldNode)]


def _c_prefix(top, node) -> str:
    """PeakRDL-cheader's name of a field of ``top`` (its path from ``top`` on,
    ``__``-separated, upper case)."""
    return node.get_rel_path(top.parent, hier_separator="__", array_suffix="x",
                             empty_array_suffix="x").upper()


def c_header(cfg: DPConfig, store=None) -> str:
    """``dptbd_regs.h`` for ``cfg`` (and ``store``): see the module doc. The header compiles
    as C99 (``-std=c99 -pedantic``)."""
    from peakrdl_cheader.c_standards import CStandard
    from peakrdl_cheader.exporter import CHeaderExporter

    top = compile_map(cfg, store)
    text = _export(lambda path: CHeaderExporter().export(
        top, path, std=CStandard.gnu99, reuse_typedefs=False), HEADER_NAME)
    lines = ["/* The allowed values of each range-checked field: a write outside them is refused",
             " * (value not taken, ERROR.write_refused set, SLVERR); _align: the value must be a",
             " * multiple of it. */"]
    for node in _fields(top):
        for prop in _RANGE:
            value = node.get_property(prop)
            if value is not None:
                lines.append(f"#define {_c_prefix(top, node)}_{prop.split('_')[1]} {value:#x}")
    lut = top.get_child_by_name("LUT")
    lines += ["", "/* byte address of weight LUT entry [p, m]: p * M + m (DPConfig.lut_address) */",
              f"#define DPTBD_LUT_ADDRESS(p, m) ({lut.absolute_address:#x}u + 4u * ((p) * "
              f"{cfg.n_moves}u + (m)))"]
    if cfg.pixels_per_clock > 1:
        lines += ["", f"/* s_axis_video carries {cfg.pixels_per_clock} pixels per beat, pixel 0 "
                      f"in the low bits */",
                  f"#define DPTBD_PIXELS_PER_CLOCK {cfg.pixels_per_clock}u"]
    lines += ["", *_candidate_lines(cfg), "", ""]
    tail = "\n#ifdef __cplusplus\n}"
    cut = text.rindex(tail)
    return text[:cut] + "\n" + "\n".join(lines) + text[cut:]


def _candidate_lines(cfg: DPConfig) -> list[str]:
    """The ``m_axis_cand`` word and the rounding mode in ``dptbd_regs.h``."""
    consts = candidate_constants(cfg)
    lines = [
        "/* m_axis_cand: one candidate word per beat (generated from hw/candidate_layout.py).",
        " * A word is w + 1 bits: the body, w = DPTBD_CAND_BODY_BITS (the wider of record and",
        " * trailer), from bit 0, holds a record (end_of_list = 0) or the list's trailer",
        " * (end_of_list = 1, bit w); tdata is the word zero-extended to whole bytes.",
        " * A field of a 64-bit word: DPTBD_CAND_FIELD(word, RECORD_ROW). */",
    ]
    for name, value in consts.items():
        if name.startswith("ROUNDING"):
            continue
        text = f"0x{value:016X}ull" if name.endswith("_MASK") else f"{value}u"
        lines.append(f"#define DPTBD_{name} {text}")
    lines += ["#define DPTBD_CAND_FIELD(word, name) \\",
              "    ((unsigned long long)((word) & DPTBD_CAND_##name##_MASK) >> "
              "DPTBD_CAND_##name##_SHIFT)",
              "",
              "/* weight multiplier rounding (docs/arithmetic.md section 4): the weighted predecessor "
              "E*c back to E's scale */"]
    for mode in ROUNDING_MODES:
        name = f"ROUNDING_{mode.upper()}"
        lines.append(f"#define DPTBD_{name} {consts[name]}u /* {ROUNDING_MEANINGS[mode]} */")
    lines.append(f"#define DPTBD_ROUNDING DPTBD_ROUNDING_{cfg.rounding.upper()} "
                 f"/* this build: {cfg.rounding} */")
    return lines


def _range_text(node) -> str:
    lo, hi, align = (node.get_property(p) for p in _RANGE)
    if hi is None:
        return "—"
    text = f"[{lo or 0}, {hi}]" if hi <= 0xFFFF else f"[0x{lo or 0:X}, 0x{hi:X}]"
    return text + ("" if align is None else f", a multiple of {align}")


def _markdown_exporter():
    from peakrdl_markdown import MarkdownExporter
    from systemrdl.node import MemNode

    class Exporter(MarkdownExporter):
        """PeakRDL-markdown with two more columns in each field table: the field's kind
        (what the register file implements; ``window`` in the LUT window) and its range (a
        write outside is refused)."""

        def _add_field(self, node, msg):
            out = super()._add_field(node, msg)
            in_window = isinstance(node.parent.parent, MemNode)
            out.table_row["Kind"] = "window" if in_window else field_kind(node) or "—"
            out.table_row["Range"] = _range_text(node)
            return out

    return Exporter()


def markdown(cfg: DPConfig, store=None) -> str:
    """PeakRDL-markdown's reference of the map for ``cfg`` (and ``store``), with each field's
    kind and range."""
    top = compile_map(cfg, store)
    return _export(lambda path: _markdown_exporter().export(top, path), "regs.md")


def ipxact(cfg: DPConfig, store=None, *, standard: int = 2014) -> str:
    """The map for ``cfg`` (and ``store``) as an IP-XACT component, VLNV
    ``dptbd:dptbd:dptbd_axi:<version of dptbd>``: IEEE 1685-2014 (``<stem>_regs.xml``), or
    1685-2009 (``standard=2009``, the memory map of ``component.xml``)."""
    from importlib.metadata import version

    from peakrdl_ipxact import IPXACTExporter, Standard

    standards = {2014: Standard.IEEE_1685_2014, 2009: Standard.IEEE_1685_2009}
    top = compile_map(cfg, store)
    exporter = IPXACTExporter(standard=standards[standard], vendor=IPXACT_VENDOR,
                              library=IPXACT_LIBRARY, version=version("dptbd"))
    return _export(lambda path: exporter.export(top, path), "regs.xml")


def write_html(folder: pathlib.Path, cfg: DPConfig, store=None) -> None:
    """PeakRDL-html's reference of the map for ``cfg`` (and ``store``) into ``folder``
    (``index.html`` and its scripts, styles and fonts), each field with its range and
    event."""
    from peakrdl_html import HTMLExporter

    exporter = HTMLExporter(extra_doc_properties=[*_RANGE, "event"],
                            generate_source_links=False)
    exporter.export(compile_map(cfg, store), str(folder))


#: The preamble of ``docs/registers.md`` (the PeakRDL-markdown reference follows).
_PREAMBLE = """\
*Reference document: what is true by design.*

# Registers of `dptbd_axi`

Generated by `python -m dptbd.hw.flow.register_outputs --markdown docs/registers.md`
(PeakRDL-markdown) from `hw/registers.rdl`, the register map's one source, compiled for the
default configuration ({describe}); reset values of the identification and control
registers and the ranges follow the build: `dptbd verilog --top axi` writes this reference
for its build (`dptbd_axi_regs.md`, beside `dptbd_axi_regs_html/`, `dptbd_axi_regs.xml` and
`dptbd_regs.h`). Do not edit by hand: `tests/hw/flow/test_register_outputs.py` checks this
file against the generator. The kinds (column Kind) are described in `docs/integration.md`,
"Registers"; the whole map of the build with `--state-store axi` follows the default one.

"""


def registers_document(cfg: DPConfig) -> str:
    """``docs/registers.md``: the preamble, the map of ``cfg``'s build, then the map of its
    build with the state store in external memory (``cfg.axi_store()``)."""
    return (_PREAMBLE.format(describe=cfg.describe()) + markdown(cfg)
            + "\n# With `--state-store axi`\n\nThe whole map of that build (default store, "
              "`DPConfig().axi_store()`): every register above is where it is there.\n\n"
            + markdown(cfg, cfg.axi_store()))


def main(argv=None) -> int:
    """Write ``docs/registers.md`` (``--markdown``) for the default configuration."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--markdown", type=pathlib.Path, required=True)
    args = parser.parse_args(argv)
    args.markdown.write_text(registers_document(DPConfig()))
    print(f"wrote {args.markdown}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
