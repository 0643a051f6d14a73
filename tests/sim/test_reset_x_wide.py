"""4-state (Icarus) runs of ``dptbd_dp`` at P = 2 and 4 pixels per clock around reset
(:mod:`dptbd.sim.reset_x`): a beat offered in every cycle, in reset and in the first cycle
after it; ``ready`` 0 during reset and in that cycle, no X on any output, no deadlock,
every state after the reset bit-exact (the P = 1 runs are ``test_reset_x.py``); the ECP5
builds with the line buffer in DP16KDs (what the P > 1 cores build in them) on the 4-state
DP16KD model."""

from __future__ import annotations

import shutil

import pytest

from dptbd.config import DPConfig
from dptbd.hw.flow.family import ECP5
from dptbd.sim.cell_models import cell_instances
from dptbd.sim.reset_x import TOPS, run_reset_x_check

pytestmark = pytest.mark.skipif(shutil.which("iverilog") is None, reason="needs Icarus Verilog")

#: (first reset cycle, reset cycles), as test_reset_x.py's
RESETS = [(0, 4), (0, 1), (1, 1), (2, 3), (5, 2)]


@pytest.mark.parametrize("p, radius", [(2, 2), (4, 1)])
def test_reset_sweep_at_p(p, radius):
    cfg = DPConfig(width=8 * p, height=9, segment_frames=2, radius=radius,
                   pixels_per_clock=p).build_config()
    results = run_reset_x_check(cfg, 4, top="dp", resets=RESETS, seed=p)
    assert [r.ok for r in results] == [True] * len(RESETS), \
        "\n".join(r.report for r in results)
    assert {r.words for r in results} == {4 * cfg.frame_beats}     # beats after the reset


def test_a_wrong_state_is_reported():
    """The beat comparison can fail: the model's frames differ from the ones streamed."""
    import numpy as np
    from dptbd.sim import reset_x

    cfg = DPConfig(width=8, height=9, segment_frames=2, pixels_per_clock=2).build_config()
    frames = np.random.default_rng(1).integers(0, 256, size=(2, 9, 8))
    words = [0] * cfg.frame_beats * 2
    problems = reset_x._compare(cfg, frames, "dp", words, [])
    assert len(problems) == 1 and problems[0].startswith("beat 0: got [")
    short = reset_x._compare(cfg, frames, "dp", words[:-1], [])
    assert short[0] == f"{2 * cfg.frame_beats - 1} states beats, the model gives 72"


@pytest.mark.parametrize("top, p, cells", [
    ("dp", 2, {"dptbd_dp.core.line_buffer": 3}),
    ("axi", 2, {"dptbd_axi.core.dp.core.line_buffer": 3,
                **{f"dptbd_axi.core.segmenter.histogram.bank_{k}": 1
                   for k in range(2)}}),
    pytest.param("dp", 4, {"dptbd_dp.core.line_buffer": 6}, marks=pytest.mark.slow),
])
def test_the_ecp5_builds_with_the_line_buffer_in_dp16kds(tmp_path, top, p, cells):
    """``Family.options_for`` with ``line_buffer_style="dp16kd"`` (the family's choice from
    512 wide) at P = 2 and 4 (``-m slow``), and in ``dptbd_axi`` the segmenter's histogram
    banks in DP16KDs (``histogram_style="dp16kd"``): X-free, ``ready`` low where promised,
    every word exact."""
    cfg = DPConfig(width=8 * p, height=9, segment_frames=2, candidate_count=4,
                   pixels_per_clock=p).build_config()
    options = {**ECP5.options_for(cfg), "line_buffer_style": "dp16kd"}
    resets = [(0, 4), (1, 1), (5, 2)]
    results = run_reset_x_check(cfg, 4, top=top, resets=resets, seed=p, core_options=options,
                                directory=tmp_path)
    assert [r.ok for r in results] == [True] * len(resets), \
        "\n".join(r.report for r in results)
    text = (tmp_path / f"{TOPS[top]['module']}.v").read_text()
    assert cell_instances(text, "DP16KD") == cells
    words = {r.words for r in results}
    if top == "dp":
        assert words == {4 * cfg.frame_beats}                      # beats after the reset
    else:
        assert len(words) == 1 and words.pop() > 2                 # lists with records
