"""``dptbd.sim.coverage.run_sets``: the counter run's scene raises every event counter of
``dptbd_axi`` at least ``events`` times (by the frame monitor's fault rule and the golden
model, the counts ``check_axi`` reads back), without a simulator."""

from __future__ import annotations

import pytest

from dptbd.sim.axi.stimulus import expected_outputs, fault_counts
from dptbd.sim.coverage.run_sets import (
    COUNTER_CONFIG,
    COUNTER_EVENTS,
    _config,
    axi_cases,
    counter_scene,
)


@pytest.mark.parametrize("events, faults, counters", [
    (16, {"sof_unexpected": 17, "frame_short": 16, "frame_long": 17, "line_length": 16},
     {"FRAMES": 24, "SEGMENTS": 21, "LISTS": 27, "SATURATED": 54}),
    (17, {"sof_unexpected": 18, "frame_short": 17, "frame_long": 18, "line_length": 17},
     {"FRAMES": 25, "SEGMENTS": 22, "LISTS": 28, "SATURATED": 54}),
])
def test_the_counter_scene_raises_every_counter_at_least_events_times(events, faults,
                                                                      counters):
    cfg = _config(COUNTER_CONFIG)
    beats, steps = counter_scene(cfg, 1, events)
    assert fault_counts(cfg, beats) == faults
    assert expected_outputs(cfg, beats, steps, cut_lists=True).counters() == counters
    assert min(faults.values()) >= events and min(counters.values()) >= events
    assert steps[-1]["stop"] == len(beats) and steps[-1]["writes"] == [["SEGMENT_FRAMES", 2]]


def test_the_coverage_campaign_runs_the_counter_scene_to_bit_19():
    """Bit 19 of a counter first becomes 1 at its 2**19-th event; 20-31 are excluded."""
    assert COUNTER_EVENTS == 2**19
    (case,) = [c for c in axi_cases() if c.scene == "counters"]
    assert (case.name, case.config, case.runs) == ("axi-3x6-counters", COUNTER_CONFIG, 1)
