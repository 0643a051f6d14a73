"""dptbd.evaluation.run.job: the scenario with run's options, the prepared input, the job's
result and what it logs, every refusal (whole message)."""

import numpy as np
import pytest

from dptbd.evaluation.run import job
from dptbd.evaluation.run.job import effective_scenario, parse_target_option, prepare, run_job
from dptbd.evaluation.run.rtl import RtlCheck
from dptbd.evaluation.run.scenario import DEFAULT_NAME, ScenarioError, parse_scenario
from helpers.refusals import whole

SMALL = {"name": "small",
         "scene": {"size": [32, 32], "frames": 24, "snr": 5.0, "seed": 3,
                   "targets": [{"start": [6.0, 6.0], "velocity": [0.8, 0.6]}]},
         "segmentation": {"false_alarm_rate": 0.005}}


@pytest.fixture(scope="module")
def small():
    sc = parse_scenario(SMALL)
    sc.check()
    return sc


@pytest.fixture(scope="module")
def small_result(small):
    lines = []
    return run_job(small, log=lines.append), lines


def test_effective_scenario_applies_the_options():
    sc = effective_scenario(seed=5, snr=3.0, targets=["20,4,0.2,0.9", "1,2,0,0,7"],
                            segment_frames=4, lists="ideal")
    assert sc.name == DEFAULT_NAME and (sc.seed, sc.snr, sc.lists) == (5, 3.0, "ideal")
    assert [t.start for t in sc.targets] == [(20.0, 4.0), (1.0, 2.0)]
    assert [t.snr for t in sc.targets] == [None, 7.0]
    assert sc.dp["segment_frames"] == 4 and "segment_stride" not in sc.dp
    # an --snr alone applies to every target of the scenario
    assert all(t.snr is None for t in effective_scenario(snr=3.0).targets)
    assert effective_scenario(segment_stride=3).dp["segment_stride"] == 3


def test_recorded_data_names_the_run(tmp_path):
    sc = effective_scenario(input_path=tmp_path / "clip.npz", npz_key="frames")
    assert sc.name == "clip.npz" and not sc.simulated and sc.input_key == "frames"


@pytest.mark.parametrize("options, message", [
    (dict(npz_key="x"), "--npz-key needs --input (or [input] in the scenario file)"),
    (dict(input_path="a.npy", seed=1),
     "--seed applies to a simulated scene, not to recorded data (--input / [input])"),
    (dict(input_path="a.npy", snr=1.0, targets=["1,2,3,4"]),
     "--snr, --target apply to a simulated scene, not to recorded data (--input / [input])"),
    (dict(seed=-1), "--seed must be an integer in [0, inf), got -1"),
    (dict(targets=["1,2,3"]),
     "--target '1,2,3': expected ROW,COL,VROW,VCOL or ROW,COL,VROW,VCOL,SNR (numbers)"),
    (dict(targets=["1,2,x,4"]),
     "--target '1,2,x,4': expected ROW,COL,VROW,VCOL or ROW,COL,VROW,VCOL,SNR (numbers)"),
])
def test_effective_scenario_refusals(options, message):
    with pytest.raises(ScenarioError, match=whole(message)):
        effective_scenario(**options)


def test_parse_target_option():
    t = parse_target_option("1.5,2,-0.5,0.25,3")
    assert (t.start, t.velocity, t.snr) == ((1.5, 2.0), (-0.5, 0.25), 3.0)
    assert parse_target_option("1,2,3,4").snr is None


def test_prepare_loads_quantises_and_configures(small):
    inp = prepare(small)
    assert inp.frames.shape == (24, 32, 32) and inp.frames.dtype.kind == "u"
    assert inp.frames.max() < 1 << inp.input_bits and inp.input_bits == small.adc_bits
    assert len(inp.truth) == len(inp.targets) == 1 and inp.report_frame == 12
    assert inp.count == 5 and inp.cfg.n_candidates == 10     # n = 0.5 % of 1024; headroom 2
    assert prepare(small, headroom=1.0).cfg.n_candidates == 5
    assert inp.shift_from.startswith("calibrated on the largest pixel")
    assert inp.describe()[0] == ("dptbd run: small: simulated 32x32, 24 frames, SNR 5, "
                                 "1 target(s), seed 3; 12-bit ADC at gain 16")


def test_prepare_refusals(small, tmp_path):
    short = tmp_path / "short.npy"
    np.save(short, np.zeros((3, 16, 16), np.uint8))
    with pytest.raises(ValueError, match=whole(
            "the sequence has 3 frame(s), shorter than one segment (segment_frames K = 6): "
            "nothing to accumulate")):
        prepare(effective_scenario(input_path=short))
    rare = small.replace(false_alarm_rate=1e-4)
    with pytest.raises(ValueError, match=whole(
            "false_alarm_rate 0.0001 of 1024 pixels keeps no candidate point; raise it")):
        prepare(rare)


def test_run_job_result_and_log(small_result):
    result, lines = small_result
    assert lines[0].startswith("dptbd run: small: simulated 32x32")
    assert lines[1].startswith("  FPGA stage: bit-accurate golden model, K = 6")
    assert lines[2].startswith("  segmentation: gateware lists")
    assert lines[3].startswith("  FPGA -> DSP: ") and lines[4].startswith("  DSP stage: ")
    assert len(lines) == 5 and result.rtl is None
    assert [r["target"] for r in result.rows] == [1]
    assert len(result.tracks) == len(result.pipeline.tracks)
    assert result.table_text.startswith("| target | start |")
    assert result.frames is result.input.frames and result.cfg is result.input.cfg
    # the effective scenario records the resolved association parameters
    assert result.scenario.association["capacity"] == result.input.assoc.capacity


def test_run_job_with_rtl_runs_the_check_and_reports_it(small, monkeypatch):
    calls = []

    def fake_check(frames, cfg, check, design, log):
        calls.append((frames.shape, check, design))
        log("  RTL: (checked)")
        return {"summary": "RTL (dptbd_seg) checked"}

    monkeypatch.setattr(job, "check_rtl", fake_check)
    lines = []
    result = run_job(small, rtl=RtlCheck(frames=12), log=lines.append)
    assert calls == [((24, 32, 32), RtlCheck(frames=12), "segmenter")]
    assert lines[3] == "  RTL: (checked)"
    assert result.table_text.endswith("\n\nRTL (dptbd_seg) checked")
    run_job(small.replace(lists="ideal"), rtl=RtlCheck())
    assert calls[-1][2] == "dp"
