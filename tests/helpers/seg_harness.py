"""Amaranth-simulator harness for the segmentation gateware: drive one input stream with
random gaps, sink one output stream with random back-pressure, collect every word.

The expectation and the comparison come from :mod:`dptbd.sim.candidate_scoreboard` (the
same scoreboard the cocotb test uses), so a mismatch names the segment, record and field.
"""

from __future__ import annotations

import dataclasses
import random
import warnings

import numpy as np
from amaranth.hdl import ResetInserter, Signal

from dptbd.config import DPConfig, EnergyWidthWarning
from dptbd.hw import layouts
from dptbd.hw.layouts import pack_pixel
from dptbd.model.segmentation import segment_stream
from dptbd.sim.candidate_scoreboard import CandidateScoreboard
from helpers.hw_harness import simulate, stream_cycle


def make_config(**kw) -> DPConfig:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        return DPConfig(**kw)


@dataclasses.dataclass
class Run:
    outputs: list          # output payload words, in order
    accept_cycles: list    # cycle of each accepted input word
    output_cycles: list    # cycle of each output transfer
    cycles: int


def pack_state_rows(cfg: DPConfig, states: np.ndarray) -> list[int]:
    """``states`` payload words from ``(N, 5)`` rows (E, d, eol, eof, eos)."""
    names = ("energy", "direction", "end_of_line", "end_of_frame", "end_of_segment")
    rows = np.asarray(states)
    return layouts.pack_states(cfg, **{n: rows[:, i] for i, n in enumerate(names)}).tolist()


def pack_frames(cfg: DPConfig, frames: np.ndarray) -> list[int]:
    """``pixels`` payload words, ``first`` on pixel (0, 0) of every frame."""
    out = []
    for frame in np.asarray(frames):
        for i, v in enumerate(frame.ravel()):
            out.append(pack_pixel(cfg, int(v), i == 0))
    return out


def run(dut, source, sink, words: list[int], *, n_out: int, valid_probability=1.0,
        ready_probability=1.0, seed=0, settle=50, max_cycles=None, extra=(),
        on_cycle=None) -> Run:
    """Offer ``words`` on stream ``source`` (gaps), take from ``sink`` (back-pressure) until
    ``n_out`` words came out and then ``settle`` more cycles (to catch extra words).
    ``on_cycle(ctx, index)``, if given, runs at the start of every cycle with the index of
    the word on offer or next to be offered (e.g. to drive run-time settings ports)."""
    rng = random.Random(seed)
    if max_cycles is None:
        slow = max(valid_probability, 0.05) * max(ready_probability, 0.05)
        max_cycles = int((len(words) + 2000) / slow * 3) + 2000
    result = Run([], [], [], 0)

    async def bench(ctx):
        sent = 0
        offering = False
        quiet = 0
        while len(result.outputs) < n_out or quiet < settle:
            if len(result.outputs) >= n_out:
                quiet += 1
            if result.cycles >= max_cycles:
                raise AssertionError(f"timeout after {result.cycles} cycles: {sent}/{len(words)} "
                                     f"in, {len(result.outputs)}/{n_out} out")
            if not offering and sent < len(words):
                offering = rng.random() < valid_probability
                if offering:
                    ctx.set(source.payload.as_value(), words[sent])
            taking = rng.random() < ready_probability
            if on_cycle is not None:
                on_cycle(ctx, sent)
            if await stream_cycle(ctx, source, sink, offering, taking, result):
                sent += 1
                offering = False

    simulate(dut, bench, background=extra)
    return result


def score(cfg: DPConfig, lists, outputs: list[int]) -> CandidateScoreboard:
    """Feed ``outputs`` to a scoreboard of ``lists``; assert bit-exact with its report."""
    board = CandidateScoreboard(cfg, lists)
    board.receive_array(np.array(outputs, dtype=np.uint64))
    assert board.done, board.report()
    return board


def run_lists(cfg: DPConfig, dut, source, sink, words: list[int], lists, **kw) -> Run:
    """:func:`run` until every word of ``lists`` came out (and ``settle`` cycles more), then
    :func:`score` them: bit-exact, or an assertion naming the first mismatch."""
    result = run(dut, source, sink, words, n_out=CandidateScoreboard(cfg, lists).total, **kw)
    score(cfg, lists, result.outputs)
    return result



# ---- the segmenters' tests (tests/hw/test_segmenter.py, tests/hw/wide/test_segmenter.py) --

