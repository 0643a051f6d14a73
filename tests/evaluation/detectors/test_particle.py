"""The particle-filter TBD (``particle``): a bright target is found and its existence rises,
noise-only keeps it low, the same seed gives the same result in any batch, the kernels, and
the refusals."""

from __future__ import annotations

import numpy as np
import pytest

from dptbd.evaluation.detectors import DetectorError
from dptbd.evaluation.detectors.adapters import detector_parameters, make_detector
from dptbd.evaluation.detectors.interface import SceneModel
from dptbd.evaluation.detectors.particle import ParticleTBD, _heaviest_cell, _systematic
from dptbd.scenes.synthetic import Target, make_scene
from helpers.refusals import whole


def image(seed=0, amplitude=4.0, trials=None, frames=12):
    tg = Target((5.0, 4.0), (1.0, 1.0), amplitude)
    return make_scene((24, 24), frames, [tg] if amplitude else [], seed=seed, trials=trials)


def test_a_bright_target_is_found_and_its_existence_rises():
    sc = image()
    run = ParticleTBD((24, 24), snr_db=12.0, likelihood="gaussian", alpha=1.0, max_speed=2.0,
                      particles=2000, birth_particles=2000).run(sc.frames)
    truth = sc.truth[0].pixel
    assert run.existence[-1] > 0.999 and run.statistic[-1] > 7
    assert np.all(run.existence[4:] > 0.8) and np.median(run.existence[4:]) > 0.999
    assert np.all(np.max(np.abs(run.estimate[4:] - truth[4:]), axis=-1) <= 1)
    # P(exists) is the logistic of the statistic
    assert np.allclose(run.existence, 1 / (1 + np.exp(-run.statistic)))


def test_noise_only_keeps_the_existence_low():
    runs = [ParticleTBD((24, 24), snr_db=12.0, likelihood="gaussian", alpha=1.0, max_speed=2.0,
                        particles=1000, birth_particles=1000).run(image(seed=s, amplitude=0.0).frames)
            for s in range(4)]
    existence = np.stack([r.existence for r in runs])
    assert existence.mean() < 0.1 and np.median(existence) < 0.1


def test_same_seed_same_result_in_any_batch_other_seed_other_result():
    model = SceneModel((24, 24), "gaussian", 1.0, 12.0, 2, None)
    frames = image(amplitude=3.0, trials=3).frames
    det = make_detector("pf-tbd", model, particles=300, birth_particles=300, seed=5)
    whole_batch = det.decide(frames)
    one_by_one = [det.decide(frames[i:i + 1]) for i in range(3)]
    assert np.array_equal(whole_batch.statistic, np.concatenate([d.statistic for d in one_by_one]))
    assert np.array_equal(whole_batch.estimate, np.concatenate([d.estimate for d in one_by_one]))
    again = make_detector("pf-tbd", model, particles=300, birth_particles=300, seed=5).decide(frames)
    assert np.array_equal(again.statistic, whole_batch.statistic)
    other = make_detector("pf-tbd", model, particles=300, birth_particles=300, seed=6).decide(frames)
    assert not np.array_equal(other.statistic, whole_batch.statistic)


def test_first_frame_has_only_births_exactly():
    # before the first frame P = 0: odds = birth * mean_c l(z_c) / (1 - birth), no particle noise
    z = np.abs(np.random.default_rng(2).normal(size=(1, 6, 7)))
    pf = ParticleTBD((6, 7), snr_db=3.0, alpha=1.0, birth=0.1, particles=10, birth_particles=10)
    ll = pf.log_likelihood(z[0])
    expected = np.log(0.1 * np.mean(np.exp(ll)) / 0.9)
    assert np.isclose(pf.run(z).statistic[0], expected, rtol=1e-12)


def test_systematic_resampling_and_heaviest_cell():
    w = np.array([0.1, 0.0, 0.6, 0.3])
    assert list(_systematic(w, 0.5, 10)) == [0, 2, 2, 2, 2, 2, 2, 3, 3, 3]
    pos = np.array([[0.2, 0.1], [2.4, 1.6], [2.0, 2.0], [-3.0, 9.0]])
    assert _heaviest_cell(pos, np.array([0.3, 0.2, 0.2, 0.25]), 3, 3) == (2, 2)  # 0.2 + 0.2
    assert _heaviest_cell(pos, np.array([0.5, 0.2, 0.2, 0.0]), 3, 3) == (0, 0)
    assert _heaviest_cell(pos, np.array([0.1, 0.0, 0.0, 0.2]), 3, 3) == (0, 2)  # clipped in


def test_adapter_parameters():
    assert detector_parameters("pf-tbd") == ("particles", "birth_particles", "birth", "death",
                                            "process_noise", "seed", "known_noise")
    det = make_detector("pf-tbd", SceneModel((20, 12), scale=2.0), known_noise=True)
    assert det.filter.alpha == 2.0 and det.filter.likelihood == "rician" and det.uses_channel


@pytest.mark.parametrize("kw, message", [
    (dict(particles=0), "particles must be an integer in [1, 10000000], got 0"),
    (dict(birth_particles=2.5), "birth_particles must be an integer in [1, 10000000], got 2.5"),
    (dict(birth=1.0), "birth must be a finite real number in (0, 1), got 1.0"),
    (dict(death=0.0), "death must be a finite real number in (0, 1), got 0.0"),
    (dict(process_noise=-0.1),
     "process_noise (velocity change, cells/frame) must be a finite real number in [0, inf), got -0.1"),
    (dict(seed=-1), "seed must be an integer in [0, inf), got -1"),
    (dict(known_noise="no"), "known_noise must be true or false, got 'no'"),
])
def test_bad_parameters(kw, message):
    with pytest.raises(DetectorError, match=whole(message)):
        make_detector("pf-tbd", SceneModel((20, 12)), **kw)


def test_bad_filter_input():
    with pytest.raises(DetectorError, match=whole(
            "max_speed (birth velocity bound, cells/frame) must be a finite real number in (0, inf), got 0.0")):
        ParticleTBD((4, 4), max_speed=0.0)
    with pytest.raises(DetectorError, match=whole(
            "likelihood must be one of ('rician', 'gaussian'), got 'poisson'")):
        ParticleTBD((4, 4), likelihood="poisson")
    pf = ParticleTBD((4, 4))
    with pytest.raises(DetectorError, match=whole(
            "frames must be one sequence (T, 4, 4), got shape (2, 4, 5)")):
        pf.run(np.ones((2, 4, 5)))
    with pytest.raises(DetectorError, match=whole(
            "frames must be magnitudes >= 0 for the Rician likelihood")):
        pf.run(-np.ones((2, 4, 4)))
