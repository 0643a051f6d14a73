"""``dptbd.hw.flow.family``: the two families, their devices and their refusals."""

import pytest

from dptbd.config import DPConfig
from dptbd.errors import ConfigError
from dptbd.hw.flow.family import ECP5, FAMILIES, ICE40, get_family
from dptbd.hw.flow.synth import ToolNotFoundError, synthesize


def test_families():
    assert FAMILIES == {"ice40": ICE40, "ecp5": ECP5} and get_family("ecp5") is ECP5
    assert ICE40.device_args("hx8k", "ct256") == ["--hx8k", "--package", "ct256"]
    assert ECP5.device_args("45k", "CABGA256") == ["--45k", "--package", "CABGA256"]
    assert (ICE40.default_target_mhz, ECP5.default_target_mhz) == (100.0, 200.0)
    assert (ICE40.logic_cell_bel, ECP5.logic_cell_bel) == ("ICESTORM_LC", "TRELLIS_COMB")
    assert ICE40.core_options == {"line_buffer_style": "bram", "sideband_delay": "memory",
                                  "max_tree": "compact", "state_store_style": "memory",
                                  "histogram_style": "memory", "control_style": "generic",
                                  "output_queue_style": "binary",
                                  "register_read": "one_level", "credit_ready": "one",
                                  "lut_write": "case"}
    assert ECP5.core_options == {"line_buffer_style": "lutram", "sideband_delay": "registers",
                                 "max_tree": "split", "state_store_style": "dp16kd",
                                 "histogram_style": "dp16kd", "control_style": "registered",
                                 "output_queue_style": "one_hot",
                                 "register_read": "two_level", "credit_ready": "per_load",
                                 "lut_write": "predecoded"}


def test_ecp5_builds_the_line_buffer_in_dp16kds_from_512_wide():
    """The options for a configuration: ECP5's line buffer in DP16KDs from 512 pixels wide,
    at P = 1 and P = 4 alike; iCE40's always its block RAM."""
    for width, p, style in ((128, 1, "lutram"), (508, 4, "lutram"), (512, 1, "dp16kd"),
                            (640, 4, "dp16kd"), (1280, 1, "dp16kd")):
        cfg = DPConfig(width=width, height=64, pixels_per_clock=p)
        assert ECP5.options_for(cfg) == {**ECP5.core_options, "line_buffer_style": style}
        assert ICE40.options_for(cfg) == ICE40.core_options
    assert ECP5.dp16kd_line_buffer_from == 512 and ICE40.dp16kd_line_buffer_from is None


def test_refusals():
    with pytest.raises(ValueError, match=r"^family must be one of \('ice40', 'ecp5'\), "
                                         r"got 'xc7'$"):
        get_family("xc7")
    with pytest.raises(ValueError, match=(
            r"^device must be one of \('lp384', 'lp1k', 'lp4k', 'lp8k', 'hx1k', 'hx4k', "
            r"'hx8k', 'up3k', 'up5k', 'u1k', 'u2k', 'u4k'\) for family 'ice40', got '25k'$")):
        ICE40.device_args("25k", "ct256")


def test_an_on_chip_store_that_fits_is_accepted():
    ICE40.check_on_chip_store(DPConfig(width=64, height=64), "hx8k")     # 57344 bits
    ECP5.check_on_chip_store(DPConfig(width=128, height=128), "25k")     # 229376 bits
    ICE40.check_on_chip_store(DPConfig(width=128, height=128), "u4k")    # capacity not listed


def test_a_frame_beyond_the_block_ram_is_refused_naming_the_limit():
    with pytest.raises(ConfigError, match=(
            r"^width=128 x height=128 does not fit the ice40 hx8k's block RAM with an on-chip "
            r"state store: 16384 words of state_bits=20 need at least 327680 bits, the device "
            r"has 131072 \(32 x 4096\); build the core with the store outside \(variant "
            r"'core', 'segmenter-ext' or 'axi-ext'\) or choose a larger device$")):
        ICE40.check_on_chip_store(DPConfig(width=128, height=128), "hx8k")
    with pytest.raises(ConfigError, match=r"^width=640 x height=512 does not fit the ecp5 25k's"):
        ECP5.check_on_chip_store(DPConfig(width=640, height=512), "25k")


@pytest.mark.parametrize("variant", ["top", "segmenter", "axi"])
def test_synthesize_refuses_the_store_before_any_tool_runs(variant):
    with pytest.raises(ConfigError, match=r"^width=128 x height=128 does not fit the ice40 hx8k"):
        synthesize(DPConfig(width=128, height=128), variant=variant, family="ice40",
                   yosys="/nonexistent/yosys", seeds=())


@pytest.mark.parametrize("variant", ["core", "core-regio", "segmenter-ext", "axi-ext"])
def test_the_store_outside_is_not_checked(variant):
    """The variants with the store outside go on to the tools (here: a missing Yosys)."""
    with pytest.raises(ToolNotFoundError, match=r"^'/nonexistent/yosys' not found on PATH"):
        synthesize(DPConfig(width=128, height=128), variant=variant, family="ice40",
                   yosys="/nonexistent/yosys", seeds=())


def test_radius_beyond_a_familys_resources_is_refused():
    """iCE40 builds r = 1 only (r = 2 does not place on the HX8K); ECP5 builds both."""
    r2 = DPConfig(width=16, height=8, radius=2)
    ICE40.check_radius(DPConfig(width=16, height=8))
    ECP5.check_radius(r2)
    with pytest.raises(ConfigError, match=r"^radius=2 is beyond the ice40 family's resources: "
                                          r"radius must be in \[1, 1\] for ice40 "
                                          r"\(docs/synthesis.md\); build for ecp5$"):
        ICE40.check_radius(r2)