#: The segmenters' random-stream cases: name: (config, frames, (E range, fraction at the
#: bottom)) (P = 1; the wide tests take them at W = 12).
SEGMENTER_CASES = {
    "k3-n4-narrow-E": (dict(width=8, height=6, segment_frames=3, candidate_count=4,
                            histogram_bits=4, histogram_shift=0), 24, (0, 15, 0.5)),
    "k2-n6-cap6-shift2": (dict(width=7, height=5, segment_frames=2, candidate_count=6,
                               candidate_capacity=6, histogram_bits=5, histogram_shift=2),
                          10, (0, 140)),
    "k1-n3-ties": (dict(width=6, height=4, segment_frames=1, candidate_count=3,
                        histogram_bits=3, histogram_shift=0), 6, (0, 4)),
    "k4-n0": (dict(width=5, height=4, segment_frames=4, candidate_count=0, histogram_bits=3),
              8, (0, 255)),
    "k2-e12-clamped-top-bin": (dict(width=8, height=4, segment_frames=2, input_bits=8,
                                    energy_bits=12, candidate_count=5, histogram_bits=4,
                                    histogram_shift=3), 10, (100, 4095)),
    "k2-all-pixels": (dict(width=4, height=4, segment_frames=2, candidate_count=16,
                           histogram_bits=3), 6, (0, 255)),
}


def synthetic_states(cfg: DPConfig, n_frames: int, rng, *, low=0, high=None, first_k=0,
                     low_fraction=0.0, segment_frames=None) -> np.ndarray:
    """``(T*H*W, 5)`` state words (E, d, eol, eof, eos) with random E in [low, high] (a
    ``low_fraction`` of them exactly ``low``) and d in [0, M], flags as the DP pipeline sets
    them for segments of ``segment_frames`` (default K) frames, the first frame being frame
    ``first_k`` of its segment."""
    high = cfg.e_max if high is None else high
    k = segment_frames or cfg.segment_frames
    h, w = cfg.height, cfg.width
    out = np.zeros((n_frames, h, w, 5), dtype=np.int64)
    out[..., 0] = rng.integers(low, high + 1, size=(n_frames, h, w))
    out[..., 0][rng.random((n_frames, h, w)) < low_fraction] = low
    out[..., 1] = rng.integers(0, cfg.n_moves + 1, size=(n_frames, h, w))
    out[:, :, -1, 2] = 1
    out[:, -1, -1, 3] = 1
    for t in range(n_frames):
        out[t, -1, -1, 4] = int((t + first_k) % k == k - 1)
    return out.reshape(-1, 5)


def truncated_stream(cfg: DPConfig, rng, pre_frames: int, keep: int, post_frames: int,
                     **kw) -> np.ndarray:
    """What the DP pipeline outputs around a resynchronisation: ``pre_frames`` whole frames,
    the first ``keep`` words of the next without end_of_frame/end_of_segment, then
    ``post_frames`` frames of a new segment (``kw``: :func:`synthetic_states`')."""
    frame = cfg.width * cfg.height
    a = synthetic_states(cfg, pre_frames + 1, rng, **kw)
    cut = a[pre_frames * frame:][:keep].copy()
    cut[:, 3:] = 0
    b = synthetic_states(cfg, post_frames, rng, **kw)
    return np.concatenate([a[: pre_frames * frame], cut, b])


def scheduled_states(cfg: DPConfig, schedule, rng, **kw) -> tuple[np.ndarray, np.ndarray]:
    """State words of consecutive segments of the schedule's K (one segment per
    :class:`~dptbd.model.settings.SegmentSettings`), and per word the (K, n, s) of its
    segment."""
    parts, settings = [], []
    for entry in schedule:
        k = entry.segment_frames
        part = synthetic_states(cfg, k, rng, segment_frames=k, **kw)
        parts.append(part)
        settings.append(np.tile([k, entry.candidate_count, entry.histogram_shift],
                                (len(part), 1)))
    return np.concatenate(parts), np.concatenate(settings)


def misaligned_settings_stream(cfg: DPConfig, keep: int) -> tuple[np.ndarray, np.ndarray]:
    """(states, settings per word) of a misaligned segment start (docs/arithmetic.md §6.5a):
    a frame of K = 1 (n = 4, s = 4), the next cut after ``keep`` words, then a resync's three
    segments of K = 3 (n = 1, s = 2)."""
    from dptbd.model.settings import SegmentSettings as S
    frame = cfg.width * cfg.height
    rng = np.random.default_rng(21)
    before, _ = scheduled_states(cfg, [S(1, 4, 4), S(1, 4, 4)], rng, high=255)
    after, _ = scheduled_states(cfg, [S(3, 1, 2)] * 3, rng, high=255)
    cut = before[frame:frame + keep].copy()
    cut[:, 3:] = 0
    states = np.concatenate([before[:frame], cut, after])
    settings = np.array([[1, 4, 4]] * (frame + keep) + [[3, 1, 2]] * len(after))
    return states, settings


