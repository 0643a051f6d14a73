"""``benchmarks/bench_axi_top_store.py --synth``: the seeds, the jobs and the time limit reach
the flow; each seed's critical path is printed, and the median only when every seed routed."""

from __future__ import annotations

import sys

import pytest

from dptbd.config import DPConfig
from dptbd.hw.flow import synth as flow
from dptbd.hw.flow import to_verilog
from dptbd.hw.flow.nextpnr import CriticalPath
from dptbd.hw.flow.synth import CellCounts, PnrRun, SynthResult
from helpers.benches import load_bench


def _run(seed, fmax, *, timed_out=False):
    path = None if fmax is None else CriticalPath(start=f"a{seed}", end="b", logic_ns=2.0,
                                                  routing_ns=3.5, steps=9)
    return PnrRun(seed=seed, fits=fmax is not None, fmax_mhz=fmax, target_mhz=200.0,
                  utilisation={"TRELLIS_COMB": (10, 24288)}, seconds=60.0,
                  error="did not route in 900 s" if timed_out else None,
                  timed_out=timed_out, critical_path=path)


@pytest.mark.parametrize("runs, median", [
    ((_run(1, 156.1), _run(2, 147.7), _run(3, 145.4)), "Fmax median: 147.7 MHz"),
    ((_run(1, 156.1), _run(2, None, timed_out=True), _run(3, 145.4)),
     "Fmax median: — (not every seed routed)"),
])
def test_synth_prints_every_seeds_path_and_the_median(runs, median, capsys, monkeypatch):
    bench = load_bench("bench_axi_top_store")
    asked = {}

    def synthesize(cfg, **kwargs):
        asked.update(kwargs)
        return SynthResult(variant="axi-store", device="25k", package="CABGA256",
                           target_mhz=200.0, params={}, cells=CellCounts({"LUT4": 5}),
                           family="ecp5", runs=runs, yosys_seconds=1.0, verilog_seconds=1.0)

    monkeypatch.setattr(flow, "synthesize", synthesize)
    monkeypatch.setattr(to_verilog, "to_verilog", lambda design, name: "")
    cfg = DPConfig(width=64, height=16).build_config()
    bench.synth(cfg, cfg.axi_store(data_bits=64, burst_beats=16, outstanding=4), "ecp5",
                seeds=[1, 2, 3], jobs=2, timeout=900)
    assert (asked["seeds"], asked["jobs"], asked["nextpnr_timeout"]) == ((1, 2, 3), 2, 900)
    lines = capsys.readouterr().out.splitlines()
    paths = [line for line in lines if line.startswith("  critical path: ")]
    assert paths == [f"  critical path: a{r.seed} -> b: 5.50 ns (2.00 logic, 3.50 routing)"
                     for r in runs if r.fmax_mhz is not None]
    assert lines[-1] == median


def test_the_options_reach_synth(monkeypatch):
    bench = load_bench("bench_axi_top_store")
    got = {}
    monkeypatch.setattr(bench, "synth", lambda cfg, store, family, **kw: got.update(
        cfg=cfg, family=family, **kw))
    monkeypatch.setattr(sys, "argv", ["bench_axi_top_store.py", "--synth", "ecp5", "--width",
                                      "64", "--height", "16", "--pixels-per-clock", "2",
                                      "--seeds", "4", "5", "--jobs", "2", "--pnr-timeout", "60"])
    bench.main()
    assert (got["cfg"].pixels_per_clock, got["family"], got["seeds"], got["jobs"],
            got["timeout"]) == (2, "ecp5", [4, 5], 2, 60.0)
