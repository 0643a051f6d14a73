"""The complete pipeline against the golden model ``dptbd.model.fixed``, bit for bit.

Every test streams whole frames through ``DPPipeline`` in the Amaranth simulator (random
input gaps and output back-pressure unless timing is the point), collects every output and
compares it with ``segment_start`` / ``dp_step`` frame by frame. The weight LUT's storage
(``lut_style``) must not change behaviour: the scoreboard cases use the default ("auto":
logic for r = 1, block RAM for r = 2) and the LUT, timing and cycle-count tests run with
both "bram" and "logic" explicitly.
"""

import warnings

import numpy as np
import pytest

from dptbd.config import DPConfig, EnergyWidthWarning
from dptbd.weights import plain_weights
from dptbd.errors import ConfigError
from dptbd.hw.dp_pipeline import DPPipeline
from helpers.hw_harness import (
    FIELDS,
    assert_states_equal,
    event_counter,
    frames_to_stream,
    lut_writes_for,
    reference_states,
    refused,
    run_stream,
    simulate,
)
from helpers.refusals import whole


def make_config(**kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        return DPConfig(**kw)


def random_frames(cfg, n_frames, seed, high=None):
    rng = np.random.default_rng(seed)
    top = cfg.pixel_max if high is None else high
    return rng.integers(0, top + 1, size=(n_frames, cfg.height, cfg.width))


SCOREBOARD_CASES = {
    "5x4-r1-k3-truncate": (dict(width=5, height=4, segment_frames=3), 7, None),
    "7x6-r2-k2-half_up": (dict(width=7, height=6, segment_frames=2, radius=2,
                               rounding="half_up"), 5, None),
    "7x6-r1-k3-half_up-f3": (dict(width=7, height=6, segment_frames=3, rounding="half_up",
                                  weight_frac_bits=3), 6, None),
    "5x4-r1-k2-f0": (dict(width=5, height=4, segment_frames=2, weight_frac_bits=0), 5, None),
    "5x4-r1-k1": (dict(width=5, height=4, segment_frames=1), 3, None),
    "6x5-r1-k3-saturating": (dict(width=6, height=5, segment_frames=3, input_bits=4,
                                  energy_bits=5), 6, None),
    "7x6-r2-k3-saturating": (dict(width=7, height=6, segment_frames=3, input_bits=6,
                                  energy_bits=7, rounding="half_up"), 4, None),
    "5x4-r1-k3-ties": (dict(width=5, height=4, segment_frames=3), 6, 1),
    "7x6-r2-k2-ties": (dict(width=7, height=6, segment_frames=2, radius=2), 4, 1),
    "3x8-r2-k2-narrow": (dict(width=3, height=8, segment_frames=2, radius=2), 4, None),
    "6x5-r1-k2-plain": (dict(width=6, height=5, segment_frames=2, weights=plain_weights(1)), 4, 2),
}


@pytest.mark.parametrize("name", list(SCOREBOARD_CASES))
def test_matches_golden_model(name):
    kw, n_frames, high = SCOREBOARD_CASES[name]
    cfg = make_config(**kw)
    frames = random_frames(cfg, n_frames, seed=len(name), high=high)
    dut = DPPipeline(cfg)
    run = run_stream(dut, cfg, frames_to_stream(frames), valid_probability=0.75,
                     ready_probability=0.6, seed=n_frames)
    expected = reference_states(cfg, frames)
    assert_states_equal(run.outputs, expected)
    if "saturating" in name:
        assert (expected[..., 0] == cfg.e_max).any(), "the test must reach saturation"


def test_random_fractional_weights_half_up():
    rng = np.random.default_rng(5)
    weights = rng.random((10, 9))
    cfg = make_config(width=6, height=5, segment_frames=4, weight_frac_bits=4,
                      rounding="half_up", weights=weights)
    assert not cfg.weights_exact
    frames = random_frames(cfg, 5, seed=9)
    run = run_stream(DPPipeline(cfg), cfg, frames_to_stream(frames), valid_probability=0.9,
                     ready_probability=0.8, seed=1)
    assert_states_equal(run.outputs, reference_states(cfg, frames))


STYLES = ("bram", "logic")


@pytest.mark.parametrize("style", STYLES)
@pytest.mark.parametrize("radius", [1, 2])
def test_lut_written_at_run_time(radius, style):
    """Write new codes through the LUT port between frames and again inside a frame."""
    cfg = make_config(width=7, height=6, segment_frames=4, radius=radius, weight_frac_bits=5)
    pixels = cfg.width * cfg.height
    rng = np.random.default_rng(radius)
    moves = cfg.n_moves
    old = cfg.weight_codes.astype(np.int64)
    between = rng.integers(0, 33, size=(moves + 1, moves))
    inside = between.copy()
    inside[:, : moves // 2] = rng.integers(0, 33, size=(moves + 1, moves // 2))
    switch_between = 1 * pixels            # before frame 1's first pixel
    switch_inside = 2 * pixels + 17        # before pixel 17 of frame 2
    writes = {switch_between: lut_writes_for(cfg, old, between),
              switch_inside: lut_writes_for(cfg, between, inside)}
    frames = random_frames(cfg, 4, seed=radius + 10)
    run = run_stream(DPPipeline(cfg, lut_style=style), cfg, frames_to_stream(frames),
                     valid_probability=0.8, ready_probability=0.7, seed=radius,
                     lut_writes=writes)
    expected = reference_states(cfg, frames, [(switch_between, between), (switch_inside, inside)])
    assert_states_equal(run.outputs, expected)
    # The write really changed results (the test would be vacuous otherwise).
    assert not np.array_equal(expected, reference_states(cfg, frames))


def test_lut_write_clamps_codes_above_one():
    cfg = make_config(width=5, height=4, segment_frames=2, weight_frac_bits=3)
    old = cfg.weight_codes.astype(np.int64)
    writes = {0: [(address, 15) for address in range(cfg.lut_entries)]}
    frames = random_frames(cfg, 2, seed=4)
    run = run_stream(DPPipeline(cfg), cfg, frames_to_stream(frames), lut_writes=writes)
    ones = np.full_like(old, 8)
    assert_states_equal(run.outputs, reference_states(cfg, frames, [(0, ones)]))


@pytest.mark.parametrize("style", ["auto", *STYLES])
@pytest.mark.parametrize("kw, n_frames", [
    (dict(width=5, height=4, segment_frames=3), 4),
    (dict(width=7, height=6, segment_frames=2, radius=2), 3),
])
def test_exact_cycle_count(kw, n_frames, style):
    """Valid and ready always high: one pixel per cycle in, one per cycle out, after L."""
    cfg = make_config(**kw)
    dut = DPPipeline(cfg, lut_style=style)
    assert dut.lut_style == {"auto": {1: "logic", 2: "bram"}[cfg.radius]}.get(style, style)
    latency = dut.latency
    assert latency == {1: 14, 2: 15}[cfg.radius]
    frames = random_frames(cfg, n_frames, seed=3)
    run = run_stream(dut, cfg, frames_to_stream(frames))
    assert_states_equal(run.outputs, reference_states(cfg, frames))
    total = n_frames * cfg.width * cfg.height
    first_in = run.accept_cycles[0]
    assert first_in == 1                         # ready rises one cycle after reset
    assert run.accept_cycles == list(range(first_in, first_in + total))   # no bubbles
    assert run.output_cycles[0] - first_in == latency
    assert run.output_cycles == list(range(first_in + latency, first_in + latency + total))
    assert run.output_cycles[-1] - first_in + 1 == total + latency
    assert total + latency == {1: 94, 2: 141}[cfg.radius]   # 4*20 + 14, 3*42 + 15


def test_back_pressure_never_loses_or_stalls_data():
    cfg = make_config(width=6, height=5, segment_frames=2)
    frames = random_frames(cfg, 4, seed=8)
    run = run_stream(DPPipeline(cfg), cfg, frames_to_stream(frames), ready_probability=0.15,
                     seed=2)
    assert_states_equal(run.outputs, reference_states(cfg, frames))
    # Output stalls throttle the input instead of overflowing the FIFO.
    assert run.accept_cycles[-1] > 4 * 30 * 3


def test_unexpected_first_resynchronises():
    """A frame cut short, then frames with `first`: a new segment starts at the `first`."""
    cfg = make_config(width=5, height=4, segment_frames=3)
    frames = random_frames(cfg, 6, seed=12)
    cut = 7
    stream = frames_to_stream(frames[:1]) + frames_to_stream(frames[1:2])[:cut] \
        + frames_to_stream(frames[2:])
    run = run_stream(DPPipeline(cfg), cfg, stream, valid_probability=0.7,
                     ready_probability=0.7, seed=4)
    head = reference_states(cfg, frames[:2])
    truncated = head[1].reshape(-1, len(FIELDS))[:cut].copy()
    truncated[:, 3:] = 0                          # the cut frame never ends
    tail = reference_states(cfg, frames[2:])      # a new segment from frame 2
    expected = np.concatenate([head[0].reshape(-1, len(FIELDS)), truncated,
                               tail.reshape(-1, len(FIELDS))])
    assert len(run.outputs) == len(expected)
    for n, (got, want) in enumerate(zip(run.outputs, expected)):
        assert [got[f] for f in FIELDS] == want.tolist(), f"output {n}"


def test_run_time_k_and_events():
    """K changed between segments (the port holds segment j's K at its first pixel, random
    values elsewhere), a resync in the middle: every word and every event count equals the
    stream model's. B_E = 9 saturates."""
    from dptbd.model.settings import SegmentSettings
    from dptbd.sim.stream_model import expected_stream

    cfg = make_config(width=5, height=4, segment_frames=2, max_segment_frames=4,
                      energy_bits=9)
    size = cfg.width * cfg.height
    lengths = [3, 1, 4, 2]
    frames = random_frames(cfg, sum(lengths) + 3, seed=21)
    stream = frames_to_stream(frames)
    stream = stream[:size * 9 + 6] + stream[size * 10:]        # resync inside frame 9
    first = np.array([f for _, f in stream])
    pixels = np.array([p for p, _ in stream])
    starts = np.cumsum([0] + lengths)[:-1] * size
    changes = {int(at): SegmentSettings(k, cfg.n_candidates, cfg.bin_shift)
               for at, k in zip(starts, lengths)}
    changes[size * 9 + 6] = SegmentSettings(3, cfg.n_candidates, cfg.bin_shift)   # the resync
    exp = expected_stream(cfg, pixels, first, settings_changes=changes)
    rng = np.random.default_rng(3)
    dut = DPPipeline(cfg)

    def drive(ctx, index):
        k = changes[index].segment_frames if index in changes else int(rng.integers(0, 8))
        ctx.set(dut.segment_frames, k)

    counts = {}
    run = run_stream(dut, cfg, stream, valid_probability=0.7, ready_probability=0.6, seed=5,
                     on_cycle=drive, processes=[event_counter(dut.events, counts)])
    assert len(run.outputs) == len(exp.fields)
    for n, (got, want) in enumerate(zip(run.outputs, exp.fields)):
        assert [got[f] for f in FIELDS] == want.tolist(), f"output {n}"
    assert counts == {"frame_done": int(exp.fields[:, 3].sum()),
                      "segment_done": int(exp.fields[:, 4].sum()), "list_done": 0,
                      "saturated": int(exp.saturated.sum())}
    assert counts["segment_done"] == 4 and counts["saturated"] > 0   # the resync cut one


def test_first_flags_are_optional():
    cfg = make_config(width=5, height=4, segment_frames=2)
    frames = random_frames(cfg, 4, seed=13)
    stream = [(pixel, False) for pixel, _ in frames_to_stream(frames)]
    run = run_stream(DPPipeline(cfg), cfg, stream, valid_probability=0.8, seed=5)
    assert_states_equal(run.outputs, reference_states(cfg, frames))


def test_refuses_overlapping_segments():
    cfg = DPConfig(width=8, height=8, segment_frames=4, segment_stride=2)
    with refused(ConfigError,
                 match=r"^segment_stride=2 is not supported by the gateware: "
                       r"only non-overlapping segments "
                       r"\(segment_stride == segment_frames == 4\) "
                       r"are implemented, with a single state store$"):
        DPPipeline(cfg)


def test_refuses_frames_too_small_for_the_read_ahead():
    cfg = DPConfig(width=5, height=4, radius=2)
    with refused(ConfigError,
                 match=r"^width=5 x height=4 is too small for the read-ahead of radius=2: "
                       r"the gateware needs width\*height - radius\*\(width\+1\) > write latency 13 "
                       r"cycles, but it is 8; each state must be written before the next frame reads "
                       r"it; use a larger frame$"):
        DPPipeline(cfg)


def test_refuses_a_too_small_output_fifo():
    cfg = DPConfig(width=5, height=4)
    with refused(ValueError, match=r"^output_fifo_depth must be an integer in \[3, inf\), got 2$"):
        DPPipeline(cfg, output_fifo_depth=2)


@pytest.mark.parametrize("bad", ["block", "Logic", None])
def test_refuses_an_unknown_lut_style(bad):
    cfg = DPConfig(width=5, height=4)
    with refused(ValueError, match=whole(f"lut_style must be one of 'auto', 'bram', 'logic', "
                                         f"got {bad!r}")):
        DPPipeline(cfg, lut_style=bad)


def test_deeper_output_fifo_works():
    cfg = make_config(width=5, height=4, segment_frames=2)
    frames = random_frames(cfg, 3, seed=14)
    dut = DPPipeline(cfg, output_fifo_depth=32)
    run = run_stream(dut, cfg, frames_to_stream(frames), ready_probability=0.5, seed=6)
    assert_states_equal(run.outputs, reference_states(cfg, frames))


@pytest.mark.parametrize("style", STYLES)
def test_lut_write_applies_from_the_pixel_accepted_in_the_same_cycle(style):
    """Write (START, move 0) := 0 in the cycle pixel n is accepted: n uses it, n - 1 does not.

    Frame 0 is flat, so in frame 1 every valid candidate ties and plain weights pick move 0
    wherever it is valid; with its weight at 0 the tie goes to move 1 instead.
    """
    cfg = make_config(width=5, height=4, segment_frames=2, weights=plain_weights(1))
    frames = random_frames(cfg, 2, seed=15)
    frames[0] = 100
    n = 20 + 1 * 5 + 1                        # frame 1, pixel (1, 1)
    address = cfg.lut_address(cfg.start_code, 0)
    run = run_stream(DPPipeline(cfg, lut_style=style), cfg, frames_to_stream(frames),
                     timed_lut_writes={n + 1: (address, 0)})   # pixel k is accepted in cycle k+1
    assert run.accept_cycles[n] == n + 1
    new = cfg.weight_codes.astype(np.int64)
    new[cfg.start_code, 0] = 0
    assert_states_equal(run.outputs, reference_states(cfg, frames, [(n, new)]))
    assert run.outputs[n - 1]["direction"] == 0 and run.outputs[n]["direction"] == 1


@pytest.mark.parametrize("style", ["logic", "bram"])
def test_input_ready_is_registered(style):
    """``pixels.ready`` comes from a register, not through logic from ``states.ready``.

    Every cycle the testbench flips ``states.ready`` (and ``pixels.valid``) both ways and
    reads ``pixels.ready`` after each settle: it must not move within the cycle. The run
    holds the output back long enough that the credit counter does drop ``pixels.ready``,
    so the check covers both of its values.
    """
    from dptbd.hw.layouts import pack_pixel

    cfg = make_config(width=6, height=5, segment_frames=2)
    dut = DPPipeline(cfg, lut_style=style)
    rng = np.random.default_rng(7)
    seen = set()

    async def bench(ctx):
        ctx.set(dut.pixels.payload.as_value(), pack_pixel(cfg, 5, True))
        for cycle in range(400):
            hold = cycle < 120 or rng.random() < 0.5      # a long stall, then random
            readings = []
            for ready in (0, 1, 0):
                for valid in (0, 1):
                    ctx.set(dut.states.ready, ready)
                    ctx.set(dut.pixels.valid, valid)
                    readings.append(ctx.get(dut.pixels.ready))
            assert len(set(readings)) == 1, f"cycle {cycle}: pixels.ready {readings}"
            seen.add(readings[0])
            ctx.set(dut.states.ready, 0 if hold else 1)
            ctx.set(dut.pixels.valid, int(rng.random() < 0.8))
            await ctx.tick()

    simulate(dut, bench)
    assert seen == {0, 1}, "the run must see pixels.ready both high and low"
