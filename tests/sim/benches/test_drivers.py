"""cocotb verification components, the parts that run without a simulator: pause
generators and what the testbenches derive from a pause spec."""

from __future__ import annotations

import itertools

import pytest

from dptbd.sim.benches.drivers import optional_pauses, pause_generator, pause_probability


def test_pause_generators():
    assert not any(itertools.islice(pause_generator(None), 100))
    assert list(itertools.islice(pause_generator({"kind": "pattern", "pattern": [1, 1, 1, 0]}),
                                 8)) == [True, True, True, False] * 2
    a = list(itertools.islice(pause_generator({"kind": "random", "probability": 0.3,
                                               "seed": 7}), 4000))
    b = list(itertools.islice(pause_generator({"kind": "random", "probability": 0.3,
                                               "seed": 7}), 4000))
    assert a == b and 0.25 < sum(a) / len(a) < 0.35
    with pytest.raises(ValueError, match=r"^pause probability must be in \[0, 1\), got 1\.0$"):
        pause_generator({"kind": "random", "probability": 1.0})
    with pytest.raises(ValueError, match=r"^a pause pattern must be non-empty and contain a 0$"):
        pause_generator({"kind": "pattern", "pattern": [1, 1]})
    with pytest.raises(ValueError,
                       match=r"^unknown pause kind 'sometimes'; use none, random or pattern$"):
        pause_generator({"kind": "sometimes"})


def test_optional_pauses_and_pause_probability():
    pattern = {"kind": "pattern", "pattern": [1, 1, 1, 0]}
    assert optional_pauses(None) is None and optional_pauses({"kind": "none"}) is None
    assert list(itertools.islice(optional_pauses(pattern), 4)) == [True, True, True, False]
    assert pause_probability(None) == pause_probability({"kind": "none"}) == 0.0
    assert pause_probability({"kind": "random", "probability": 0.3, "seed": 1}) == 0.3
    assert pause_probability(pattern) == 0.75