def settings_driver(cfg: DPConfig, states, settings, seed: int):
    """``make(dut)``: the ``on_cycle`` of :func:`run` that drives a segmenter's settings
    ports with the offered beat's segment's values at a segment's first beat (the first and
    each after an end_of_segment; a beat: P words, its last word's) and with random (also
    out-of-range) values elsewhere: only those beats' values may matter."""
    p = cfg.pixels_per_clock
    rng = np.random.default_rng(seed)
    beat_settings = settings[p - 1::p]
    first = np.ones(len(beat_settings), dtype=bool)
    first[1:] = states[p - 1::p][:-1, 4] == 1

    def make(dut):
        def drive(ctx, index):
            for column, port in enumerate((dut.segment_frames, dut.candidate_count,
                                           dut.histogram_shift)):
                if index < len(beat_settings) and first[index]:
                    value = int(beat_settings[index, column])
                else:
                    value = int(rng.integers(0, 1 << len(port)))
                ctx.set(port, value)
                if port is dut.segment_frames:              # the driver's K == 1 with K
                    ctx.set(dut.segment_frames_one, value == 1)
        return drive
    return make


def check_reset_in_a_scored_frame(cfg: DPConfig, dut, pack, keep: int) -> None:
    """``rst`` in the middle of a scored frame: ``keep`` words of three frames of states
    (``pack(cfg, states)``: the segmenter's input words), the reset, six frames; afterwards
    the first list is unprimed again and every output word is the model's of the six frames
    (:func:`score`)."""
    rng = np.random.default_rng(5)
    before = pack(cfg, synthetic_states(cfg, 3, rng, high=255))[:keep]
    after_states = synthetic_states(cfg, 6, rng, high=255)
    lists = segment_stream(after_states, cfg)
    score(cfg, lists, outputs_after_reset(dut, before, pack(cfg, after_states)))
    assert not lists[0].primed and lists[1].primed


def outputs_after_reset(dut, before: list[int], after: list[int]) -> list[int]:
    """Offer the words ``before`` (valid always, ready always), pulse ``rst`` for a cycle
    after the last is taken, offer ``after``: the candidate words out after the reset (until
    60 idle cycles after the last word is taken)."""
    rst = Signal()
    top = ResetInserter({"sync": rst})(dut)
    outputs = []

    async def bench(ctx):
        ctx.set(dut.candidates.ready, 1)
        for phase, words in (("before", before), ("after", after)):
            sent = idle = 0
            while sent < len(words) or (phase == "after" and idle < 60):
                ctx.set(dut.states.valid, sent < len(words))
                if sent < len(words):
                    ctx.set(dut.states.payload.as_value(), words[sent])
                took = sent < len(words) and ctx.get(dut.states.ready)
                if ctx.get(dut.candidates.valid) and phase == "after":
                    outputs.append(ctx.get(dut.candidates.payload.as_value()))
                await ctx.tick()
                sent += took
                idle = idle + 1 if sent == len(words) else 0
            if phase == "before":
                ctx.set(dut.states.valid, 0)
                ctx.set(rst, 1)
                await ctx.tick()
                ctx.set(rst, 0)

    simulate(top, bench)
    return outputs


async def scan_histogram(ctx, dut, scans: int) -> tuple[list, list]:
    """Scan a ``Histogram`` / ``BankedHistogram`` ``scans`` times from idle: the scans'
    (bin, count) lists in output order (with ``held_apart``, count + ``scan_held``) and
    the cycles from each scan_start to its last
    count; ``scanning`` is asserted throughout each scan and low after it."""
    out_scans, spans = [], []
    for _ in range(scans):
        ctx.set(dut.scan_start, 1)
        await ctx.tick()
        ctx.set(dut.scan_start, 0)
        got, cycles = [], 1
        while True:
            assert ctx.get(dut.scanning)
            if "scan_first" in dut.signature.members:          # Histogram(held_apart=True)
                top = (1 << len(dut.scan_bin)) - 1
                assert ctx.get(dut.scan_first) == (ctx.get(dut.scan_valid)
                                                   and ctx.get(dut.scan_bin) == top)
            if ctx.get(dut.scan_valid):
                # Histogram(held_apart=True): the held increment apart, added here
                held = ctx.get(dut.scan_held) if "scan_held" in dut.signature.members else 0
                got.append((ctx.get(dut.scan_bin), ctx.get(dut.scan_count) + held))
                if ctx.get(dut.scan_last):
                    break
            await ctx.tick()
            cycles += 1
        await ctx.tick()
        assert not ctx.get(dut.scanning)
        out_scans.append(got)
        spans.append(cycles)
    return out_scans, spans
