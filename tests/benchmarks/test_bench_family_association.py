"""``benchmarks/bench_family_association.py --false-tracks``: refusals are usage errors
before any run, and the report's tables."""

from __future__ import annotations

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
