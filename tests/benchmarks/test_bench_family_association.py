"""``benchmarks/bench_family_association.py --false-tracks``: refusals are usage errors
before any run, and the report's tables."""

from __future__ import annotations

import numpy as np
import pytest

from helpers.benches import load_bench


def _bench():
    return load_bench("bench_family_association")


@pytest.mark.parametrize("args, message", [
    (["--false-tracks"], "--false-tracks needs --alpha"),
    (["--false-tracks", "--alpha", "1.5"], "forgetting must be a finite real number in (0, 1], got 1.5"),
    (["--false-tracks", "--alpha", "0.7", "--seg-counts", "33,x"],
     "seg_counts must be comma-separated integers in [1, 128], got '33,x'"),
    (["--false-tracks", "--alpha", "0.7", "--rec-counts", "0"], "rec_counts[0] must be an integer in [1, 128], got 0"),
    (["--false-tracks", "--alpha", "0.7", "--seeds", "2", "--descent-seeds", "3"],
     "descent_seeds must be an integer in [0, seeds=2], got 3"),
    (["--false-tracks", "--alpha", "0.7", "--descent-lags", "0-6"], "lags[0] must be an integer in [1, 99], got 0"),
])
def test_refusals_are_usage_errors(args, message, capsys, monkeypatch):
    bench = _bench()
    monkeypatch.setattr(bench, "false_track_report", lambda *a, **k: pytest.fail("ran after a refusal"))
    with pytest.raises(SystemExit) as exc:
        bench.main(args)
    assert exc.value.code == 2
    assert capsys.readouterr().err.splitlines()[-1].endswith(f"error: {message}")


def test_arguments_reach_the_report(monkeypatch):
    bench = _bench()
    seen = []
    monkeypatch.setattr(bench, "false_track_report", lambda *a: seen.append(a))
    bench.main(["--false-tracks", "--alpha", "0.7", "--seeds", "4", "--first-seed", "2",
                "--seg-counts", "33,43", "--rec-counts", "26", "--descent-seeds", "1",
                "--descent-lags", "1-3,12"])
    assert seen == [(0.7, range(2, 6), [33, 43], [26], 1, (1, 2, 3, 12))]


@pytest.mark.parametrize("args, message", [
    (["--list-swaps"], "--list-swaps needs --alpha"),
    (["--list-swaps", "--alpha", "0"], "forgetting must be a finite real number in (0, 1], got 0.0"),
    (["--list-swaps", "--alpha", "0.7", "--seeds", "0"], "seeds must be an integer in [1, inf), got 0"),
    (["--list-swaps", "--alpha", "0.7", "--rec-counts", "26"],
     "--list-swaps crosses --seg-counts with --rec-counts: give as many of each, got 2 and 1"),
])
def test_list_swap_refusals_are_usage_errors(args, message, capsys, monkeypatch):
    bench = _bench()
    monkeypatch.setattr(bench, "list_swap_report", lambda *a, **k: pytest.fail("ran after a refusal"))
    with pytest.raises(SystemExit) as exc:
        bench.main(args)
    assert exc.value.code == 2
    assert capsys.readouterr().err.splitlines()[-1].endswith(f"error: {message}")


def test_list_swap_arguments_reach_the_report(monkeypatch):
    bench = _bench()
    seen = []
    monkeypatch.setattr(bench, "list_swap_report", lambda *a: seen.append(a))
    bench.main(["--list-swaps", "--alpha", "0.7", "--seeds", "3", "--first-seed", "5",
                "--rec-counts", "26,33", "--workers", "2"])
    assert seen == [(0.7, range(5, 8), [33, 43], [26, 33], 2, None)]


def test_list_swap_report_sums_seeds_and_pairs_by_density(monkeypatch, capsys):
    from dptbd.evaluation.family import list_swaps as lsw

    bench = _bench()
    pairs = np.arange(lsw.PAIR_TOP + 1)         # 0, 1, 2, ... pairs at distance 0, 1, 2, ...

    def task(alpha, seed, seg_counts, rec_counts):
        # false tracks: seg 33 -> 1 + seed, seg 43 -> 10, rec 26 -> 2, rec 33 -> 20 (per seed)
        false = {("seg", 33): 1 + seed, ("seg", 43): 10, ("rec", 26): 2, ("rec", 33): 20}
        out = {}
        for key in [("seg", n) for n in seg_counts] + [("rec", n) for n in rec_counts]:
            row = {how: lsw.Seeding(false[key] * (2 if how == "uniform" else 1), (100, 10, 3, 1, 0))
                   for how in lsw.SWAPS if how != "alternate-seed" or key[0] == "rec"}
            geo = [(25 * 4, 4, pairs, 0.04 * 4), (25 * 4, 4, pairs, 0.05 * 4)]
            out[key] = (row, geo)
        return out

    monkeypatch.setattr(lsw, "seed_swaps", task)
    bench.list_swap_report(0.7, range(0, 2), [33, 43], [33, 26], 1, None)
    out = capsys.readouterr().out
    # seg 33: 1 + 2 = 3 false tracks over seeds 0 and 1; uniform twice that
    assert "| segments K=6 | 33 | 25.0 | 3 | 6 | 3 | 3 | 3 | 3 | 3 | - |" in out
    assert "| recursive alpha=0.7 | 33 | 25.0 | 40 | 80 | 40 | 40 | 40 | 40 | 40 | 40 |" in out
    assert "* alternate-seed:" not in out      # segments have no such row
    # rec 26 pairs with seg 33, rec 33 with seg 43; pooled (4 + 40) / (3 + 20)
    assert "* none: rec n=26 / seg n=33 4/3 = 1.33" in out
    assert "rec n=33 / seg n=43 40/20 = 2.00" in out and "pooled 44/23 = 1.91" in out
    assert "* segments K=6, n = 43: uniform / lists 40/20 = 2.00" in out
    assert "* recursive alpha=0.7, n = 26: alternate-seed / lists 4/4 = 1.00" in out
    assert "* segments K=6, pooled over n: uniform / lists 46/23 = 2.00" in out
    assert "* recursive alpha=0.7, pooled over n: alternate-seed / lists 44/44 = 1.00" in out
    assert "| segments K=6 | 33 | 200 (200) | 20 (20) (0.100; 0.100) |" in out
    # per list: 2 seeds x 2 pairs at distance 2 over 8 lists = 0.5
    assert "| segments K=6 | 33 | 0.50 / 0.50 | 0.75 / 0.75 |" in out
    assert "| 2.00 / 2.00 | 0.0400 / 0.0500 |" in out
