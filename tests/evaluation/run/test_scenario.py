"""``dptbd.evaluation.run.scenario``: the scalar values of a scenario file and the SNR options,
refused with ``dptbd.errors``' one message format."""

from __future__ import annotations


import pytest

from dptbd.evaluation.run.scenario import ScenarioError, check_snr, parse_scenario
from helpers.refusals import whole

SNR = "(001's SNR = (target mean - noise mean) / sigma)"
TARGET = {"start": [1.0, 2.0], "velocity": [0.5, 0.5]}


def scene(**kw):
    return {"scene": {"size": [16, 16], "frames": 12, "targets": [TARGET], **kw}}


def target(**kw):
    return {"scene": {"size": [16, 16], "frames": 12, "targets": [{**TARGET, **kw}]}}


@pytest.mark.parametrize("data, message", [
    (scene(frames=0), "[scene] frames must be an integer in [1, inf), got 0"),
    (scene(frames=12.0), "[scene] frames must be an integer in [1, inf), got 12.0"),
    (scene(frames=True), "[scene] frames must be an integer in [1, inf), got True"),
    (scene(seed=-1), "[scene] seed must be an integer in [0, inf), got -1"),
    (scene(size=[2, 16]), "[scene] size[0] (height) must be an integer in [3, inf), got 2"),
    (scene(mu="30"), "[scene] mu must be a finite real number in (-inf, inf), got '30'"),
    (scene(mu=float("nan")), "[scene] mu must be a finite real number in (-inf, inf), got nan"),
    (scene(sigma=0.0), "[scene] sigma must be a finite real number in (0, inf), got 0.0"),
    (scene(snr=-5.0), "[scene] snr must be a finite real number in (0, inf), got -5.0"),
    ({"adc": {"bits": 0}}, "[adc] bits must be an integer in [1, inf), got 0"),
    ({"adc": {"gain": float("inf")}},
     "[adc] gain must be a finite real number in (-inf, inf), got inf"),
    ({"segmentation": {"false_alarm_rate": 0}},
     "[segmentation] false_alarm_rate must be a finite real number in (0, inf), got 0"),
    ({"report": {"frame": -1}}, "[report] frame must be an integer in [0, inf), got -1"),
    (target(birth=-1), "[[scene.targets]] #1.birth must be an integer in [0, inf), got -1"),
    (target(death=0), "[[scene.targets]] #1.death must be an integer in [1, inf), got 0"),
    (target(snr=0), "[[scene.targets]] #1.snr must be a finite real number in (0, inf), got 0"),
    (target(start=[1.0, "x"]),
     "[[scene.targets]] #1.start[1] must be a finite real number in (-inf, inf), got 'x'"),
    (target(turns=[{"frame": 0, "degrees": 90.0}]),
     "[[scene.targets]] #1.turns[0].frame must be an integer in [1, inf), got 0"),
])
def test_scalar_values_are_refused_whole(data, message):
    with pytest.raises(ScenarioError, match=whole(message)):
        parse_scenario(data)


@pytest.mark.parametrize("snr, shown", [(0.0, "0.0"), (-1, "-1"), (float("inf"), "inf"),
                                        (float("nan"), "nan"), ("2", "'2'"), (True, "True")])
def test_check_snr(snr, shown):
    message = f"--snr {SNR} must be a finite real number in (0, inf), got {shown}"
    with pytest.raises(ScenarioError, match=whole(message)):
        check_snr("--snr", snr)
    assert check_snr("--snr", 2) == 2.0 and type(check_snr("--snr", 2)) is float


@pytest.mark.parametrize("data, message", [
    (target(velocity=[1.5, 0.0]),
     # row 1 -> 2.5 -> 4: rounded 1, 2, 4
     "scenario 'paper001-experiment-2': target 1 moves (2, 0) pixels from frame 1 to frame 2, beyond "
     "the move set's reach: its row and column steps must be integers in [-1, 1] (radius=1)"),
    (target(turns=[{"frame": 5, "velocity": [0.0, -3.0]}]),  # column 4.5 -> 1.5: pixels 4 -> 2
     "scenario 'paper001-experiment-2': target 1 moves (0, -2) pixels from frame 5 to frame 6, beyond "
     "the move set's reach: its row and column steps must be integers in [-1, 1] (radius=1)"),
    ({**target(velocity=[0.0, 3.0]), "dp": {"radius": 2}},
     "scenario 'paper001-experiment-2': target 1 moves (0, 3) pixels from frame 0 to frame 1, beyond "
     "the move set's reach: its row and column steps must be integers in [-2, 2] (radius=2)"),
])
def test_targets_beyond_the_move_sets_reach_are_refused(data, message):
    with pytest.raises(ScenarioError, match=whole(message)):
        parse_scenario(data)  # checks the scenario


def test_targets_within_reach_pass():
    parse_scenario(target(velocity=[1.0, -1.0])).check()
    parse_scenario({**target(velocity=[0.0, 2.0]), "dp": {"radius": 2}}).check()
    # leaving the image is not a move: 3 pixels a frame from outside is never visible twice
    parse_scenario(target(start=[-50.0, 1.0], velocity=[0.0, 0.0])).check()


def test_scenario_file_with_recorded_data_is_named_after_it(tmp_path):
    sc = parse_scenario({"input": {"path": "clip.npz"}}, tmp_path)
    assert sc.name == "clip.npz" and sc.input_path == tmp_path / "clip.npz"
    sc = parse_scenario({"name": "mine", "input": {"path": "clip.npz"}}, tmp_path)
    assert sc.name == "mine"
