"""``benchmarks/bench_synth.py``: ``--nextpnr-args`` is split into nextpnr's arguments and
refused, as a usage error before any run, when it sets what the flow sets."""

from __future__ import annotations

import pytest

from helpers.benches import load_bench


def _bench():
    return load_bench("bench_synth")


class _Ran(Exception):
    pass


@pytest.mark.parametrize("value, message", [
    ("--seed 4", "--nextpnr-args may not set --seed: set it with the bench's --seeds; "
                 "allowed: nextpnr's other options, e.g. --tmg-ripup"),
    ("--tmg-ripup --router router2",
     "--nextpnr-args may not set --router: set it with the bench's --router; allowed: "
     "nextpnr's other options, e.g. --tmg-ripup"),
    ("--freq=250", "--nextpnr-args may not set --freq: set it with the bench's --freq; "
                   "allowed: nextpnr's other options, e.g. --tmg-ripup"),
    ("--45k --tmg-ripup", "--nextpnr-args may not set --45k: set it with the bench's "
                          "--device; allowed: nextpnr's other options, e.g. --tmg-ripup"),
    ("-l other.log --tmg-ripup", "--nextpnr-args may not set -l: the flow writes its own "
                                 "files; allowed: nextpnr's other options, e.g. --tmg-ripup"),
    ("--placer-heap-critexp '4", "--nextpnr-args must split into words like a shell's: No "
                                 "closing quotation; got \"--placer-heap-critexp '4\""),
])
def test_refusals_are_usage_errors(value, message, capsys, monkeypatch):
    bench = _bench()
    monkeypatch.setattr(bench, "synthesize", lambda *a, **k: pytest.fail("ran after a refusal"))
    with pytest.raises(SystemExit) as exc:
        bench.main(["--families", "ecp5", "--cases", "tiny", f"--nextpnr-args={value}"])
    assert exc.value.code == 2
    assert capsys.readouterr().err.splitlines()[-1].endswith(f"error: {message}")


@pytest.mark.parametrize("argv, family, expected", [
    (["--speed", "7", "--router", "router2", "--nextpnr-args",
      "--tmg-ripup --placer-heap-timingweight 30"], "ecp5",
     ("--speed", "7", "--router", "router2", "--tmg-ripup", "--placer-heap-timingweight",
      "30")),
    (["--nextpnr-args=--tmg-ripup"], "ecp5", ("--tmg-ripup",)),
    (["--speed", "7", "--nextpnr-args=--placer sa"], "ice40", ("--placer", "sa")),
    ([], "ecp5", ()),
])
def test_the_arguments_reach_synthesize(argv, family, expected, monkeypatch, tmp_path):
    bench = _bench()
    seen = {}

    def synthesize(cfg, **kwargs):
        seen.update(kwargs)
        raise _Ran

    monkeypatch.setattr(bench, "synthesize", synthesize)
    with pytest.raises(_Ran):
        bench.main(["--families", family, "--cases", "tiny", "--workdir", str(tmp_path),
                    *argv])
    assert seen["nextpnr_args"] == expected
