"""4-state (Icarus) check: an external state store's power-up contents never reach an output.

``DPCore``'s Verilog with a one-cycle SRAM model that powers up uninitialised (X) or with
``$random`` bits (direction codes above M included), frames streamed with valid and ready
held high: no output bit of the module may be X/Z in any cycle and every ``states`` word
must equal the golden model (:func:`dptbd.sim.x_store.run_x_store_check`,
``docs/gateware.md``, DPCore's state-store port).

Before the fix (weight code gated by the edge flag, LUT address clamped to M) the second
frame's words carried X: read-ahead garbage of the first frame sits in the window cells
whose predecessor is outside the image, and 4-state arithmetic carried it through the
multiplier into the max tree. :func:`test_the_check_sees_x_without_the_edge_gate` keeps
that failure reproducible.
"""

from __future__ import annotations

import re
import shutil

import pytest
from amaranth.hdl import Module

from dptbd.config import DPConfig
from dptbd.hw.dp_core import core as dp_core
from dptbd.hw.weighted_candidate import WeightedCandidate
from dptbd.sim.x_store import run_x_store_check

pytestmark = pytest.mark.skipif(shutil.which("iverilog") is None, reason="needs Icarus Verilog")

CONFIGS = {
    "16x12-r1-k3": dict(width=16, height=12, segment_frames=3),
    "16x12-r2-k2-half_up-f6": dict(width=16, height=12, segment_frames=2, radius=2,
                                   rounding="half_up", weight_frac_bits=6),
}


@pytest.mark.parametrize("init, seed", [("x", 1), ("random", 1), ("random", 2)])
@pytest.mark.parametrize("name", list(CONFIGS))
def test_no_x_and_model_exact_with_garbage_store(name, init, seed):
    cfg = DPConfig(**CONFIGS[name])
    n_frames = 2 * cfg.segment_frames + 1          # >= 3 frames, a second segment and more
    result = run_x_store_check(cfg, n_frames, init=init, seed=seed)
    assert result.ok, result.report
    assert result.words == n_frames * cfg.width * cfg.height
    if init == "random":   # the garbage did hold out-of-range direction codes
        out_of_range = re.search(r"(\d+) of \d+ words with d > M", result.report)
        assert out_of_range and int(out_of_range.group(1)) > 0, result.report


class _UngatedCandidate(WeightedCandidate):
    """The multiplier before the fix: the edge flag is ignored (the code is never gated)."""

    def elaborate(self, platform):
        m = Module()
        m.submodules.inner = inner = WeightedCandidate(self._cfg)
        m.d.comb += [inner.energy.eq(self.energy), inner.code.eq(self.code),
                     inner.inside.eq(1), self.weighted.eq(inner.weighted)]
        return m


def test_the_check_sees_x_without_the_edge_gate(monkeypatch):
    """Self-check: without the gate, the second frame's words carry X and the check fails."""
    monkeypatch.setattr(dp_core, "WeightedCandidate", _UngatedCandidate)
    cfg = DPConfig(**CONFIGS["16x12-r1-k3"])
    result = run_x_store_check(cfg, 3, init="x", seed=1)
    assert not result.ok
    first_bad = result.report.splitlines()[1:]
    assert any("(frame 1, row 0, col 0): X/Z in states__payload" in line
               for line in first_bad), result.report
