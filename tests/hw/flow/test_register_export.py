"""The renderings of the register map: the committed ``docs/registers.md`` is the
generator's output, the C header compiles and carries the map's numbers, the Python
constants are the same numbers; the header's candidate word decodes every word the
gateware's pack helpers make, field by field."""

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
from dptbd.hw.flow import register_export
from dptbd.hw.register_map import register_map
from helpers.refusals import whole
from helpers.seg_harness import make_config

ROOT = pathlib.Path(__file__).resolve().parents[3]


def test_committed_markdown_is_the_generators_output():
    cfg = DPConfig()
    want = register_export.markdown(register_map(cfg), cfg,
                                    register_map(cfg, cfg.axi_store()))
    assert (ROOT / "docs" / "registers.md").read_text() == want, (
        "docs/registers.md is stale: python -m dptbd.hw.flow.register_export "
        "--markdown docs/registers.md")


def test_c_header_compiles_and_matches_the_map(tmp_path):
    cfg = make_config(width=24, height=20, radius=2, candidate_count=7)
    regmap = register_map(cfg)
    consts = register_export.register_constants(regmap)
    (tmp_path / "dptbd_regs.h").write_text(register_export.c_header(regmap, cfg))
    prints = "\n".join(f'    printf("{name} %lu\\n", (unsigned long)DPTBD_{name});'
                       for name in consts)
    (tmp_path / "probe.c").write_text(
        '#include <stdio.h>\n#include "dptbd_regs.h"\nint main(void) {\n' + prints +
        '\n    printf("LUT_ADDRESS %lu\\n", (unsigned long)DPTBD_LUT_ADDRESS(25, 3));\n'
        '    return 0;\n}\n')
    exe = tmp_path / "probe"
    subprocess.run([find_compiler(), *C_FLAGS, "-o", str(exe),
                    str(tmp_path / "probe.c")], check=True, cwd=tmp_path)
    out = subprocess.run([str(exe)], check=True, capture_output=True, text=True).stdout
    got = dict(line.split() for line in out.splitlines())
    assert {k: int(v) for k, v in got.items()} == {
        **consts, "LUT_ADDRESS": consts["LUT_BASE"] + 4 * cfg.lut_address(25, 3)}
    assert consts["REG_SEGMENT_FRAMES"] == regmap["SEGMENT_FRAMES"].address


C_FLAGS = ("-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic")


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
    consts = register_export.candidate_constants(cfg)
    (tmp_path / "dptbd_regs.h").write_text(register_export.c_header(register_map(cfg), cfg))
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
    (tmp_path / "decode.c").write_text(
        '#include <stdio.h>\n#include "dptbd_regs.h"\nint main(void) {\n'
        f'    unsigned long long w;\n    {sizes}\n'
        '    while (scanf("%llu", &w) == 1) {\n        ' + "\n        ".join(body) +
        '\n    }\n    return 0;\n}\n')
    exe = tmp_path / "decode"
    subprocess.run([find_compiler(), *C_FLAGS, "-o", str(exe), str(tmp_path / "decode.c")],
                   check=True, cwd=tmp_path)
    words = _random_words(cfg, np.random.default_rng(3), 200)
    out = subprocess.run([str(exe)], input=" ".join(map(str, words)), check=True,
                         capture_output=True, text=True).stdout.splitlines()
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
    monkeypatch.setattr(register_export, "candidate_layout", lambda c: data.StructLayout({
        "body": data.UnionLayout({"record": data.StructLayout({"row": unsigned(4)}),
                                  "trailer": wider}),
        "end_of_list": unsigned(1)}))
    consts = register_export.candidate_constants(cfg)
    assert {k: v for k, v in consts.items() if k.startswith("CAND_TRAILER_CUT")} == {
        "CAND_TRAILER_CUT_SHIFT": 3, "CAND_TRAILER_CUT_WIDTH": 1, "CAND_TRAILER_CUT_MASK": 8}
    assert (consts["CAND_END_OF_LIST_SHIFT"], consts["CAND_WORD_BITS"]) == (4, 5)
    assert "#define DPTBD_CAND_TRAILER_CUT_MASK 0x0000000000000008ull\n" in \
        register_export.c_header(register_map(cfg), cfg)
    monkeypatch.setattr(register_export, "candidate_layout", lambda c: data.StructLayout({
        "body": data.UnionLayout({"record": unsigned(64)}), "end_of_list": unsigned(1)}))
    with pytest.raises(ValueError, match=whole(
            "the candidate word is 65 bits wide; dptbd_regs.h holds a word in a uint64_t "
            "(at most 64 bits)")):
        register_export.candidate_constants(cfg)


def test_python_module_and_namespace_carry_the_same_numbers():
    cfg = make_config(width=16, height=12)
    regmap = register_map(cfg)
    scope = {}
    exec(register_export.python_module(regmap, cfg), scope)
    consts = register_export.register_constants(regmap)
    cand = register_export.candidate_constants(cfg)
    assert {k: scope[k] for k in scope if not k.startswith("__")} == {**consts, **cand}
    assert vars(register_export.constants_namespace(cfg)) == consts
    assert consts["ERROR_WRITE_REFUSED_MASK"] == 1 << 4
    assert consts["BUILD_FRAME_WIDTH_RESET"] == 16
