"""``benchmarks/bench_synth.py``: ``--nextpnr-args`` is split into nextpnr's arguments and
refused, as a usage error before any run, when it sets what the flow sets; the time limits
reach the flow, and a seed stopped at nextpnr's is printed so, with no median."""

from __future__ import annotations

import pytest

from dptbd.hw.flow.synth import CellCounts, PnrRun, SynthResult
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
    ("--pnr-timeout=0", "--pnr-timeout must be a number of seconds in (0, inf), got 0"),
    ("--yosys-args=-nowidelut -top x", "--yosys-args may not set -top: the flow names the top "
                                       "module; allowed: the synthesis command's other "
                                       "options, e.g. -nowidelut"),
    ("--yosys-args=-json n.json", "--yosys-args may not set -json: the flow writes its own "
                                  "files; allowed: the synthesis command's other options, "
                                  "e.g. -nowidelut"),
    ("--yosys-args=-noflatten", "--yosys-args may not set -noflatten: the flow's per-block "
                                "pass has it (the bench's --no-breakdown drops that pass); "
                                "allowed: the synthesis command's other options, e.g. "
                                "-nowidelut"),
    ("--yosys-args=-run begin:coarse", "--yosys-args may not set -run: the flow runs the "
                                       "whole command; allowed: the synthesis command's "
                                       "other options, e.g. -nowidelut"),
    ("--yosys-args=-abc9 '-W", "--yosys-args must split into words like a shell's: No "
                               "closing quotation; got \"-abc9 '-W\""),
    ("--timeout=-5", "--timeout must be a number of seconds in (0, inf), got -5"),
])
def test_refusals_are_usage_errors(value, message, capsys, monkeypatch):
    bench = _bench()
    monkeypatch.setattr(bench, "synthesize", lambda *a, **k: pytest.fail("ran after a refusal"))
    with pytest.raises(SystemExit) as exc:
        bench.main(["--families", "ecp5", "--cases", "tiny",
                    *([value] if value.startswith(("--pnr-timeout", "--timeout", "--yosys"))
                      else [f"--nextpnr-args={value}"])])
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
    seen = _synthesize_kwargs(monkeypatch, tmp_path, "--families", family, *argv)
    assert seen["nextpnr_args"] == expected
    assert (seen["yosys_timeout"], seen["nextpnr_timeout"]) == (3600, _bench().PNR_TIMEOUT)


def _synthesize_kwargs(monkeypatch, tmp_path, *argv):
    """The keyword arguments the bench's ``main(argv)`` passes to ``synthesize`` for the
    tiny case (ECP5 unless ``argv`` names the families)."""
    bench = _bench()
    seen = {}

    def synthesize(cfg, **kwargs):
        seen.update(kwargs)
        raise _Ran

    monkeypatch.setattr(bench, "synthesize", synthesize)
    families = () if "--families" in argv else ("--families", "ecp5")
    with pytest.raises(_Ran):
        bench.main([*families, "--cases", "tiny", "--workdir", str(tmp_path), *argv])
    return seen


@pytest.mark.parametrize("argv, expected", [
    ([], None),                                   # the family's (Family.synth_args)
    (["--yosys-args="], ()),                      # none
    (["--yosys-args", "-nowidelut -dff"], ("-nowidelut", "-dff")),
    (["--yosys-args=-cmp2softlogic"], ("-cmp2softlogic",)),
])
def test_the_yosys_arguments_reach_synthesize(argv, expected, monkeypatch, tmp_path):
    assert _synthesize_kwargs(monkeypatch, tmp_path, *argv)["yosys_args"] == expected


def test_the_time_limits_reach_synthesize(monkeypatch, tmp_path):
    seen = _synthesize_kwargs(monkeypatch, tmp_path, "--timeout", "600", "--pnr-timeout", "1200")
    assert (seen["yosys_timeout"], seen["nextpnr_timeout"]) == (600, 1200)


def test_a_stopped_seed_is_printed_with_no_median(monkeypatch, tmp_path, capsys):
    bench = _bench()

    def run(seed, fmax, timed_out=False):
        return PnrRun(seed=seed, fits=fmax is not None, fmax_mhz=fmax, target_mhz=200.0,
                      utilisation={"TRELLIS_COMB": (10, 24288)}, seconds=60.0,
                      error="did not route in 900 s" if timed_out else None,
                      timed_out=timed_out)

    def synthesize(cfg, **kwargs):
        return SynthResult(variant="core", device="25k", package="CABGA256",
                           target_mhz=200.0, params=dict(cfg.__dict__, core_options={}),
                           cells=CellCounts({"LUT4": 5}), family="ecp5",
                           runs=(run(1, 194.2), run(2, None, timed_out=True), run(3, 189.1)),
                           yosys_seconds=1.0, verilog_seconds=1.0)

    monkeypatch.setattr(bench, "synthesize", synthesize)
    assert bench.main(["--families", "ecp5", "--cases", "tiny", "--workdir", str(tmp_path),
                       "--no-breakdown"]) == 0
    out, err = capsys.readouterr()
    row = next(line for line in out.splitlines() if line.startswith("| tiny |"))
    assert row.endswith("| yes | 1: 194.2, 2: did not route in 900 s, 3: 189.1 | "
                        "— (not every seed routed) | — |")
    assert "s); seed 2 did not route in 900 s; fits: True\n" in err
