"""The float kernel of ``dptbd compare`` (:func:`dptbd.model.fast.floating.run_float_fast`):
bit-identical to :func:`dptbd.model.reference.run_float`, refusing what it refuses."""

from __future__ import annotations

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.weights import plain_weights
from dptbd.model.fast.floating import run_float_fast
from dptbd.model.reference import run_float


@pytest.mark.parametrize("kw", [
    {}, {"radius": 2}, {"segment_frames": 3, "segment_stride": 2}, {"segment_frames": 1},
    {"weights": "random"}, {"weights": "plain"},
])
def test_float_kernel_is_bit_identical_to_run_float(kw):
    kw = dict(kw)
    radius = kw.get("radius", 1)
    m = (2 * radius + 1) ** 2
    if kw.get("weights") == "random":
        kw["weights"] = np.random.default_rng(3).random((m + 1, m))
    elif kw.get("weights") == "plain":
        kw["weights"] = plain_weights(radius)
    cfg = DPConfig(width=11, height=7, **kw)
    rng = np.random.default_rng(1)
    frames = rng.normal(30, 2, (2, 9, 7, 11)).astype(np.float32)
    frames[0, :, 3, 4] = 30.0  # equal values: ties must break the same way
    frames[1] = np.rint(frames[1])
    a, b = run_float_fast(frames, cfg, threads=2), run_float(frames, cfg)
    assert np.array_equal(a.energy, b.energy) and a.energy.dtype == np.float64
    assert np.array_equal(a.direction, b.direction)
    assert np.array_equal(a.end_frames, b.end_frames)


def test_float_kernel_refuses_what_run_float_refuses():
    cfg = DPConfig(width=5, height=5)
    bad = np.full((4, 5, 5), np.nan)
    for fn in (run_float, run_float_fast):
        with pytest.raises(ValueError, match=r"^pixels must be finite; found NaN or inf$"):
            fn(bad, cfg)
        with pytest.raises(ValueError, match=r"^a sequence of 2 frames is shorter than one segment "
                                           r"\(segment_frames=4\)$"):
            fn(np.zeros((2, 5, 5)), cfg)
