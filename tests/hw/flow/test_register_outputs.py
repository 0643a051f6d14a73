"""PeakRDL's renderings of the register map: the committed ``docs/registers.md`` is the
generator's output; the C header compiles as C99 and carries the register file's numbers
(offsets, masks, resets, ranges) and the candidate word, which decodes every word the
gateware's pack helpers make; the IP-XACT read back by PeakRDL-ipxact's importer is the
compiled source; the Markdown shows each field's kind and range."""

import pathlib
import subprocess

import numpy as np
import pytest
from amaranth.hdl import Shape, unsigned
from amaranth.lib import data

from dptbd.config import ROUNDING_MODES, DPConfig
from dptbd.dsp.firmware import find_compiler
from dptbd.hw.axis_video import candidate_out_signature
from dptbd.hw.candidate_layout import (candidate_layout, pack_record, pack_trailer,
                                       record_layout, trailer_layout, unpack_candidate)
from dptbd.hw.flow import register_outputs
from dptbd.hw.register_map import register_map
from dptbd.hw.registers import compile_map
from helpers.refusals import whole
from helpers.seg_harness import make_config

ROOT = pathlib.Path(__file__).resolve().parents[3]

C_FLAGS = ("-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic")


def test_committed_markdown_is_the_generators_output():
    assert (ROOT / "docs" / "registers.md").read_text() == \
        register_outputs.registers_document(DPConfig()), (
            "docs/registers.md is stale: python -m dptbd.hw.flow.register_outputs "
            "--markdown docs/registers.md")


def _compile_and_run(tmp_path, header: str, body: str, stdin: str = "") -> list[str]:
    (tmp_path / "dptbd_regs.h").write_text(header)
    (tmp_path / "probe.c").write_text(
        '#include <stddef.h>\n#include <stdio.h>\n#include "dptbd_regs.h"\n'
        'int main(void) {\n' + body + '\n    return 0;\n}\n')
    exe = tmp_path / "probe"
    subprocess.run([find_compiler(), *C_FLAGS, "-o", str(exe), str(tmp_path / "probe.c")],
                   check=True, cwd=tmp_path)
    return subprocess.run([str(exe)], input=stdin, check=True, capture_output=True,
                          text=True).stdout.splitlines()


@pytest.mark.parametrize("store", [False, True])
@pytest.mark.parametrize("cfg", [make_config(width=24, height=20, radius=2, candidate_count=7),
                                 DPConfig().build_config()])
def test_c_header_compiles_and_carries_the_register_files_numbers(cfg, store, tmp_path):
    """Every register's offset in ``dptbd_axi_t`` (``offsetof``), every field's mask, shift,
    width and reset, every range, the LUT entry address: printed by a C99 program that knows
    only the header, equal to the map the register file decodes."""
    store = cfg.axi_store() if store else None
    regmap = register_map(cfg, store)
    want, prints = {}, []

    def probe(name, expr, value):
        want[name] = value
        prints.append(f'    printf("{name} %lu\\n", (unsigned long)({expr}));')

    for reg in regmap.registers:
        probe(f"{reg.name}@", f"offsetof(dptbd_axi_t, {reg.group}.{reg.name})", reg.address)
        for f in reg.fields:
            c = f"DPTBD_AXI__{reg.group}__{reg.name}__{f.name}".upper()
            probe(f"{reg.name}.{f.name}.bm", f"{c}_bm", f.mask)
            probe(f"{reg.name}.{f.name}.bp", f"{c}_bp", f.lsb)
            probe(f"{reg.name}.{f.name}.bw", f"{c}_bw", f.width)
            probe(f"{reg.name}.{f.name}.reset", f"{c}_reset", f.reset)
            if f.limits is not None:
                probe(f"{reg.name}.{f.name}.min", f"{c}_min", f.limits[0])
                probe(f"{reg.name}.{f.name}.max", f"{c}_max", f.limits[1])
            if f.align is not None:
                probe(f"{reg.name}.{f.name}.align", f"{c}_align", f.align)
    (lut,) = regmap.windows
    probe("LUT@", "offsetof(dptbd_axi_t, LUT)", lut.base)
    probe("LUT.entries", "sizeof(((dptbd_axi_t *)0)->LUT.entry) / 4", lut.entries)
    probe("LUT.code.min", "DPTBD_AXI__LUT__ENTRYX__CODE_min", lut.field.limits[0])
    probe("LUT.code.max", "DPTBD_AXI__LUT__ENTRYX__CODE_max", lut.field.limits[1])
    probe("LUT.code.bm", "DPTBD_AXI__LUT__ENTRYX__CODE_bm", lut.field.mask)
    probe("LUT_ADDRESS", "DPTBD_LUT_ADDRESS(3, 2)", lut.base + 4 * cfg.lut_address(3, 2))
    out = _compile_and_run(tmp_path, register_outputs.c_header(cfg, store), "\n".join(prints))
    assert {k: int(v) for k, v in (line.split() for line in out)} == want


