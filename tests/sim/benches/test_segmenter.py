"""RTL simulation of the generated ``dptbd_seg`` (DP pipeline + segmenter; cocotb 2 + Icarus)
against the golden models: every candidate record and trailer of multi-segment scenes, with
random input gaps and back-pressure on ``candidates``, bit for bit.

Builds go to ``build/sim/<config>-seg/`` (cached). ``pytest -m slow tests/sim`` adds a
128 x 128 run with paper 001's 0.2 % count.
"""

from __future__ import annotations

import pathlib
import shutil
import warnings

import pytest

from dptbd.config import DPConfig, EnergyWidthWarning
from dptbd.hw.candidate_layout import bits_per_segment
from dptbd.sim.icarus import build, simulate
from dptbd.sim.scenarios import make_frames
from dptbd.sim.candidate_scoreboard import expected_lists

pytestmark = pytest.mark.skipif(shutil.which("iverilog") is None, reason="needs Icarus Verilog")

BUILD_ROOT = pathlib.Path(__file__).resolve().parents[3] / "build" / "sim"
RANDOM = lambda p, seed: {"kind": "random", "probability": p, "seed": seed}  # noqa: E731

_BUILDS: dict = {}


def make_config(**kw) -> DPConfig:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        return DPConfig(**kw)


def built(cfg):
    if cfg not in _BUILDS:
        _BUILDS[cfg] = build(cfg, BUILD_ROOT, design="segmenter")
    return _BUILDS[cfg]


def assert_passed(result):
    assert result.passed, f"{result.report}\n--- {result.log} (tail) ---\n{result.log_tail()}"


# 16 x 12, K = 3, 0.2 % would be 0 points: n = 6 (3 %), C = 9, 64 bins of width 2
SCENE_CFG = dict(width=16, height=12, segment_frames=3, candidate_count=6, candidate_capacity=9,
                 histogram_bits=6, histogram_shift=1)


def test_multi_segment_scene_with_gaps_and_back_pressure():
    """Five segments of 001's two-target scene (scaled to 16 x 12) with both streams paused."""
    cfg = make_config(**SCENE_CFG)
    frames = make_frames("two-targets", cfg, 15, seed=7)
    lists = expected_lists(cfg, frames)
    assert len(lists) == 5 and sum(lst.count for lst in lists) >= 10
    result = simulate(built(cfg), frames, run_name="seg-two-targets",
                      valid_pause=RANDOM(0.2, 1), ready_pause=RANDOM(0.5, 2))
    assert_passed(result)
    s = result.summary
    assert s["lists"] == 5 and s["counts"] == [lst.count for lst in lists]
    assert s["outputs"] == sum(lst.count for lst in lists) + 5


def test_exact_cycles_no_bubbles():
    """No pauses, K >= 2: S*K*W*H + latency + 1 cycles from the first pixel to the last
    trailer — the segmenter never stalls the pipeline."""
    cfg = make_config(**SCENE_CFG)
    frames = make_frames("table1", cfg, 9, seed=3)
    sim = built(cfg)
    assert sim.latency == 14 + 3
    result = simulate(sim, frames, run_name="seg-exact", exact_cycles=True)
    assert_passed(result)
    assert result.cycles == 9 * 16 * 12 + 17 + 1


def test_scoreboard_names_the_segment_record_and_field():
    """The checker can fail: one flipped bit of one expected record fails the run and the
    report locates it."""
    cfg = make_config(**SCENE_CFG)
    frames = make_frames("two-targets", cfg, 9, seed=7)
    lists = expected_lists(cfg, frames)
    index = lists[0].count + 1 + 1               # segment 1, record 1
    assert lists[1].count >= 2
    result = simulate(built(cfg), frames, run_name="seg-corrupted",
                      corrupt_expected={"index": index, "xor": 1 << 7})     # col bit 0
    assert not result.passed
    assert result.summary["verdict"] == "mismatch"
    assert "segment 1, record 1, field col" in result.report


@pytest.mark.slow
def test_128x128_paper_count():
    """001's frame size and count (n = 33 of 16384, C = 66, 1024 bins): four segments of
    K = 4 of the two-target scene with gaps and back-pressure; the reduction in bits."""
    cfg = make_config(width=128, height=128, segment_frames=4)
    frames = make_frames("two-targets", cfg, 16, seed=51)
    result = simulate(built(cfg), frames, run_name="seg-128x128",
                      valid_pause=RANDOM(0.1, 52), ready_pause=RANDOM(0.3, 53))
    assert_passed(result)
    bits = bits_per_segment(cfg)
    assert result.summary["bits_image_per_segment"] == bits.image == 327680
