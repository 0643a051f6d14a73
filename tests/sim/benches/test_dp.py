"""RTL simulation of the generated Verilog (cocotb 2 + Icarus) against the golden model.

Every test builds ``dptbd_dp`` for its parameter set in its own directory under
``build/sim/`` (cached between runs: Icarus recompiles only when the Verilog changed), writes
the scene and the job into a run directory and runs a cocotb test of
:mod:`dptbd.sim.benches.dp` through ``cocotb_tools.runner``. The cocotb scoreboard compares every
output word with :mod:`dptbd.model.fixed`, bit for bit, over whole multi-segment scenes.

``pytest -m slow tests/sim`` adds the longer 128 x 128 run.
"""

from __future__ import annotations

import pathlib
import shutil
import warnings

import numpy as np
import pytest

from dptbd.config import DPConfig, EnergyWidthWarning
from dptbd.hw.layouts import unpack_state
from dptbd.sim.icarus import build, simulate
from dptbd.sim.scenarios import make_frames
from dptbd.sim.scoreboard import expected_words

pytestmark = pytest.mark.skipif(shutil.which("iverilog") is None, reason="needs Icarus Verilog")

BUILD_ROOT = pathlib.Path(__file__).resolve().parents[3] / "build" / "sim"

RANDOM = lambda p, seed: {"kind": "random", "probability": p, "seed": seed}  # noqa: E731
CYCLE_PAUSE = {"kind": "pattern", "pattern": [1, 1, 1, 0]}   # verilog-axis cycle_pause


def make_config(**kw) -> DPConfig:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        return DPConfig(**kw)


_BUILDS: dict = {}


def built(cfg: DPConfig):
    """One build per parameter set and session (its own directory under build/sim)."""
    if cfg not in _BUILDS:
        _BUILDS[cfg] = build(cfg, BUILD_ROOT)
    return _BUILDS[cfg]


def run(cfg: DPConfig, frames, run_name: str, **options):
    sim = built(cfg)
    result = simulate(sim, frames, run_name=run_name, **options)
    return sim, result


def assert_passed(result) -> None:
    assert result.passed, (f"{result.report}\n--- {result.log} (tail) ---\n"
                           f"{result.log_tail()}")


def energies(cfg: DPConfig, frames) -> np.ndarray:
    words = expected_words(cfg, frames).ravel()
    return np.array([unpack_state(cfg, w)["energy"] for w in words])


# name: (config, scenario, frames, options)
CASES = {
    "8x6-k3-mixed-random-pauses": (
        dict(width=8, height=6, segment_frames=3), "mixed", 9,
        dict(valid_pause=RANDOM(0.3, 1), ready_pause=RANDOM(0.3, 2))),
    "8x6-k3-random-cycle-pause": (
        dict(width=8, height=6, segment_frames=3), "random", 7,
        dict(valid_pause=CYCLE_PAUSE, ready_pause=RANDOM(0.5, 3))),
    "13x7-k4-half_up-edges": (
        dict(width=13, height=7, segment_frames=4, rounding="half_up"), "edges", 10,
        dict(valid_pause=RANDOM(0.2, 4), ready_pause=RANDOM(0.4, 5))),
    "9x7-in6-e7-saturating": (
        dict(width=9, height=7, segment_frames=3, input_bits=6, energy_bits=7), "saturating", 7,
        dict(valid_pause=RANDOM(0.2, 6), ready_pause=RANDOM(0.2, 7))),
    "8x6-k4-ties": (
        dict(width=8, height=6, segment_frames=4), "ties", 8,
        dict(valid_pause=RANDOM(0.25, 8), ready_pause=RANDOM(0.25, 9))),
    "11x9-r2-k3-half_up-f6": (
        dict(width=11, height=9, segment_frames=3, radius=2, rounding="half_up",
             weight_frac_bits=6), "mixed", 7,
        dict(valid_pause=RANDOM(0.2, 10), ready_pause=RANDOM(0.3, 11))),
    "12x10-k2-f0-two-targets": (
        dict(width=12, height=10, segment_frames=2, weight_frac_bits=0), "two-targets", 5,
        dict(valid_pause=RANDOM(0.1, 12), ready_pause=RANDOM(0.1, 13))),
    "10x8-k1-in12-e16-table1": (
        dict(width=10, height=8, segment_frames=1, input_bits=12), "table1", 3,
        dict(ready_pause=RANDOM(0.3, 14))),
}


@pytest.mark.parametrize("name", list(CASES))
def test_scene_matches_model(name):
    kw, scenario, n_frames, options = CASES[name]
    cfg = make_config(**kw)
    frames = make_frames(scenario, cfg, n_frames, seed=len(name))
    if scenario == "saturating":
        assert (energies(cfg, frames) == cfg.e_max).any(), "the scene must saturate"
    if scenario == "ties":
        assert frames.max() <= 1
    _, result = run(cfg, frames, name, **options)
    assert_passed(result)
    assert result.summary["outputs"] == frames.size


