"""``dptbd.hw.flow.family``: the two families, their devices and their refusals."""

import pytest

from dptbd.hw.flow.family import ECP5, FAMILIES, ICE40, get_family


def test_families():
    assert FAMILIES == {"ice40": ICE40, "ecp5": ECP5} and get_family("ecp5") is ECP5
    assert ICE40.device_args("hx8k", "ct256") == ["--hx8k", "--package", "ct256"]
    assert ECP5.device_args("45k", "CABGA256") == ["--45k", "--package", "CABGA256"]
    assert (ICE40.default_target_mhz, ECP5.default_target_mhz) == (100.0, 200.0)
    assert (ICE40.logic_cell_bel, ECP5.logic_cell_bel) == ("ICESTORM_LC", "TRELLIS_COMB")


def test_refusals():
    with pytest.raises(ValueError, match=r"^family must be one of \('ice40', 'ecp5'\), "
                                         r"got 'xc7'$"):
        get_family("xc7")
    with pytest.raises(ValueError, match=(
            r"^device must be one of \('lp384', 'lp1k', 'lp4k', 'lp8k', 'hx1k', 'hx4k', "
            r"'hx8k', 'up3k', 'up5k', 'u1k', 'u2k', 'u4k'\) for family 'ice40', got '25k'$")):
        ICE40.device_args("25k", "ct256")
