"""cocotb verification components, the parts that run without a simulator: pause
generators."""

from __future__ import annotations

import itertools

import pytest

from dptbd.sim.components import pause_generator


def test_pause_generators():
    assert not any(itertools.islice(pause_generator(None), 100))
    assert list(itertools.islice(pause_generator({"kind": "pattern", "pattern": [1, 1, 1, 0]}),
                                 8)) == [True, True, True, False] * 2
    a = list(itertools.islice(pause_generator({"kind": "random", "probability": 0.3,
                                               "seed": 7}), 4000))
    b = list(itertools.islice(pause_generator({"kind": "random", "probability": 0.3,
                                               "seed": 7}), 4000))
    assert a == b and 0.25 < sum(a) / len(a) < 0.35
    with pytest.raises(ValueError, match=r"\[0, 1\)"):
        pause_generator({"kind": "random", "probability": 1.0})
    with pytest.raises(ValueError, match="contain a 0"):
        pause_generator({"kind": "pattern", "pattern": [1, 1]})
    with pytest.raises(ValueError, match="unknown pause kind"):
        pause_generator({"kind": "sometimes"})
