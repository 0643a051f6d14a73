"""``hw/registers.rdl`` compiled per build: the configuration reaches it as parameter
overrides, ``--state-store axi`` as a preprocessor define; a malformed ``.rdl`` is refused by
the compiler's own error with the file, line and column."""

import pathlib

import pytest

from dptbd.config import DPConfig
from dptbd.hw.registers import (RDL_PATH, TOP_NAME, RegisterMapError, compile_map,
                                rdl_parameters)
from helpers.refusals import whole
from helpers.seg_harness import make_config


def _reset(top, path: str) -> int:
    return top.find_by_path(path).get_property("reset")


def test_the_configuration_reaches_the_map_as_parameters():
    cfg = make_config(width=24, height=20, radius=2, candidate_count=7, energy_bits=12,
                      segment_frames=3, max_segment_frames=9)
    top = compile_map(cfg)
    assert top.inst_name == TOP_NAME and top.type_name.startswith(TOP_NAME)
    assert (_reset(top, "identification.BUILD_FRAME.width"),
            _reset(top, "identification.BUILD_FRAME.height")) == (24, 20)
    assert _reset(top, "identification.BUILD_SEGMENT.k_max") == 9
    field = top.find_by_path("control.HISTOGRAM_SHIFT.histogram_shift")
    assert (field.width, field.get_property("range_max")) == (4, 11)
    lut = top.get_child_by_name("LUT")
    assert lut.get_property("mementries") == cfg.lut_entries == 650
    assert rdl_parameters(cfg)["HISTOGRAM_SHIFT_MAX"] == 11


def test_the_state_store_registers_are_in_its_build_only():
    cfg = DPConfig().build_config()
    store = cfg.axi_store(data_bits=128, base_address=0x8000)
    plain, full = compile_map(cfg), compile_map(cfg, store)
    assert plain.find_by_path("control.STATE_BASE") is None
    base = full.find_by_path("control.STATE_BASE.state_base")
    # burst: 16 beats of 128 bits
    assert (base.get_property("reset"), base.get_property("range_align")) == (0x8000, 256)
    assert rdl_parameters(cfg, store)["STORE_BASE_MAX"] == 2**32 - store.frame_bytes


def test_a_build_is_compiled_once():
    cfg = make_config(width=16, height=12)
    assert compile_map(cfg) is compile_map(cfg)
    assert compile_map(cfg) is not compile_map(cfg, cfg.axi_store())


def _broken(tmp_path, old: str, new: str, token: str) -> tuple[pathlib.Path, str]:
    """A copy of the ``.rdl`` with ``old`` replaced by ``new``, and ``path:line:column`` of
    ``token`` on the replaced line (where the compiler points)."""
    text = RDL_PATH.read_text()
    assert text.count(old) == 1
    path = tmp_path / "broken.rdl"
    path.write_text(text.replace(old, new))
    before = text[:text.index(old)]
    line = before.count("\n") + 1
    column = len(before) - before.rfind("\n") + new.index(token)
    return path, f"{path}:{line}:{column}"


def test_overlapping_fields_are_refused_with_file_and_line(tmp_path):
    text = RDL_PATH.read_text()
    path = tmp_path / "broken.rdl"
    path.write_text(text.replace("constant minor[16] = MINOR;", "constant minor[15:0] = MINOR;")
                    .replace("constant major[16] = MAJOR;", "constant major[23:8] = MAJOR;"))
    before = text[:text.index("constant major[16]")]
    where = f"{path}:{before.count(chr(10)) + 1}:{len(before) - before.rfind(chr(10)) + 9}"
    with pytest.raises(RegisterMapError, match=whole(
            f"{where}: error: Field 'major[23:8]' overlaps with field 'minor[15:0]'")):
        compile_map(DPConfig(), source=path)


def test_a_reset_value_wider_than_its_field_is_refused_with_file_and_line(tmp_path):
    path, where = _broken(tmp_path, "enable fault[1] = 0;", "enable fault[1] = 2;", "fault")
    with pytest.raises(RegisterMapError, match=whole(
            f"{where}: error: The reset value (2) of field 'fault' cannot fit within its "
            f"width (1)")):
        compile_map(DPConfig(), source=path)


def test_the_rdl_is_package_data():
    """An installed ``dptbd`` carries the ``.rdl`` (pyproject's package data of
    ``dptbd.hw``, whose folder is ``hw/``)."""
    import fnmatch
    import tomllib

    root = pathlib.Path(__file__).resolve().parents[2]
    tool = tomllib.loads((root / "pyproject.toml").read_text())["tool"]["setuptools"]
    assert tool["package-dir"]["dptbd.hw"] == "hw" and RDL_PATH.parent == root / "hw"
    assert any(fnmatch.fnmatch(RDL_PATH.name, pattern)
               for pattern in tool["package-data"]["dptbd.hw"])
