"""``benchmarks/bench_family_detection.py``: every refusal is a usage error before any run."""

from __future__ import annotations


import pytest

from helpers.benches import load_bench


def _bench():
    return load_bench("bench_family_detection")


@pytest.mark.parametrize("args, message", [
    (["--k", "6,x"], "k must be comma-separated integers in [1, 100], got '6,x'"),
    (["--k", "0"], "segment_frames must be an integer in [1, 100], got 0"),
    (["--frame-ranges", "7-15,64-100"], "frame range 1 last must be an integer in [64, 99], got 100"),
    (["--wake-lags", "0-40"], "lags[0] must be an integer in [1, 99], got 0"),
    (["--alpha", "1.5"], "forgetting must be a finite real number in (0, 1], got 1.5"),
])
def test_refusals_are_usage_errors(args, message, capsys, monkeypatch):
    bench = _bench()
    monkeypatch.setattr(bench, "report", lambda *a, **k: pytest.fail("ran after a refusal"))
    with pytest.raises(SystemExit) as exc:
        bench.main(["--alpha", "0.97"] + args)
    assert exc.value.code == 2
    assert capsys.readouterr().err.splitlines()[-1].endswith(f"error: {message}")
