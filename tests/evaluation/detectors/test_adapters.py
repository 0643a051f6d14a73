"""The seven detectors by name: the registry's refusals, each detector on a small scene, the
dw-dp adapter against the golden model."""

from __future__ import annotations

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.evaluation.detectors import DetectorError
from dptbd.evaluation.detectors.adapters import DETECTORS, make_detector, parse_detectors
from dptbd.evaluation.detectors.interface import SceneModel
from dptbd.model.fixed import run_fixed
from dptbd.scenes.range_doppler import rd_scene, straight_track


def test_parse_detectors():
    assert parse_detectors("info, ca-cfar,info") == ("info", "ca-cfar")
    with pytest.raises(DetectorError, match=(r"^unknown detector 'mht'; known: dw-dp, "
                                             r"dp-amplitude, dp-penalty, dp-likelihood, info, "
                                             r"grid-bayes, ca-cfar$")):
        parse_detectors("info,mht")
    with pytest.raises(DetectorError, match=(r"^detectors must name at least one of dw-dp, "
                                             r"dp-amplitude, dp-penalty, dp-likelihood, info, "
                                             r"grid-bayes, ca-cfar$")):
        parse_detectors("")


@pytest.mark.parametrize("name", list(DETECTORS))
def test_every_detector_runs_on_a_small_scene(name):
    model = SceneModel((20, 12), "rayleigh", 1.0, 12.0, 1, None)
    track = straight_track((8, 5), (0.2, 0.1), 10)
    frames = rd_scene((20, 12), 10, track, snr_db=25.0, seed=1, trials=2).frames
    kw = dict(segment_frames=4) if "dp" in name else {}
    dec = make_detector(name, model, **kw).decide(frames)
    assert dec.statistic.shape == (2, 10) and dec.estimate.shape == (2, 10, 2)
    scored = ~np.isnan(dec.statistic)
    assert scored[:, 3:].all()
    if "dp" in name:
        assert not scored[:, :3].any()  # a K-frame segment decides from frame K-1 on
    if name != "dp-likelihood":  # 000's bump merit is not made for a fluctuating target
        near = np.max(np.abs(dec.estimate[:, -1] - np.rint(track[-1])), axis=-1) <= 1
        assert near.all()


def test_dw_dp_adapter_is_the_golden_model():
    model = SceneModel((9, 10), "gaussian", 1.0, 10.0, 2, None)
    det = make_detector("dw-dp", model, segment_frames=3)
    frames = np.random.default_rng(0).normal(size=(2, 5, 9, 10))
    dec = det.decide(frames)
    codes = det.codes(frames)
    cfg = DPConfig(width=10, height=9, segment_frames=3, segment_stride=1, input_bits=10,
                   energy_bits=16, radius=2)
    energy = run_fixed(codes, cfg).energy
    assert np.array_equal(dec.statistic[:, 2:], energy.reshape(2, 3, -1).max(axis=-1))