def test_lut_written_at_run_time():
    """A non-default LUT through lut_addr/lut_data/lut_we before the first frame."""
    cfg = make_config(width=10, height=8, segment_frames=4, weight_frac_bits=5,
                      rounding="half_up")
    rng = np.random.default_rng(21)
    codes = rng.integers(0, (1 << cfg.weight_frac_bits) + 1, size=cfg.weight_codes.shape)
    frames = make_frames("mixed", cfg, 8, seed=21)
    # the written LUT must change the result, or the test would prove nothing
    assert not np.array_equal(expected_words(cfg, frames),
                              expected_words(cfg.with_weight_codes(codes), frames))
    _, result = run(cfg, frames, "runtime-lut", lut_codes=codes,
                    valid_pause=RANDOM(0.2, 22), ready_pause=RANDOM(0.2, 23))
    assert_passed(result)
    assert result.summary["lut_written"]


@pytest.mark.parametrize("kw, scenario, n_frames", [
    (dict(width=16, height=12, segment_frames=2), "table1", 5),
    (dict(width=11, height=9, segment_frames=3, radius=2), "noise", 4),
    # 001's size: 15 s of Icarus, -m slow (the small sizes take the same paths)
    pytest.param(dict(width=128, height=128, segment_frames=2), "two-targets", 3,
                 marks=pytest.mark.slow),
], ids=["16x12-r1", "11x9-r2", "128x128-r1"])
def test_exact_cycle_count(kw, scenario, n_frames):
    """No gaps, no back-pressure: T*W*H + latency cycles from first input to last output."""
    cfg = make_config(**kw)
    frames = make_frames(scenario, cfg, n_frames, seed=5)
    sim, result = run(cfg, frames, f"exact-{cfg.width}x{cfg.height}", exact_cycles=True)
    assert_passed(result)
    total = frames.size
    assert result.cycles == total + sim.latency
    assert result.summary["first_output_cycle"] - result.summary["first_accept_cycle"] \
        == sim.latency
    assert sim.latency == {1: 14, 2: 15}[cfg.radius]            # F = 8
    assert result.cycles == {(16, 1): 5 * 192 + 14, (11, 2): 4 * 99 + 15,
                             (128, 1): 3 * 16384 + 14}[(cfg.width, cfg.radius)]


def test_mid_frame_reset():
    """rst in the middle of frame 4 (2nd frame of a segment) with pixels in flight; clean
    frames follow. A run-time LUT written before the first frame survives the reset."""
    cfg = make_config(width=8, height=6, segment_frames=3, weight_frac_bits=3)
    codes = np.random.default_rng(30).integers(0, 9, size=cfg.weight_codes.shape)
    frames = make_frames("mixed", cfg, 4 + 1 + 7, seed=31)
    _, result = run(cfg, frames, "mid-frame-reset", testcase="mid_frame_reset", lut_codes=codes,
                    reset={"pre_frames": 4, "cut_pixel": 19, "hold_cycles": 3},
                    valid_pause=RANDOM(0.2, 32), ready_pause=RANDOM(0.3, 33))
    assert_passed(result)
    s = result.summary
    assert s["frames_after_reset"] == 7 and s["lut_written"]
    assert s["outputs_before_reset"] < s["reset_after_pixels"]     # some were in flight


def test_truncated_frame_resynchronises():
    """Frame 3 cut after 21 pixels, then frames with `first`: a new segment starts."""
    cfg = make_config(width=8, height=6, segment_frames=3)
    frames = make_frames("mixed", cfg, 3 + 1 + 6, seed=35)
    _, result = run(cfg, frames, "truncated-resync", testcase="truncated_frame_resync",
                    truncate={"pre_frames": 3, "keep_pixels": 21},
                    valid_pause=RANDOM(0.3, 36), ready_pause=RANDOM(0.3, 37))
    assert_passed(result)
    assert result.summary["outputs"] == 3 * 48 + 21 + 6 * 48


def test_scoreboard_catches_a_corrupted_expectation():
    """The checker can fail: one flipped bit of one expected word fails the run."""
    cfg = make_config(width=8, height=6, segment_frames=3)
    frames = make_frames("noise", cfg, 4, seed=41)
    index = 2 * 48 + 3 * 8 + 5                                    # frame 2, row 3, col 5
    _, result = run(cfg, frames, "corrupted", corrupt_expected={"index": index, "xor": 1 << 2})
    assert not result.passed
    assert result.summary["verdict"] == "mismatch"
    assert "frame 2, row 3, col 5, field energy" in result.report


@pytest.mark.slow
def test_128x128_segments_with_pauses():
    """001's frame size, two segments of K = 4 with gaps and back-pressure (about 2 min)."""
    cfg = make_config(width=128, height=128, segment_frames=4)
    frames = make_frames("two-targets", cfg, 8, seed=51)
    _, result = run(cfg, frames, "128x128-pauses", valid_pause=RANDOM(0.1, 52),
                    ready_pause=RANDOM(0.1, 53))
    assert_passed(result)
