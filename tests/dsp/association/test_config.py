"""Association parameters of ``dptbd.dsp.association.config``: domains, order, refusals."""

import dataclasses

import numpy as np
import pytest

from dptbd.dsp.association.config import AssociationConfig, AssociationError
from dptbd.errors import DptbdError
from helpers.refusals import whole


def test_thresholds_output_above_predict_above_delete():
    order = "association thresholds must be ordered as 001 §3 says (output > predict > delete): "
    with pytest.raises(AssociationError, match=whole(
            order + "confirm_ratio=0.4 >= predict_ratio=0.5 >= delete_ratio=0.4")):
        AssociationConfig(confirm_ratio=0.4, predict_ratio=0.5)
    with pytest.raises(AssociationError, match=whole(
            order + "confirm_ratio=0.6 >= predict_ratio=0.3 >= delete_ratio=0.35")):
        AssociationConfig(predict_ratio=0.3, delete_ratio=0.35)
    with pytest.raises(AssociationError, match=whole(
            "association confirm_hits=1 must be >= predict_hits=2 (output threshold above predict "
            "threshold)")):
        AssociationConfig(confirm_hits=1, predict_hits=2)
    allowed = [f.name for f in dataclasses.fields(AssociationConfig)]
    with pytest.raises(AssociationError, match=whole(
            f"unknown association parameter(s) ['capacitty']; allowed: {allowed}")):
        AssociationConfig.from_mapping({"capacitty": 3})


@pytest.mark.parametrize("overrides, message", [
    (dict(capacity=0), "association capacity must be an integer in [1, 65535], got 0"),
    (dict(capacity=2.0), "association capacity must be an integer in [1, 65535], got 2.0"),
    (dict(max_misses=256), "association max_misses must be an integer in [0, 255], got 256"),
    (dict(merge_radius=True), "association merge_radius must be an integer in [0, 16], got True"),
    (dict(max_speed=65.0), "association max_speed must be a finite real number in [0, 64], got 65.0"),
    (dict(gate_max=float("nan")),
     "association gate_max must be a finite real number in [0, 1000], got nan"),
    (dict(confirm_ratio="0.6"),
     "association confirm_ratio must be a finite real number in [0, 1], got '0.6'"),
    (dict(reject_reversed=1), "association reject_reversed must be true or false, got 1"),
    (dict(confirm_disjoint="yes"), "association confirm_disjoint must be true or false, got 'yes'"),
    (dict(wake_radius=17), "association wake_radius must be an integer in [0, 16], got 17"),
    (dict(wake_points=0), "association wake_points must be an integer in [1, 65535], got 0"),
])
def test_parameters_outside_their_domain_are_refused(overrides, message):
    with pytest.raises(AssociationError, match=whole(message)):
        AssociationConfig(**overrides)
    assert issubclass(AssociationError, DptbdError)


def test_numpy_parameters_become_python_values():
    cfg = AssociationConfig(capacity=np.int64(3), reject_reversed=np.bool_(True), max_speed=np.float32(0.5))
    assert type(cfg.capacity) is int and type(cfg.reject_reversed) is bool and type(cfg.max_speed) is float
