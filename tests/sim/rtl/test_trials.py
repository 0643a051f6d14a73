"""RTL in the loop (``dptbd.sim.rtl.trials``): ``compare --rtl`` and ``table1 --rtl`` give the
golden model's numbers, a corrupted RTL word is caught and located, unsupported
configurations are refused up front.

Needs Verilator (skipped otherwise). Builds are cached (``~/.cache/dptbd/verilator``): the
first run compiles a few small executables (~7 s each), later runs take seconds.
"""

from __future__ import annotations

import dataclasses
import json
import re
import shutil

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.errors import ConfigError
from dptbd.hw.layouts import state_layout
from dptbd.sim import verilator
from dptbd.sim.rtl import trials as rtl_trials
from helpers.compare_spec import small_spec, spec_toml

pytestmark = pytest.mark.skipif(shutil.which("verilator") is None,
                                reason="needs Verilator (scripts/setup.sh)")

SMALL = DPConfig(width=16, height=16, segment_frames=4, input_bits=6, energy_bits=8)


def _frames(n_trials=3, n_frames=10, seed=1):
    rng = np.random.default_rng(seed)
    return rng.integers(0, 64, size=(n_trials, n_frames, 16, 16)).astype(np.uint16)


def test_expected_words_are_the_reference_models_frame_by_frame():
    from dptbd.sim.scoreboard import expected_words

    segments, n_seg = rtl_trials._segments_view(SMALL, _frames())
    assert n_seg == 2 and segments.shape == (6, 4, 16, 16)
    got = rtl_trials.expected_state_words(SMALL, segments)
    assert np.array_equal(got, expected_words(SMALL, segments.reshape(-1, 16, 16)).ravel())


def test_accumulate_trials_equals_the_model_and_counts_what_it_checked():
    from dptbd.model.fast import run_fixed_fast

    frames = _frames()
    res = rtl_trials.accumulate_trials(SMALL, frames)
    ref = run_fixed_fast(frames, SMALL)
    assert res.energy.dtype == ref.energy.dtype and res.direction.dtype == ref.direction.dtype
    assert np.array_equal(res.energy, ref.energy) and np.array_equal(res.direction, ref.direction)
    assert np.array_equal(res.end_frames, ref.end_frames)
    t = res.tally
    # 3 trials x 2 whole segments x 4 frames (the 2 frames after the last segment are not sent)
    assert t.pixel_updates == t.state_words == t.segmenter_pixels == 3 * 2 * 4 * 256
    assert t.lists == 6 and t.runs == 2 and t.list_words == t.records + t.lists


def _run_job(tmp_path, name, **options):
    """The compare job (the library call behind ``dptbd compare``) on the small spec: its
    folder and its outcome (text, ``run_compare``'s result, workers)."""
    from dptbd.evaluation.compare import compare_job

    out = tmp_path / name
    return out, compare_job(small_spec(), out, progress=False, **options)


def test_small_sweep_gives_identical_tables_on_the_model_the_rtl_and_a_cluster(tmp_path):
    """The model and ``compare --rtl`` on one worker: the same tables, counts trial by trial
    and printed tables; then ``compare --rtl`` on a scheduler and two ``dask worker``
    processes on 127.0.0.1: the workers run the executables built here (same machine: same
    paths) and write the CSVs and RTL counts of the one-worker run. (The RTL's tasks on
    local workers: ``test_table1_rows_identical_on_the_model_and_on_the_rtl``.)"""
    from helpers.dask_processes import process_cluster

    model, one_model = _run_job(tmp_path, "model", workers=1)
    rtl, one = _run_job(tmp_path, "rtl", workers=1, rtl=True)
    printed_model, printed_rtl = one_model.text(), one.text()
    for name in ("compare_pd.csv", "compare_pfa.csv", "compare_configs.csv"):
        assert (model / name).read_bytes() == (rtl / name).read_bytes(), name
    # run_compare's counts, trial by trial, not only the tables made of them
    a, b = one_model.result, one.result
    assert a.rtl is None and b.rtl["runs"] > 0
    assert a.counts.keys() == b.counts.keys()
    for key in a.counts:
        assert np.array_equal(a.counts[key], b.counts[key]), key
    summary = json.loads((rtl / "compare_summary.json").read_text())
    info = summary["run"]["rtl"]
    assert summary["run"]["engine"] == "rtl"
    assert json.loads((model / "compare_summary.json").read_text())["run"]["rtl"] is None
    # 2 fixed configurations x 4 trials x (3 SNRs + noise only) x 3 segments x 4 frames x 256
    pixels = 2 * 4 * 4 * 3 * 4 * 256
    assert info["pixel_updates"] == info["state_words"] == info["segmenter_pixels"] == pixels
    assert info["lists"] == 2 * 4 * 4 * 3 and info["segmenter_skipped"] == {}
    assert sorted(info["segmenter_checked"]) == ["4/5/8 truncate paper", "exact-ish"]
    assert "every candidate list" in info["verdict"]
    assert "RTL in the loop" not in printed_model
    line = [ln for ln in printed_rtl.splitlines() if ln.startswith("RTL in the loop: ")]
    assert len(line) == 1 and f"{pixels:,} pixel updates" in line[0]
    assert f"every state word ({pixels} compared) equals the golden model's" in line[0]
    # the tables printed are the same too
    assert printed_model.split("\n\n")[0] == printed_rtl.split("\n\n")[0]

    with process_cluster(tmp_path) as (address, _):
        two_dir, two = _run_job(tmp_path, "two", scheduler=address, rtl=True)
    assert one.workers == 1 and two.workers == 2
    for name in ("compare_pd.csv", "compare_pfa.csv", "compare_configs.csv"):
        assert (rtl / name).read_bytes() == (two_dir / name).read_bytes(), name
    timing = ("sim_seconds", "wall_seconds")
    assert ({k: v for k, v in one.result.rtl.items() if k not in timing}
            == {k: v for k, v in two.result.rtl.items() if k not in timing})
    assert one.result.rtl["runs"] == two.result.rtl["runs"] > 0


