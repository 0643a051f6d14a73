"""``CandidateEmitter``: the record cap C, the overflow bit, the trailer, the FIFO (§6.4)."""

import random

import pytest

from dptbd.hw.candidate_emitter import CandidateEmitter
from dptbd.hw.candidate_layout import pack_record, pack_trailer
from helpers.hw_harness import refused, simulate
from helpers.seg_harness import make_config


def emit(cfg, pixels, *, ready_probability=1.0, seed=0, **options):
    """``pixels``: (selected, end_of_list, row, col, energy) per scored pixel; a pixel is
    presented only while ``space`` is high, with an idle cycle after each list end."""
    dut = CandidateEmitter(cfg, **options)
    rng = random.Random(seed)
    out = []

    async def bench(ctx):
        queue = list(pixels)
        idle = 0
        gap = False
        while queue or idle < 40:
            present = False
            if queue and ctx.get(dut.space) and not gap:
                sel, eol, row, col, energy = queue.pop(0)
                present = True
                ctx.set(dut.selected, sel)
                ctx.set(dut.end_of_list, eol)
                ctx.set(dut.record.row, row)
                ctx.set(dut.record.col, col)
                ctx.set(dut.record.energy, energy)
                ctx.set(dut.record.direction, 3)
                ctx.set(dut.threshold, 5)
                ctx.set(dut.primed, 1)
                ctx.set(dut.aligned, 1)
                ctx.set(dut.missed, 0)
            ctx.set(dut.valid, present)
            take = rng.random() < ready_probability
            ctx.set(dut.candidates.ready, take)
            if take and ctx.get(dut.candidates.valid):
                out.append(ctx.get(dut.candidates.payload.as_value()))
            await ctx.tick()
            gap = present and eol                     # the segmenter's scan gap
            idle = 0 if queue else idle + 1

    simulate(dut, bench)
    return out


def reference(cfg, pixels):
    words, emitted, overflow = [], 0, False
    for sel, eol, row, col, energy in pixels:
        if sel and emitted < cfg.record_capacity:
            words.append(pack_record(cfg, row, col, energy, 3))
            emitted += 1
        elif sel:
            overflow = True
        if eol:
            words.append(pack_trailer(cfg, count=emitted, threshold=5, overflow=overflow,
                                      primed=1, aligned=1, missed=0, cut=0))
            emitted, overflow = 0, False
    return words


OPTIONS = [{"registered_cap": False}, {"registered_cap": True, "staged_fifo": True},
           {"registered_cap": False, "staged_fifo": True},
           {"registered_cap": True, "staged_fifo": False}]
OPTION_IDS = ["generic", "registered", "staged", "registered_unstaged"]


@pytest.mark.parametrize("options", OPTIONS, ids=OPTION_IDS)
@pytest.mark.parametrize("ready", [1.0, 0.3])
def test_cap_overflow_and_trailer(ready, options):
    cfg = make_config(width=8, height=8, candidate_count=3, candidate_capacity=4,
                      histogram_bits=4)
    rng = random.Random(7)
    pixels = []
    for length, p in [(20, 0.5), (10, 0.0), (15, 0.1), (12, 1.0), (1, 1.0), (4, 1.0)]:
        for i in range(length):
            pixels.append((rng.random() < p, i == length - 1, i // 8, i % 8, rng.randrange(256)))
    want = reference(cfg, pixels)
    got = emit(cfg, pixels, ready_probability=ready, seed=3, **options)
    assert got == want
    # the lists exercised: an overflowing one (12 selected > C = 4), an empty one,
    # a list whose last pixel is a record
    assert pixels[-1][0] and pixels[-1][1]


@pytest.mark.parametrize("options", OPTIONS, ids=OPTION_IDS)
def test_zero_capacity_only_trailers(options):
    cfg = make_config(width=8, height=8, candidate_count=0, candidate_capacity=0)
    pixels = [(True, i == 5, 0, i, 9) for i in range(6)]
    got = emit(cfg, pixels, **options)
    assert got == [pack_trailer(cfg, count=0, threshold=5, overflow=1, primed=1, aligned=1,
                                missed=0, cut=0)]


def test_refuses_a_small_fifo():
    with refused(ValueError, match=r"^fifo_depth must be an integer in \[6, inf\), got 5$"):
        CandidateEmitter(make_config(width=8, height=8), fifo_depth=5)


def lockstep(cfg, seed, cycles, options, replay=None):
    """Every output of a ``CandidateEmitter(cfg, **options)`` in every cycle (the payload
    while valid) under a random stimulus that keeps the emitter's rules (a pixel only while
    ``space``, none in the cycle after a list end), or ``replay``'s, an earlier trace's."""
    dut = CandidateEmitter(cfg, **options)
    rng = random.Random(seed)
    trace = []

    async def bench(ctx):
        gap = False
        for cycle in range(cycles):
            if replay is not None:
                draw = replay[cycle][0]
            else:
                draw = {"offer": rng.random() < 0.8, "selected": rng.random() < 0.6,
                        "end_of_list": rng.random() < 0.08, "ready": rng.random() < 0.4,
                        "row": rng.randrange(8), "col": rng.randrange(8),
                        "energy": rng.randrange(256), "threshold": rng.randrange(16)}
            present = draw["offer"] and bool(ctx.get(dut.space)) and not gap
            ctx.set(dut.valid, present)
            ctx.set(dut.selected, draw["selected"])
            ctx.set(dut.end_of_list, draw["end_of_list"])
            ctx.set(dut.record.row, draw["row"])
            ctx.set(dut.record.col, draw["col"])
            ctx.set(dut.record.energy, draw["energy"])
            ctx.set(dut.threshold, draw["threshold"])
            ctx.set(dut.candidates.ready, draw["ready"])
            valid = ctx.get(dut.candidates.valid)
            out = (valid, ctx.get(dut.candidates.payload.as_value()) if valid else None,
                   ctx.get(dut.space))
            trace.append((draw, out))
            gap = present and draw["end_of_list"]
            await ctx.tick()

    simulate(dut, bench)
    return trace


@pytest.mark.parametrize("registered_cap", [False, True])
def test_staged_fifo_is_the_library_fifo_cycle_for_cycle(registered_cap):
    """``staged_fifo=True`` (the write through a stage register, the trailer's count
    completed as it is written) against ``SyncFIFOBuffered``: the same words, ``valid``
    and ``space`` in every cycle, with the FIFO filled to ``space``'s mark."""
    cfg = make_config(width=8, height=8, candidate_count=3, candidate_capacity=4,
                      histogram_bits=4)
    library = lockstep(cfg, 11, 4000, {"registered_cap": registered_cap, "staged_fifo": False})
    staged = lockstep(cfg, 11, 4000, {"registered_cap": registered_cap, "staged_fifo": True},
                      replay=library)
    assert [out for _d, out in staged] == [out for _d, out in library]
    # not vacuous: words sent, space low (the FIFO filled to its mark)
    assert sum(valid and draw["ready"] for draw, (valid, _w, _s) in library) > 500
    assert sum(not space for _d, (_v, _w, space) in library) > 200
