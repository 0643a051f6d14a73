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

from dptbd.config import DPConfig, EnergyWidthWarning
from dptbd.hw import layouts
from dptbd.hw.layouts import pack_pixel
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