def _corrupting(monkeypatch, design, index, xor):
    real = verilator.run

    def run(sim, words, **kw):
        raw = real(sim, words, **kw)
        if sim.design == design:
            out = raw.out_words.copy()
            out[index] ^= np.uint64(xor)
            raw = dataclasses.replace(raw, out_words=out)
        return raw

    monkeypatch.setattr(verilator, "run", run)


def test_a_flipped_state_bit_is_located_by_trial_segment_frame_row_col_and_field(monkeypatch):
    frames = _frames()
    builds = rtl_trials.prepare_builds(SMALL)
    # trial 1, segment 1, frame 2 of it, row 3, col 5; bit 0 of E
    index = ((1 * 2 + 1) * 4 + 2) * 256 + 3 * 16 + 5
    offset = rtl_trials_state_offset("energy")
    _corrupting(monkeypatch, "dp", index, 1 << offset)
    with pytest.raises(rtl_trials.RTLMismatchError, match=(
            r"^RTL states differ from the golden model: configuration 'x', scene SNR 2: "
            r"trial 8, segment 1, frame 2 of the segment \(frame 6 of the trial\), row 3, "
            r"col 5, field energy: expected (\d+), got (?!\1)\d+ \(output word "
            rf"{index} of the run; differing fields \['energy'\]\)$")):
        rtl_trials.accumulate_trials(builds, frames, first_trial=7,
                                     label="configuration 'x', scene SNR 2: ")


def rtl_trials_state_offset(name):
    return state_layout(SMALL)[name].offset


def test_a_flipped_candidate_word_is_located_by_trial_segment_record_and_field(monkeypatch):
    from dptbd.hw.candidate_layout import candidate_field_offsets

    frames = _frames()
    builds = rtl_trials.prepare_builds(SMALL)
    assert builds.segmenter is not None, builds.segmenter_missing
    clean = rtl_trials.accumulate_trials(builds, frames)
    assert clean.tally.records > 0
    # the first record of the run: flip the lowest bit of its column
    col = candidate_field_offsets(SMALL)["record"]["col"]["offset"]
    real = verilator.run
    first_record = {}

    def run(sim, words, **kw):
        raw = real(sim, words, **kw)
        if sim.design == "segmenter":
            from dptbd.hw.candidate_layout import unpack_candidate
            kinds = [unpack_candidate(SMALL, w)[0] for w in raw.out_words.tolist()]
            i = kinds.index("record")
            lists_before = kinds[:i].count("trailer")
            first_record.update(index=i, lists=lists_before)
            out = raw.out_words.copy()
            out[i] ^= np.uint64(1 << col)
            raw = dataclasses.replace(raw, out_words=out)
        return raw

    monkeypatch.setattr(verilator, "run", run)
    with pytest.raises(rtl_trials.RTLMismatchError) as info:
        rtl_trials.accumulate_trials(builds, frames, label="L: ")
    trial, segment = divmod(first_record["lists"], 2)
    assert re.fullmatch(
        rf"RTL candidate list differs from the golden model: L: trial {trial}, segment "
        rf"{segment}, record 0, field col: expected (\d+), got (?!\1)\d+ \(output word "
        rf"{first_record['index']} of the run\)", str(info.value)), str(info.value)