def _random_words(cfg, rng, count):
    """Records and trailers packed by the gateware's helpers, every field drawn over its
    whole width (names from the layouts' field lists), plus the all-ones of each."""
    words = []
    for kind, layout, pack in (("record", record_layout(cfg), pack_record),
                               ("trailer", trailer_layout(cfg), pack_trailer)):
        for i in range(count):
            fields = {name: (1 << f.width) - 1 if i == 0 else int(rng.integers(0, 1 << f.width))
                      for name, f in layout}
            words.append(pack(cfg, **fields))
    return words


@pytest.mark.parametrize("cfg", [DPConfig(), DPConfig(height=100, width=300, rounding="half_up"),
                                 make_config(width=4096, height=4096, input_bits=16,
                                             energy_bits=32, radius=2)])
def test_c_header_decodes_the_candidate_words(cfg, tmp_path):
    """A C program that knows only dptbd_regs.h decodes random records and trailers made by
    pack_record / pack_trailer exactly as unpack_candidate does; the word widths are the
    layout's and the AXI port's, and the rounding define is the build's."""
    consts = register_outputs.candidate_constants(cfg)
    kinds = {kind: [name for name, _f in layout] for kind, layout in
             (("record", record_layout(cfg)), ("trailer", trailer_layout(cfg)))}
    body = []
    for kind, names in kinds.items():
        prints = "".join(f' printf(" %llu", DPTBD_CAND_FIELD(w, {kind.upper()}_{n.upper()}));'
                         for n in names)
        body.append(f'if (DPTBD_CAND_FIELD(w, END_OF_LIST) == {int(kind == "trailer")}u) '
                    f'{{ printf("{kind}");{prints} printf("\\n"); }}')
    sizes = " ".join(f'printf("{n} %llu\\n", (unsigned long long)DPTBD_{n});'
                     for n in ("CAND_BODY_BITS", "CAND_WORD_BITS", "CAND_TDATA_BITS",
                               "CAND_TDATA_BYTES", "ROUNDING"))
    words = _random_words(cfg, np.random.default_rng(3), 200)
    out = _compile_and_run(
        tmp_path, register_outputs.c_header(cfg),
        f'    unsigned long long w;\n    {sizes}\n'
        '    while (scanf("%llu", &w) == 1) {\n        ' + "\n        ".join(body) + '\n    }',
        " ".join(map(str, words)))
    sizes = dict(line.split() for line in out[:5])
    word_bits = data.Layout.cast(candidate_layout(cfg)).size
    tdata = Shape.cast(candidate_out_signature(cfg).members["tdata"].shape).width
    assert {k: int(v) for k, v in sizes.items()} == {
        "CAND_BODY_BITS": word_bits - 1, "CAND_WORD_BITS": word_bits, "CAND_TDATA_BITS": tdata,
        "CAND_TDATA_BYTES": tdata // 8, "ROUNDING": ROUNDING_MODES.index(cfg.rounding)}
    assert consts["CAND_END_OF_LIST_SHIFT"] == word_bits - 1
    assert len(out) == 5 + len(words)
    for word, line in zip(words, out[5:]):
        kind, fields = unpack_candidate(cfg, word)
        assert line == " ".join([kind, *(str(fields[n]) for n in kinds[kind])])


def test_candidate_constants_follow_the_layout(monkeypatch):
    """Names and numbers come from the layout's field lists: a field added to the trailer
    appears in the header without a change here; a word over 64 bits is refused."""
    cfg = make_config(width=16, height=12)
    wider = data.StructLayout({"count": unsigned(3), "cut": unsigned(1)})
    monkeypatch.setattr(register_outputs, "candidate_layout", lambda c: data.StructLayout({
        "body": data.UnionLayout({"record": data.StructLayout({"row": unsigned(4)}),
                                  "trailer": wider}),
        "end_of_list": unsigned(1)}))
    consts = register_outputs.candidate_constants(cfg)
    assert {k: v for k, v in consts.items() if k.startswith("CAND_TRAILER_CUT")} == {
        "CAND_TRAILER_CUT_SHIFT": 3, "CAND_TRAILER_CUT_WIDTH": 1, "CAND_TRAILER_CUT_MASK": 8}
    assert (consts["CAND_END_OF_LIST_SHIFT"], consts["CAND_WORD_BITS"]) == (4, 5)
    assert "#define DPTBD_CAND_TRAILER_CUT_MASK 0x0000000000000008ull\n" in \
        register_outputs.c_header(cfg)
    monkeypatch.setattr(register_outputs, "candidate_layout", lambda c: data.StructLayout({
        "body": data.UnionLayout({"record": unsigned(64)}), "end_of_list": unsigned(1)}))
    with pytest.raises(ValueError, match=whole(
            "the candidate word is 65 bits wide; dptbd_regs.h holds a word in a uint64_t "
            "(at most 64 bits)")):
        register_outputs.candidate_constants(cfg)


def test_c_header_names_pixels_per_clock_at_p_above_1():
    cfg = make_config(width=12, height=10, candidate_count=3, pixels_per_clock=2)
    assert "#define DPTBD_PIXELS_PER_CLOCK 2u\n" in register_outputs.c_header(cfg)
    assert "DPTBD_PIXELS_PER_CLOCK" not in register_outputs.c_header(
        make_config(width=12, height=10, candidate_count=3))


def _summary(top):
    """Everything IP-XACT carries of a compiled map, by path below the top: each block's,
    register's and field's address or bits, array size, reset, software access, write side
    effect and description."""
    from systemrdl.node import AddressableNode, FieldNode

    out = {}
    for node in top.descendants(unroll=False):
        path = node.get_rel_path(top)
        if isinstance(node, FieldNode):
            out[path] = (node.lsb, node.width, node.get_property("reset"),
                         node.get_property("sw"), node.get_property("onwrite"),
                         node.get_property("desc"))
        elif isinstance(node, AddressableNode):
            out[path] = (node.raw_absolute_address - top.raw_absolute_address,
                         node.array_dimensions, node.get_property("desc"))
    return out


@pytest.mark.parametrize("store", [False, True])
def test_ipxact_read_back_is_the_source(tmp_path, store):
    """PeakRDL-ipxact's importer reads the component back to the compiled map: every block
    (an address block each: identification, control, status, the LUT memory), register and
    field, with addresses, resets, access, write-1-to-clear and descriptions."""
    from peakrdl_ipxact import IPXACTImporter
    from systemrdl import RDLCompiler

    cfg = make_config(width=24, height=20, radius=2, candidate_count=7)
    store = cfg.axi_store() if store else None
    (tmp_path / "regs.xml").write_text(register_outputs.ipxact(cfg, store))
    compiler = RDLCompiler()
    IPXACTImporter(compiler).import_file(str(tmp_path / "regs.xml"))
    block = compiler.elaborate().top        # the memory map: an address block per group
    source = compile_map(cfg, store)
    assert [c.inst_name for c in block.children()] == ["identification", "control", "status",
                                                       "LUT"]
    assert _summary(block) == _summary(source)
    assert len(_summary(source)) > 70


def test_markdown_shows_each_fields_kind_and_range():
    text = register_outputs.markdown(make_config(width=16, height=12, candidate_count=3))
    assert "|Bits|  Identifier  |Access|Reset|Name|  Kind | Range|" in text
    assert "|15:0|segment_frames|  rw  | 0x4 |  — |setting|[1, 4]|" in text
    assert "| 8:0|   code   |   w  | 0x0 |  — |window|[0, 256]|" in text
