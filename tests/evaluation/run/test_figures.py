"""dptbd.evaluation.run.figures: the three figures of a run, with and without ground truth."""

import numpy as np
import pytest
from PIL import Image

from dptbd.evaluation.run.figures import figure_accumulated, figure_raw_frame, figure_tracks
from dptbd.evaluation.run.job import run_job
from dptbd.evaluation.run.scenario import parse_scenario


@pytest.fixture(scope="module")
def result():
    sc = parse_scenario({"scene": {"size": [32, 32], "frames": 24, "snr": 5.0, "seed": 3,
                                   "targets": [{"start": [6.0, 6.0], "velocity": [0.8, 0.6]}]},
                         "segmentation": {"false_alarm_rate": 0.005}})
    sc.check()
    return run_job(sc)


def size(path):
    with Image.open(path) as img:
        assert img.format == "PNG"
        return img.size


def test_raw_frame_has_a_truth_panel_only_with_truth(tmp_path, result):
    frame = result.frames[3]
    figure_raw_frame(tmp_path / "one.png", frame, 3, input_bits=12)
    figure_raw_frame(tmp_path / "two.png", frame, 3, input_bits=12,
                     truth_pixels=[(5, 6), None])
    assert size(tmp_path / "one.png") == (638, 550)            # (5.2 + 0.6) x 5 in at 110 dpi
    assert size(tmp_path / "two.png") == (1210, 550)


def test_accumulated_and_tracks(tmp_path, result):
    pipe = result.pipeline
    figure_accumulated(tmp_path / "acc.png", pipe.segments.energy[1], pipe.candidates[1], 1, 6,
                       11, truth_pixels=[(8, 9)])
    assert size(tmp_path / "acc.png") == (726, 616)
    figure_tracks(tmp_path / "tracks.png", pipe, truth=result.input.truth,
                  evaluation=result.evaluation, title="t")
    figure_tracks(tmp_path / "recorded.png", pipe)
    assert size(tmp_path / "tracks.png") == size(tmp_path / "recorded.png") == (1034, 726)
    assert not np.array_equal(np.asarray(Image.open(tmp_path / "tracks.png")),
                              np.asarray(Image.open(tmp_path / "recorded.png")))
