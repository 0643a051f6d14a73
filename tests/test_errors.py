"""``dptbd.errors``: the error family and the one message format of every parameter check."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dptbd.errors import (ConfigError, DptbdError, check_bool, check_int, check_prob, check_real,
                          check_shape, interval, shown)
from dptbd.dsp.association import AssociationError
from dptbd.evaluation.detectors import DetectorError
from dptbd.evaluation.run.scenario import ScenarioError
from dptbd.scenes.recorded import SequenceError
from dptbd.scenes.synthetic import SceneError
from helpers.refusals import whole


class PartError(DptbdError):
    """A caller's own error class."""


def test_every_error_class_is_a_dptbd_error_and_a_value_error():
    for error in (ConfigError, SceneError, SequenceError, AssociationError, DetectorError,
                  ScenarioError):
        assert issubclass(error, DptbdError) and issubclass(error, ValueError)


def test_interval():
    assert interval(1, 16) == "[1, 16]"
    assert interval(0, None) == "[0, inf)"
    assert interval(0.0, 1.0, lo_open=True, hi_open=True) == "(0, 1)"
    assert interval(-math.inf, 0.25) == "(-inf, 0.25]"
    assert interval(-30.0, 60.0) == "[-30, 60]"
    assert interval(8, 32, lo_name="input_bits=") == "[input_bits=8, 32]"
    assert interval(1, 4, hi_name="segment_frames=") == "[1, segment_frames=4]"


def test_shown_writes_numpy_scalars_as_python_values():
    assert shown(np.int64(5)) == "5" and shown(np.float32(0.5)) == "0.5"
    assert shown("8") == "'8'" and shown(None) == "None" and shown((5,)) == "(5,)"


@pytest.mark.parametrize("value", [1, 16, np.int64(7), np.uint8(3)])
def test_check_int_accepts_integers_in_range(value):
    out = check_int("bits", value, 1, 16)
    assert out == value and type(out) is int


@pytest.mark.parametrize("value, hi, got", [
    (0, 16, "0"), (17, 16, "17"), (np.int64(-3), 16, "-3"), (8.0, 16, "8.0"), (True, 16, "True"),
    ("8", 16, "'8'"), (None, 16, "None"), (np.bool_(True), 16, "True"),
])
def test_check_int_refuses_with_one_message(value, hi, got):
    with pytest.raises(DptbdError, match=whole(f"bits must be an integer in [1, 16], got {got}")):
        check_int("bits", value, 1, hi)


def test_check_int_unbounded_labelled_and_the_callers_class():
    assert check_int("seed", 10**12, 0) == 10**12
    with pytest.raises(PartError, match=whole("seed must be an integer in [0, inf), got -1")):
        check_int("seed", -1, 0, error=PartError)
    with pytest.raises(PartError, match=whole(
            "energy_bits must be an integer in [input_bits=12, 32], got 11")):
        check_int("energy_bits", 11, 12, 32, lo_name="input_bits=", error=PartError)


@pytest.mark.parametrize("value", [0, 0.5, 1, np.float32(0.25), np.int16(1)])
def test_check_real_accepts_finite_reals_in_range(value):
    out = check_real("ratio", value, 0.0, 1.0)
    assert out == float(value) and type(out) is float


@pytest.mark.parametrize("value, got", [
    (-0.5, "-0.5"), (1.5, "1.5"), (math.nan, "nan"), (math.inf, "inf"), (True, "True"),
    ("0.5", "'0.5'"), (None, "None"), (np.float64(2.0), "2.0"),
])
def test_check_real_refuses_with_one_message(value, got):
    with pytest.raises(DptbdError, match=whole(f"ratio must be a finite real number in [0, 1], got {got}")):
        check_real("ratio", value, 0.0, 1.0)


def test_check_real_open_ends_and_infinite_bounds():
    assert check_real("x", -1e300) == -1e300
    with pytest.raises(PartError, match=whole("x must be a finite real number in (-inf, inf), got inf")):
        check_real("x", math.inf, error=PartError)
    with pytest.raises(DptbdError, match=whole("sigma must be a finite real number in (0, inf), got 0.0")):
        check_real("sigma", 0.0, 0.0, lo_open=True)
    with pytest.raises(DptbdError, match=whole("p must be a finite real number in [0, 1), got 1.0")):
        check_real("p", 1.0, 0.0, 1.0, hi_open=True)


def test_check_prob():
    assert check_prob("pfa", 1e-6) == 1e-6
    for value in (0.0, 1.0):
        with pytest.raises(DptbdError, match=whole(
                f"pfa must be a finite real number in (0, 1), got {value!r}")):
            check_prob("pfa", value)
    assert check_prob("rate", 1.0, hi_open=False) == 1.0
    with pytest.raises(PartError, match=whole("rate must be a finite real number in [0, 1), got 1.0")):
        check_prob("rate", 1.0, lo_open=False, error=PartError)


def test_check_bool():
    assert check_bool("flag", True) is True and check_bool("flag", np.bool_(False)) is False
    for value, got in ((1, "1"), ("yes", "'yes'"), (None, "None")):
        with pytest.raises(PartError, match=whole(f"flag must be true or false, got {got}")):
            check_bool("flag", value, error=PartError)


def test_check_shape():
    assert check_shape("shape", (4, np.int64(5))) == (4, 5)
    assert check_shape("shape", [3, 7], 65535, axes=("height", "width")) == (3, 7)
    for value, got in ((5, "5"), ((5,), "(5,)"), ((1, 2, 3), "(1, 2, 3)"), ("ab", "'ab'")):
        with pytest.raises(DptbdError, match=whole(
                f"shape must be a pair (H, W) of integers in [1, inf), got {got}")):
            check_shape("shape", value)
    with pytest.raises(PartError, match=whole("grid[1] (J) must be an integer in [1, 8], got 9")):
        check_shape("grid", (2, 9), 8, axes=("I", "J"), error=PartError)
    with pytest.raises(DptbdError, match=whole("shape[0] (H) must be an integer in [1, inf), got 2.0")):
        check_shape("shape", (2.0, 3))
