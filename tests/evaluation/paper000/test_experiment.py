"""``dptbd.evaluation.paper000.experiment``: paper 000's cases and gain curve on the gateware equal
the same job on the golden model exactly; a corrupted RTL state is located; refusals.

The RTL tests need Verilator (skipped otherwise); a 64 x 64, radius-2 build compiles in a
few seconds and is cached.
"""

from __future__ import annotations

import dataclasses
import shutil

import numpy as np
import pytest

from dptbd.errors import ConfigError
from dptbd.evaluation.detectors import paper000
from dptbd.evaluation.detectors._checks import DetectorError
from dptbd.evaluation.paper000.experiment import GAIN_DPS, Paper000Spec, run_paper000
from dptbd.evaluation.paper000.variants import fixed_variant

needs_verilator = pytest.mark.skipif(shutil.which("verilator") is None,
                                     reason="needs Verilator (scripts/setup.sh)")

#: Paper 001's datapath (eq (15)) and a family configuration (merit and penalty LUTs, eqs
#: (19)-(23)) on a few 4-frame scenes; every variant on whole scenes: the slow test below.
TINY = dict(cases=("5.1 eq (15)", "5.2 6 dB"), seeds=3, gain=("DP eq (15)",),
            gain_snrs_db=(6.0, 9.0), gain_trials=4, noise_trials=3, frames=4, chunk=2)


def _same(a, b) -> None:
    if isinstance(a, dict):
        assert a.keys() == b.keys()
        for k in a:
            _same(a[k], b[k])
    else:
        assert np.array_equal(a, b), (a, b)


@needs_verilator
def test_the_job_on_the_rtl_equals_the_job_on_the_golden_model_exactly():
    rtl = run_paper000(Paper000Spec(engine="rtl", **TINY), workers=1)
    model = run_paper000(Paper000Spec(engine="model", **TINY), workers=1)
    _same(rtl.cases, model.cases)
    _same(rtl.gain, model.gain)
    assert model.rtl == {}
    # every state of every frame compared: case 3 seeds, gain (3 noise + 2 x 4 target) scenes
    assert rtl.rtl["5.1 eq (15)"].state_words == 3 * 4 * 64 * 64
    assert rtl.rtl["5.2 6 dB"].state_words == 3 * 4 * 64 * 64
    assert rtl.rtl["DP eq (15)"].state_words == (3 + 2 * 4) * 4 * 64 * 64
    assert rtl.rtl["DP eq (15)"].pixel_updates == (3 + 2 * 4) * 4 * 64 * 64


@needs_verilator
def test_a_corrupted_rtl_state_is_reported_by_variant_seed_frame_row_column_and_field(monkeypatch):
    from dptbd.hw.layouts import state_layout
    from dptbd.sim import verilator
    from dptbd.sim.rtl import trials as rtl_trials

    real = verilator.run
    spec = Paper000Spec(engine="rtl", **dict(TINY, cases=("5.1 eq (15)",), gain=(), seeds=2))
    offset = state_layout(fixed_variant(paper000.CASES[0], frames=4).cfg)["energy"].offset
    index = (1 * 4 + 2) * 64 * 64 + 7 * 64 + 9   # trial 1, frame 2, row 7, col 9

    def run(sim, words, **kw):
        raw = real(sim, words, **kw)
        out = raw.out_words.copy()
        out[index] ^= np.uint64(1 << offset)
        return dataclasses.replace(raw, out_words=out)

    monkeypatch.setattr(verilator, "run", run)
    with pytest.raises(rtl_trials.RTLMismatchError, match=(
            r"^RTL states differ from the golden model: variant '5\.1 eq \(15\)' \(trial = seed\): "
            r"trial 1, segment 0, frame 2 of the segment \(frame 2 of the trial\), row 7, "
            r"col 9, field energy: expected (\d+), got (?!\1)\d+ \(output word "
            rf"{index} of the run; differing fields \['energy'\]\)$")):
        run_paper000(spec, workers=1)


