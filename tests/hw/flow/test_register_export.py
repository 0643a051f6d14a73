"""The renderings of the register map: the committed ``docs/registers.md`` is the
generator's output, the C header compiles and carries the map's numbers, the Python
constants are the same numbers."""

import pathlib
import subprocess

from dptbd.config import DPConfig
from dptbd.dsp.firmware_build import find_compiler
from dptbd.hw.flow import register_export
from dptbd.hw.register_map import register_map
from helpers.seg_harness import make_config

ROOT = pathlib.Path(__file__).resolve().parents[3]


def test_committed_markdown_is_the_generators_output():
    cfg = DPConfig()
    want = register_export.markdown(register_map(cfg), cfg)
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
    subprocess.run([find_compiler(), "-std=c99", "-Wall", "-Wextra", "-Werror", "-o", str(exe),
                    str(tmp_path / "probe.c")], check=True, cwd=tmp_path)
    out = subprocess.run([str(exe)], check=True, capture_output=True, text=True).stdout
    got = dict(line.split() for line in out.splitlines())
    assert {k: int(v) for k, v in got.items()} == {
        **consts, "LUT_ADDRESS": consts["LUT_BASE"] + 4 * cfg.lut_address(25, 3)}
    assert consts["REG_SEGMENT_FRAMES"] == regmap["SEGMENT_FRAMES"].address


def test_python_module_and_namespace_carry_the_same_numbers():
    cfg = make_config(width=16, height=12)
    regmap = register_map(cfg)
    scope = {}
    exec(register_export.python_module(regmap, cfg), scope)
    consts = register_export.register_constants(regmap)
    assert {k: scope[k] for k in consts} == consts
    assert vars(register_export.constants_namespace(cfg)) == consts
    assert consts["ERROR_WRITE_REFUSED_MASK"] == 1 << 4
    assert consts["BUILD_FRAME_WIDTH_RESET"] == 16