def test_missing_output_words_are_an_error(monkeypatch):
    real = verilator.run

    def run(sim, words, **kw):
        raw = real(sim, words, **kw)
        return dataclasses.replace(raw, out_words=raw.out_words[:-300])

    monkeypatch.setattr(verilator, "run", run)
    with pytest.raises(rtl_trials.RTLMismatchError, match=(
            r"^RTL states: 5844 of 6144 words came out \(all bit-exact\), the run ended "
            r"before trial 2, segment 1, frame 2 of the segment \(frame 6 of the trial\)$")):
        rtl_trials.accumulate_trials(rtl_trials.prepare_builds(SMALL), _frames())


def test_unsupported_configurations_are_refused_up_front_by_name(monkeypatch):
    from dptbd.evaluation.compare import build_spec, run_compare

    def no_build(*a, **k):  # nothing may be built or simulated before the refusal
        raise AssertionError("built before refusing")

    monkeypatch.setattr(verilator, "build", no_build)
    spec = build_spec(small_spec(segment_stride=2))
    with pytest.raises(ConfigError, match=(
            r"^RTL in the loop: configuration 'exact-ish' cannot run on the gateware: "
            r"segment_stride=2 is not supported by the gateware: only non-overlapping segments "
            r"\(segment_stride == segment_frames == 4\) are implemented, with a single state "
            r"store$")):
        run_compare(spec, workers=1, rtl=True)
    spec = build_spec(small_spec(size=4, false_alarm_rate=0.2))
    with pytest.raises(ConfigError, match=(
            r"^RTL in the loop: configuration 'exact-ish' cannot run on the gateware: "
            r"width=4 x height=4 is too small for the read-ahead of radius=1: the gateware "
            r"needs width\*height - radius\*\(width\+1\) > write latency 12 cycles, but it is "
            r"11; each state must be written before the next frame reads it; use a larger "
            r"frame$")):
        run_compare(spec, workers=1, rtl=True)


def test_compare_command_refuses_rtl_before_any_work(tmp_path, monkeypatch, capsys):
    from dptbd import cli

    cfg = tmp_path / "c.toml"
    cfg.write_text(spec_toml(small_spec(segment_stride=3)))
    monkeypatch.setattr(verilator, "build", lambda *a, **k: pytest.fail("built"))
    assert cli.main(["compare", "--config", str(cfg), "--out", str(tmp_path / "o"),
                     "--rtl"]) == 2
    err = capsys.readouterr().err
    assert re.fullmatch(r"dptbd compare: error: RTL in the loop: configuration 'exact-ish' "
                        r"cannot run on the gateware: segment_stride=3 is not supported .*\n",
                        err), err
    assert not (tmp_path / "o").exists()


# ---- table1 --rtl -------------------------------------------------------------------------

def test_table1_rows_identical_on_the_model_and_on_the_rtl():
    from dptbd.evaluation.table1.experiment import SETTINGS, run_table1

    kw = dict(segment_frames=6, segment_stride=6, seed=5, chunk=2, settings=SETTINGS[:1],
              size=24)
    model = run_table1(3, **kw)
    rtl = run_table1(3, rtl=True, workers=2, **kw)  # the RTL's tasks on 2 local workers
    assert model.rtl is None and model.rows == rtl.rows
    # 3 trials x 16 segments x 6 frames x 24 x 24, for each of the two DP detectors
    assert rtl.rtl["pixel_updates"] == 2 * 3 * 16 * 6 * 24 * 24
    assert rtl.rtl["segmenter_checked"] == ["direction-weighted DP", "plain DP"]


def test_table1_rtl_refuses_overlapping_segments():
    from dptbd.evaluation.table1.experiment import run_table1

    with pytest.raises(ConfigError, match=(
            r"^RTL in the loop: configuration 'direction-weighted DP' cannot run on the "
            r"gateware: segment_stride=4 is not supported by the gateware: only "
            r"non-overlapping segments \(segment_stride == segment_frames == 6\) are "
            r"implemented, with a single state store$")):
        run_table1(1, segment_frames=6, segment_stride=4, rtl=True, size=24)


def test_table1_command_rtl_stride(capsys):
    from dptbd import cli

    assert cli.main(["table1", "--rtl", "--segment-stride", "4"]) == 2
    assert capsys.readouterr().err == (
        "dptbd table1: error: --rtl needs --segment-stride equal to --segment-frames (6): "
        "the gateware implements non-overlapping segments only, got --segment-stride 4\n")
