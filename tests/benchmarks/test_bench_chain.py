"""``benchmarks/bench_chain.py``: refusals are usage errors before any run; one run's report."""

from __future__ import annotations

import csv

import pytest

from helpers.benches import load_bench


def _bench():
    return load_bench("bench_chain")


@pytest.mark.parametrize("args, message", [
    (["--scenario", "straight"],
     "unknown scenario 'straight'; allowed: paper001-experiment-2, manoeuvring, crossing"),
    (["--seeds", "9-1"], "seeds A-B need A <= B, got '9-1'"),
    (["--seeds", "a-b"], "seeds must be A-B (integers 0 <= A <= B) or A, got 'a-b'"),
    (["--lists", "best"], "lists must be one of 'gateware', 'ideal', got 'best'"),
    (["--set", "confirm_hits"], "--set takes KEY=VALUE with a TOML value, got 'confirm_hits'"),
    (["--dp", "segment_frames=["], "--dp takes KEY=VALUE with a TOML value, got 'segment_frames=['"),
    (["--dp", "segment_frames=0"],
     "scenario 'paper001-experiment-2': segment_frames must be an integer in [1, 65535], got 0"),
    (["--false-alarm-rate", "0"],
     "[segmentation] false_alarm_rate must be in (0, 1], got 0.0"),
    (["--false-alarm-rate", "1e-5"],
     "false_alarm_rate 1e-05 keeps no candidate point of 16384 pixels; allowed: at least "
     "3.05176e-05 (n = 1)"),
    (["--false-alarm-rate", "x"], "argument --false-alarm-rate: invalid float value: 'x'"),
])
def test_refusals_are_usage_errors(args, message, capsys, monkeypatch):
    bench = _bench()
    monkeypatch.setattr(bench.e2e, "run_chain", lambda *a, **k: pytest.fail("ran after a refusal"))
    with pytest.raises(SystemExit) as exc:
        bench.main(args)
    assert exc.value.code == 2
    assert capsys.readouterr().err.splitlines()[-1].endswith(f"error: {message}")


def test_one_seed_prints_the_summary_and_writes_the_runs(tmp_path, capsys):
    bench = _bench()
    out = tmp_path / "runs.csv"
    bench.main(["--scenario", "crossing", "--seeds", "0", "--runs", str(out)])
    lines = capsys.readouterr().out.splitlines()
    assert lines[0] == "scenario crossing, seeds 0-0, ideal lists"
    assert lines[1] == "clean runs (all targets confirmed, no false track): 0/1 [0.00, 0.79]"
    rows = list(csv.reader(out.open()))
    assert rows == [["seed", "frames_until_output_1", "frames_until_output_2", "false_tracks",
                     "clean"], ["0", "30", "", "0", "0"]]


def test_a_variant_prints_its_chain(capsys):
    bench = _bench()
    bench.main(["--scenario", "crossing", "--seeds", "0", "--dp", "segment_frames=8",
                "--set", "confirm_hits=3"])
    lines = capsys.readouterr().out.splitlines()
    assert lines[0] == ("chain: [dp] {'segment_frames': 8}, [association] {'confirm_hits': 3}, "
                        "false_alarm_rate 0.002")
    assert lines[1] == "scenario crossing, seeds 0-0, ideal lists"


def test_another_false_alarm_rate_is_another_list_length(capsys):
    bench = _bench()
    bench.main(["--scenario", "crossing", "--seeds", "0", "--false-alarm-rate", "0.004"])
    lines = capsys.readouterr().out.splitlines()
    assert lines[0] == "chain: [dp] {'segment_frames': 6}, [association] {}, false_alarm_rate 0.004"
    assert lines[1] == "scenario crossing, seeds 0-0, ideal lists"
