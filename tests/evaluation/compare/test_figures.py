"""The figures of ``dptbd compare`` (:mod:`dptbd.evaluation.compare.figures`): each drawn from
a summary, at its size and resolution, with and without synthesis numbers."""

from __future__ import annotations

import struct

import pytest

from dptbd.evaluation import sweep
from dptbd.evaluation.compare import figures
from dptbd.evaluation.compare.report import summarise
from dptbd.evaluation.compare.runner import run_compare
from dptbd.evaluation.compare.spec import build_spec


def _png_size(path) -> tuple[int, int]:
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    return struct.unpack(">II", data[16:24])


@pytest.fixture(scope="module")
def result():
    spec = build_spec({"trials": 2, "size": 16, "frames": 8, "segment_frames": 4,
                       "false_alarm_rate": 0.02, "bootstrap": 10, "snr": [1.5, 2.5, 3.5],
                       "thresholds": [2.0, 3.0], "config": [{"name": "ten", "input_bits": 10}],
                       "sweep": {"input_bits": [3, 4, 5]}})
    return run_compare(spec, workers=1)


def test_draw_figures_writes_the_three_at_their_sizes(tmp_path, result):
    summary = summarise(result)
    paths = figures.draw_figures(summary, tmp_path)
    assert paths == [tmp_path / name for name in figures.FIGURES]
    # figsize x 110 dpi; the loss figure is 7 inches wide up to 7 configurations
    assert [_png_size(p) for p in paths] == [(1430, 704), (880, 594), (770, 572)]


def test_each_figure_alone(tmp_path, result):
    summary = summarise(result)
    assert figures.draw_pd_figure(summary, tmp_path / "a.png") == tmp_path / "a.png"
    assert figures.draw_pfa_figure(summary, tmp_path / "b.png") == tmp_path / "b.png"
    assert figures.draw_loss_figure(summary, tmp_path / "c.png") == tmp_path / "c.png"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.png", "b.png", "c.png"]


def test_loss_figure_shows_the_synthesis_numbers_when_there_are_some(tmp_path, result):
    plain = summarise(result)
    cost = {f.name: sweep.HardwareCost(
        lut4=700 + 10 * i, ff=300, bram=4, carry=50, fmax_median_mhz=90.0 + i, fmax_mhz=(90.0,),
        fits=True, logic_cells=800, device="hx8k", package="ct256", variant="core", width=128,
        height=128, seconds=1.0) for i, f in enumerate(result.spec.configs)}
    synthesised = summarise(result, cost)
    synthesised["run"]["synth"] = {"variant": "core", "device": "hx8k", "package": "ct256",
                                   "seeds": [1, 2, 3], "target_mhz": 100.0, "size": 128}
    figures.draw_loss_figure(plain, tmp_path / "plain.png")
    figures.draw_loss_figure(synthesised, tmp_path / "synth.png")
    assert _png_size(tmp_path / "plain.png") == _png_size(tmp_path / "synth.png")
    assert (tmp_path / "plain.png").read_bytes() != (tmp_path / "synth.png").read_bytes()


def test_loss_rows_are_the_sweep_smallest_first():
    rows = [{"name": n, "in_sweep": s, "state_bits_per_pixel": b, "hw_lut4": None,
             "input_bits": i, "weight_frac_bits": 0, "widths": f"{i}/{b - 4}/0",
             "rounding": r, "lut": "paper"}
            for n, s, b, i, r in [("big", True, 16, 8, "truncate"), ("mine", False, 8, 3, "truncate"),
                                  ("small", True, 12, 6, "half_up")]]
    chosen, labels = figures._loss_rows({"configs": rows})
    assert [r["name"] for r in chosen] == ["small", "big"]
    assert labels == ["6/8/0 half_", "8/12/0 trunc"]   # the rounding shown as it varies
