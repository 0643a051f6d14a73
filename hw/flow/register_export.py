"""Renderings of the register map (:func:`dptbd.hw.register_map.register_map`): the
Markdown table of ``docs/registers.md``, the C header ``dptbd_regs.h`` and the Python
constants the testbenches use. All three come from :func:`register_constants` and the map,
so a register can never move in one of them only.

``dptbd_regs.h`` (and the Python constants) also carry the layout of the candidate word on
``m_axis_cand`` (:func:`candidate_constants`, generated from the field lists of
:func:`dptbd.hw.candidate_layout.candidate_layout`, the layout the gateware's port is built
from) and the weight multiplier's rounding mode, so firmware decodes the lists without the
manifest.

Command line (regenerates the committed document for the default configuration)::

    python -m dptbd.hw.flow.register_export --markdown docs/registers.md
"""

from __future__ import annotations

import argparse
import pathlib
import types

from amaranth.lib import data

from dptbd.config import ROUNDING_MODES, DPConfig
from dptbd.hw.axis_video import byte_padded
from dptbd.hw.candidate_layout import candidate_layout
from dptbd.hw.register_map import (ADDRESS_BITS, FIELD_ACCESS, FIELD_KINDS, RegisterMap,
                                   constants_namespace, register_constants, register_map)

__all__ = ["ROUNDING_MEANINGS", "register_constants", "candidate_constants",
           "constants_namespace", "markdown", "c_header", "python_module", "main"]

#: What each rounding mode of the weight multiplier computes (``docs/arithmetic.md`` §4),
#: written beside its code in ``dptbd_regs.h``; the code of a mode is its index in
#: :data:`~dptbd.config.ROUNDING_MODES`.
ROUNDING_MEANINGS = {
    "truncate": "C = (E*c) >> F, floor",
    "half_up": "C = (E*c + 2^(F-1)) >> F for F >= 1, C = E*c for F = 0",
}

#: A candidate word is held in a ``uint64_t`` by the C header.
_WORD_LIMIT = 64

_KIND_TEXT = {
    "constant": "build parameter; writes refused (SLVERR)",
    "setting": "run-time setting; a write outside the range is refused: value not taken, "
               "ERROR.write_refused set, SLVERR",
    "enable": "read/write",
    "pulse": "write 1: one-cycle pulse; reads 0",
    "counter": "32-bit event count, wraps modulo 2^32, cleared by CONTROL.clear_counters; "
               "writes refused (SLVERR)",
    "sticky": "set by its event; write 1 to clear (a set in the same cycle wins)",
    "interrupt": "pending; write 1 to clear; irq = any pending AND enabled",
    "status": "the core's state now (not latched); writes refused (SLVERR)",
}


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


def _bits(field) -> str:
    hi = field.lsb + field.width - 1
    return f"{hi}:{field.lsb}" if field.width > 1 else str(field.lsb)


def _range(field) -> str:
    if field.limits is None:
        return ""
    lo, hi = field.limits
    text = f"[{lo}, {hi}]" if hi <= 0xFFFF else f"[0x{lo:X}, 0x{hi:X}]"
    return text + ("" if field.align is None else f", a multiple of {field.align}")


def markdown(regmap: RegisterMap, cfg: DPConfig, store_map: RegisterMap | None = None) -> str:
    """The register tables as Markdown (the body of ``docs/registers.md``); with
    ``store_map`` (the map of the same configuration with the state store in external
    memory) a last section lists what that build adds."""
    lines = [
        "*Reference document: what is true by design.*",
        "",
        "# Registers of `dptbd_axi`",
        "",
        "Generated by `python -m dptbd.hw.flow.register_export --markdown docs/registers.md` "
        "from `hw/register_map.py` for the default configuration "
        f"({cfg.describe()}); reset values of "
        "the identification and control registers follow the build. Do not edit by hand: "
        "`tests/hw/flow/test_register_export.py` checks this file against the generator.",
        "",
        f"AXI4-Lite, 32-bit data, {ADDRESS_BITS}-bit byte addresses, every register one "
        f"aligned word. {_bus_rules()} See `docs/integration.md` for the ports and the protocol.",
        "",
        "| kind | access | behaviour |",
        "|---|---|---|",
        *[f"| {kind} | {FIELD_ACCESS[kind]} | {_KIND_TEXT[kind]} |" for kind in FIELD_KINDS],
    ]
    for group in ("identification", "control", "status"):
        lines += ["", f"## {group.capitalize()}", ""]
        lines += _table([(reg, reg.fields) for reg in regmap.registers if reg.group == group])
    lines += ["", "## Windows", "",
              "| address | window | entries | bits | range | meaning |", "|---|---|---|---|---|---|"]
    for win in regmap.windows:
        lines.append(f"| 0x{win.base:03X} … 0x{win.end - 4:03X} | {win.name} | {win.entries} | "
                     f"{_bits(win.field)} | {_range(win.field)} | {win.doc}; "
                     f"{win.field.doc} |")
    if store_map is not None:
        lines += _store_section(regmap, store_map)
    return "\n".join(lines) + "\n"


