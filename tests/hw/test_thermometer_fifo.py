"""``ThermometerFIFO``: cycle for cycle ``SyncFIFOBuffered``, under random write gaps ×
random read back-pressure. ``ref_fifo`` is a Python model of ``SyncFIFOBuffered``'s cycles;
``rtl_fifo`` records every cycle's ``w.ready``, ``r.valid`` and (when valid) ``r.payload`` of
the component under test, or of ``amaranth.lib.fifo.SyncFIFOBuffered`` itself, driven alike.
"""

import collections
import random

import pytest
from amaranth.hdl import Module
from amaranth.lib import data, fifo

from dptbd.errors import DptbdError
from dptbd.hw.thermometer_fifo import STORAGES, ThermometerFIFO
from helpers.hw_harness import refused, simulate

WIDTH = 8


def cases():
    """(depth, write gap probability, read stall probability, seed)."""
    return [(2, 0.0, 0.0, 1), (2, 0.3, 0.5, 2), (3, 0.0, 0.6, 3), (3, 0.5, 0.2, 4),
            (5, 0.2, 0.5, 5), (8, 0.0, 0.7, 6), (9, 0.4, 0.4, 7), (17, 0.1, 0.6, 8),
            (17, 0.6, 0.1, 9)]


def stimulus(gap, stall, seed, cycles=300):
    """Per cycle: (offer a word?, take a word?)."""
    rng = random.Random(seed)
    return [(rng.random() >= gap, rng.random() >= stall) for _ in range(cycles)]


def ref_fifo(depth, stim):
    """Every cycle's (w.ready, r.valid, r.payload or None) of ``SyncFIFOBuffered(depth)``:
    depth - 1 words in memory, read into an output register when that is empty or read."""
    memory, out_valid, out_word, next_word = collections.deque(), False, None, 1
    trace = []
    for offer, take in stim:
        w_ready = len(memory) < depth - 1
        trace.append((w_ready, out_valid, out_word if out_valid else None))
        do_read = bool(memory) and (not out_valid or take)
        if do_read:
            out_word, out_valid = memory.popleft(), True
        elif take:
            out_valid = False
        if offer and w_ready:
            memory.append(next_word)
            next_word += 1
    return trace


class LibraryFIFO(fifo.SyncFIFOBuffered):
    """``SyncFIFOBuffered`` with the stream member names of :class:`ThermometerFIFO`."""

    def __init__(self, depth):
        super().__init__(width=WIDTH, depth=depth)
        self.w, self.r = self.w_stream, self.r_stream


def rtl_fifo(dut, stim):
    trace = []

    async def bench(ctx):
        next_word = 1
        for offer, take in stim:
            ctx.set(dut.w.valid, offer)
            ctx.set(dut.w.payload, next_word)
            ctx.set(dut.r.ready, take)
            w_ready, r_valid = bool(ctx.get(dut.w.ready)), bool(ctx.get(dut.r.valid))
            trace.append((w_ready, r_valid, ctx.get(dut.r.payload) if r_valid else None))
            next_word += offer and w_ready
            await ctx.tick()

    m = Module()
    m.submodules.dut = dut
    simulate(m, bench)
    return trace


@pytest.mark.parametrize("staged", [False, True], ids=["direct", "staged"])
@pytest.mark.parametrize("storage", STORAGES)
@pytest.mark.parametrize("depth, gap, stall, seed", cases())
def test_cycles_are_those_of_sync_fifo_buffered(depth, gap, stall, seed, storage, staged):
    stim = stimulus(gap, stall, seed)
    trace = rtl_fifo(ThermometerFIFO(WIDTH, depth, storage=storage, staged=staged), stim)
    assert trace == ref_fifo(depth, stim)
    assert trace == rtl_fifo(LibraryFIFO(depth), stim)          # the model is the library's
    if stall > gap:     # back-pressure wins: the FIFO fills up and refuses writes
        assert not all(w_ready for w_ready, _, _ in trace)


@pytest.mark.parametrize("staged", [False, True], ids=["direct", "staged"])
@pytest.mark.parametrize("storage", STORAGES)
def test_a_word_takes_two_cycles_and_then_one_per_cycle(storage, staged):
    """Written in cycles 0, 1, 2 into an empty FIFO: on ``r`` from cycles 2, 3, 4."""
    stim = [(cycle < 3, True) for cycle in range(8)]
    trace = rtl_fifo(ThermometerFIFO(WIDTH, 4, storage=storage, staged=staged), stim)
    assert [word for _, _, word in trace] == [None, None, 1, 2, 3, None, None, None]


@pytest.mark.parametrize("storage", STORAGES)
def test_carries_a_layout(storage):
    layout = data.StructLayout({"a": 3, "b": 1})
    dut = ThermometerFIFO(layout, 3, storage=storage)
    assert dut.r.payload.shape() == layout and dut.depth == 3
    seen = []

    async def bench(ctx):
        ctx.set(dut.r.ready, 1)
        for cycle in range(6):
            ctx.set(dut.w.valid, cycle < 2)
            ctx.set(dut.w.payload, {"a": 5 - cycle, "b": cycle})
            if ctx.get(dut.r.valid):
                seen.append((ctx.get(dut.r.payload.a), ctx.get(dut.r.payload.b)))
            await ctx.tick()

    simulate(dut, bench)
    assert seen == [(5, 0), (4, 1)]


def ref_levels(depth, stim):
    """Every cycle's level of ``SyncFIFOBuffered(depth)`` (memory words and the output
    register) under ``stim``, as :func:`ref_fifo` drives it."""
    memory, out_valid, levels = 0, False, []
    for offer, take in stim:
        levels.append(memory + out_valid)
        w_ready = memory < depth - 1
        if memory and (not out_valid or take):
            memory, out_valid = memory - 1, True
        elif take:
            out_valid = False
        memory += offer and w_ready
    return levels


@pytest.mark.parametrize("staged", [False, True], ids=["direct", "staged"])
@pytest.mark.parametrize("depth, gap, stall, seed", [(2, 0.3, 0.5, 2), (8, 0.2, 0.5, 6),
                                                     (9, 0.4, 0.4, 7)])
def test_low_is_the_level_at_most_the_mark(depth, gap, stall, seed, staged):
    """``low_mark=k``: ``low`` is high exactly in the cycles whose level is at most k, for
    every k from 0 to the depth."""
    stim = stimulus(gap, stall, seed)
    levels = ref_levels(depth, stim)
    assert len(set(levels)) == depth + 1                  # every level is reached
    for mark in range(depth + 1):
        dut = ThermometerFIFO(WIDTH, depth, storage="memory", staged=staged, low_mark=mark)
        lows = []

        async def bench(ctx, dut=dut, lows=lows):
            for offer, take in stim:
                ctx.set(dut.w.valid, offer)
                ctx.set(dut.r.ready, take)
                lows.append(bool(ctx.get(dut.low)))
                await ctx.tick()

        simulate(dut, bench)
        assert lows == [level <= mark for level in levels], mark


def test_refuses_a_depth_below_two():
    with refused(DptbdError, r"^depth must be an integer in \[2, inf\), got 1$"):
        ThermometerFIFO(WIDTH, 1)


def test_refuses_an_unknown_storage():
    with refused(DptbdError, r"^storage must be one of 'memory', 'registers', 'one_hot', got 'flops'$"):
        ThermometerFIFO(WIDTH, 3, storage="flops")
