"""``dptbd.toml_writer``: what ``dump_toml`` writes ``tomllib`` reads back as the same values."""

from __future__ import annotations

import math
import tomllib

import pytest

from dptbd.toml_writer import dump_toml
from helpers.refusals import whole


def test_two_level_document_round_trips():
    doc = {
        "name": 'a "quoted" \\ name',
        "seed": 7,
        "scene": {"size": [128, 96], "snr": 2.5, "on": True, "off": False,
                  "targets": [{"start": [30.0, 100.0], "velocity": [0.8, -0.4]},
                              {"start": [1.0, 2.0], "turns": [{"frame": 5, "degrees": 90.0}]}]},
        "adc": {"bits": 12, "gain": 16.0, "big": 1e300, "small": -2.5e-12},
    }
    text = dump_toml(doc)
    assert tomllib.loads(text) == doc
    assert text.startswith('name = "a \\"quoted\\" \\\\ name"\nseed = 7\n\n[scene]\n')
    assert "\n[[scene.targets]]\nstart = [30.0, 100.0]\n" in text
    assert text.endswith("\n") and not text.endswith("\n\n")


def test_non_finite_floats():
    back = tomllib.loads(dump_toml({"t": {"a": math.inf, "b": -math.inf, "c": math.nan}}))["t"]
    assert back["a"] == math.inf and back["b"] == -math.inf and math.isnan(back["c"])


def test_a_value_toml_cannot_hold_is_refused_by_type():
    message = ("cannot write set to TOML; allowed: bool, int, float, str, list, tuple, mapping")
    with pytest.raises(TypeError, match=whole(message)):
        dump_toml({"t": {"s": {1, 2}}})