def _table(rows) -> list[str]:
    """A register table of ``(register, fields)`` rows."""
    lines = ["| address | register | field | bits | kind | reset | range | meaning |",
             "|---|---|---|---|---|---|---|---|"]
    for reg, fields in rows:
        for i, field in enumerate(fields):
            head = (f"0x{reg.address:03X} | {reg.name}" if i == 0 else " | ")
            doc = field.doc if i or field.doc == reg.doc else f"{reg.doc}: {field.doc}"
            reset = "—" if field.kind == "pulse" else (
                f"0x{field.reset:X}" if field.reset > 0xFFFF else str(field.reset))
            lines.append(f"| {head} | {field.name} | {_bits(field)} | {field.kind} | "
                         f"{reset} | {_range(field)} | {doc} |")
    return lines


def _store_section(regmap: RegisterMap, store_map: RegisterMap) -> list[str]:
    """What the build with the state store in external memory adds to ``regmap``."""
    old = {reg.name: reg for reg in regmap.registers}
    rows = []
    for reg in store_map.registers:
        known = {f.name for f in old[reg.name].fields} if reg.name in old else set()
        fields = [f for f in reg.fields if f.name not in known]
        if fields:
            rows.append((reg, fields))
    return ["", "## With `--state-store axi`", "",
            "`dptbd verilog --top axi --state-store axi` (the state in external memory behind "
            "`m_axi_state_*`, `docs/integration.md`) adds these registers and `ERROR` bits; "
            "every other register is where it is above. Reset values and ranges here are "
            "those of the default store (`DPConfig().axi_store()`); they follow the build.",
            "", *_table(rows)]


def c_header(regmap: RegisterMap, cfg: DPConfig) -> str:
    """``dptbd_regs.h``: every :func:`register_constants` entry as ``DPTBD_<NAME>``."""
    guard = "DPTBD_REGS_H"
    lines = [
        "/* dptbd_regs.h: register map of dptbd_axi (generated from hw/register_map.py;",
        f" * build {cfg.width}x{cfg.height}, K_max {regmap['BUILD_SEGMENT'].fields[0].reset}, "
        f"B_in {cfg.input_bits}, B_E {cfg.energy_bits}, F {cfg.weight_frac_bits}, "
        f"r {cfg.radius}). Do not edit. */",
        f"#ifndef {guard}",
        f"#define {guard}",
        "",
    ]
    for name, value in register_constants(regmap).items():
        lines.append(f"#define DPTBD_{name} 0x{value:08X}u")
    lines += ["", "/* byte address of weight LUT entry [p, m]: p * M + m (DPConfig.lut_address) */",
              f"#define DPTBD_LUT_ADDRESS(p, m) (DPTBD_LUT_BASE + 4u * ((p) * {cfg.n_moves}u + (m)))",
              "", *_candidate_lines(cfg), "", f"#endif /* {guard} */", ""]
    return "\n".join(lines)


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
    rounding = {f"ROUNDING_{m.upper()}": ROUNDING_MEANINGS[m] for m in ROUNDING_MODES}
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
    for name, meaning in rounding.items():
        lines.append(f"#define DPTBD_{name} {consts[name]}u /* {meaning} */")
    lines.append(f"#define DPTBD_ROUNDING DPTBD_ROUNDING_{cfg.rounding.upper()} "
                 f"/* this build: {cfg.rounding} */")
    return lines


def python_module(regmap: RegisterMap, cfg: DPConfig) -> str:
    """``dptbd_regs.py``: the same constants for Python drivers outside this package."""
    lines = ['"""Register map of dptbd_axi (generated from hw/register_map.py). Do not edit."""',
             ""]
    lines += [f"{name} = 0x{value:X}" for name, value in
              {**register_constants(regmap), **candidate_constants(cfg)}.items()]
    return "\n".join(lines) + "\n"


def _bus_rules() -> str:
    from dptbd.hw.registers import compile_map
    return compile_map(DPConfig()).get_property("desc")


def main(argv=None) -> int:
    """Write ``docs/registers.md`` (``--markdown``) for the default configuration."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--markdown", type=pathlib.Path, required=True)
    args = parser.parse_args(argv)
    cfg = DPConfig()
    args.markdown.write_text(markdown(register_map(cfg), cfg, register_map(cfg, cfg.axi_store())))
    print(f"wrote {args.markdown}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