def test_a_variant_the_gateware_cannot_build_is_refused_before_any_build(monkeypatch):
    from dptbd.hw import schedule
    from dptbd.sim import verilator

    def refuse(cfg):
        if not cfg.is_paper001_datapath:
            raise ConfigError("cannot")
        return None

    monkeypatch.setattr(schedule, "check_supported", refuse)
    monkeypatch.setattr(verilator, "build", lambda *a, **k: pytest.fail("built"))
    spec = Paper000Spec(engine="rtl", **dict(TINY, cases=("5.1 eq (15)", "5.1 eq (24)")))
    with pytest.raises(ConfigError, match=r"^RTL in the loop: configuration '5\.1 eq \(24\)' "
                                          r"cannot run on the gateware: cannot$"):
        run_paper000(spec, workers=1)


@pytest.mark.parametrize("fields, message", [
    (dict(engine="fpga"), r"^engine must be one of \('model', 'rtl'\), got 'fpga'$"),
    (dict(cases=("5.3",)), r"^cases must be among 5\.1 eq \(15\), 5\.1 eq \(24\), 5\.2 6 dB, "
                           r"5\.2 3 dB, got '5\.3'$"),
    (dict(gain=("DP",)), r"^gain must be among DP eq \(15\), DP eq \(24\), DP eqs \(19\)-\(23\), "
                         r"got 'DP'$"),
    (dict(cases=(), gain=()), r"^cases and gain are both empty: nothing to run$"),
    (dict(gain_snrs_db=(3.0, 3.0)), r"^gain_snrs_db must be a strictly increasing non-empty "
                                    r"list, got \[3\.0, 3\.0\]$"),
    (dict(frames=1), r"^frames must be an integer in \[2, 64\], got 1$"),
    (dict(seeds=0), r"^seeds must be an integer in \[1, 100000\], got 0$"),
])
def test_bad_specs_are_refused_by_name(fields, message):
    with pytest.raises(DetectorError, match=message):
        Paper000Spec(**fields)


def test_the_float_side_is_the_float_run_of_docs_section_1_4():
    spec = Paper000Spec(engine="model", cases=("5.1 eq (24)", "5.2 3 dB"), seeds=2, gain=())
    res = run_paper000(spec, workers=1)
    for case in paper000.CASES[1::2]:
        ref = paper000.run_case(case, range(2))
        assert np.array_equal(res.cases[case.label]["float"]["target"], ref.target)
        assert np.array_equal(res.cases[case.label]["float"]["noise_max"], ref.noise_max)
        assert np.array_equal(res.cases[case.label]["float"]["false_tracks@" + format(
            case.thresholds[0], "g")], ref.false_tracks[case.thresholds[0]])


def test_gain_float_detections_follow_snr_gain_on_the_same_scenes():
    spec = Paper000Spec(engine="model", cases=(), gain=GAIN_DPS[1:2], gain_snrs_db=(6.0, 8.0),
                        gain_trials=6, noise_trials=4, chunk=4)
    res = run_paper000(spec, workers=1)
    ref = paper000.snr_gain((6.0, 8.0), trials=6, noise_trials=4, chunk=4,
                            detectors=("DP eq (24)",))
    assert list(res.gain["DP eq (24)"]["float"].sum(axis=1)) == list(ref.detections["DP eq (24)"])


@pytest.mark.slow
@needs_verilator
def test_whole_000_scenes_of_every_variant_on_verilator_equal_the_golden_model_bit_for_bit():
    spec = Paper000Spec(engine="rtl", seeds=1, gain=GAIN_DPS, gain_snrs_db=(6.0,),
                        gain_trials=1, noise_trials=1)
    rtl = run_paper000(spec, workers=1)
    model = run_paper000(dataclasses.replace(spec, engine="model"), workers=1)
    _same(rtl.cases, model.cases)
    _same(rtl.gain, model.gain)
    for case in paper000.CASES:
        assert rtl.rtl[case.label].state_words == 20 * 64 * 64
    for dp in GAIN_DPS:
        assert rtl.rtl[dp].state_words == 2 * 20 * 64 * 64
