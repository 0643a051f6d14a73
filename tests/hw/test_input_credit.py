"""``InputCredit`` in front of a pipeline of fixed latency and a ``ThermometerFIFO``, under
random input gaps × random output back-pressure. ``ref_ready`` is the binary credit counter
the core had before (committed(t + 1) = committed(t) + accept - handed_out, ready(t + 1) =
committed(t) < depth - 1, as a Python integer) fed with the handshakes the RTL made;
``rtl_credit`` runs the credit, the pipeline and the FIFO and records every cycle.
"""

import random

import pytest
from amaranth.hdl import Module, Signal

from dptbd.errors import DptbdError
from dptbd.hw.delay import delayed
from dptbd.hw.input_credit import InputCredit
from dptbd.hw.thermometer_fifo import ThermometerFIFO
from helpers.hw_harness import refused, simulate

WIDTH = 8


def cases():
    """(pipeline registers, FIFO depth, input gap probability, output stall probability,
    seed). A word takes registers + 2 cycles from the input to the output (the FIFO adds
    2); the core's FIFO depth is that latency + 2; shallower and deeper FIFOs too."""
    return [(1, 5, 0.0, 0.5, 1), (3, 7, 0.2, 0.4, 2), (6, 10, 0.0, 0.7, 3),
            (6, 10, 0.5, 0.2, 4), (6, 4, 0.1, 0.3, 5), (12, 16, 0.3, 0.6, 6),
            (12, 20, 0.0, 0.5, 7), (2, 3, 0.0, 0.3, 8), (0, 3, 0.2, 0.2, 9)]


def ref_ready(depth, accepts, handed_out):
    """``pixels.ready`` of every cycle from the binary counter, given the handshakes."""
    committed, ready_early, ready, out = 0, True, False, []
    for accept, handed in zip(accepts, handed_out):
        out.append(ready)
        committed += accept - handed
        assert 0 <= committed <= depth
        ready, ready_early = ready_early, committed < depth - 1
    return out


def rtl_credit(registers, depth, gap, stall, seed, cycles=400, copies=1):
    """Per cycle: ready, accept, handed_out, and the word handed out (or None); and whether
    the FIFO ever refused a word from the pipeline. With ``copies`` > 1 ``ready`` is the
    tuple of the copies, the credit counting the accepts of its copy 0 and the pipeline
    those of the last copy."""
    rng = random.Random(seed)
    m = Module()
    m.submodules.credit = credit = InputCredit(depth, copies=copies)
    m.submodules.fifo = out = ThermometerFIFO(WIDTH, depth)
    in_valid, in_word = Signal(), Signal(WIDTH)
    accept = in_valid & credit.ready[-1]
    late = delayed(m, accept, registers, name="valid")
    late_word = delayed(m, in_word, registers, name="word")
    m.d.comb += [
        credit.accept.eq(in_valid & credit.ready[0]),
        credit.handed_out.eq(out.r.valid & out.r.ready),
        out.w.valid.eq(late),
        out.w.payload.eq(late_word),
    ]
    trace, refused_words = [], []

    async def bench(ctx):
        next_word = 1
        for _ in range(cycles):
            offer, take = rng.random() >= gap, rng.random() >= stall
            ctx.set(in_valid, offer)
            ctx.set(in_word, next_word)
            ctx.set(out.r.ready, take)
            readies = [bool(ctx.get(credit.ready[k])) for k in range(copies)]
            ready, valid = readies[-1], bool(ctx.get(out.r.valid))
            if ctx.get(out.w.valid) and not ctx.get(out.w.ready):
                refused_words.append(ctx.get(out.w.payload))
            trace.append((readies[0] if copies == 1 else tuple(readies), offer and ready,
                          valid and take,
                          ctx.get(out.r.payload) if valid and take else None))
            next_word = (next_word + (offer and ready)) % (1 << WIDTH)
            await ctx.tick()

    simulate(m, bench)
    return trace, refused_words


@pytest.mark.parametrize("registers, depth, gap, stall, seed", cases())
def test_ready_is_the_binary_credit_and_no_word_is_lost(registers, depth, gap, stall, seed):
    trace, refused_words = rtl_credit(registers, depth, gap, stall, seed)
    readies, accepts, handed, words = zip(*trace)
    assert list(readies) == ref_ready(depth, accepts, handed)
    assert refused_words == []
    got = [word for word in words if word is not None]
    assert got == [(n + 1) % (1 << WIDTH) for n in range(len(got))]
    assert len(got) > sum(accepts) - depth - 1    # all but those still committed came out


@pytest.mark.parametrize("depth, period", [(10, [True]), (9, [True] * 9 + [False] * 2)])
def test_latency_plus_two_words_keep_one_pixel_per_clock(depth, period):
    """Without back-pressure (6 registers: latency 8) the input is ready from cycle 1 on
    with a FIFO of latency + 2 words; with one word less, 9 cycles of every 11."""
    trace, _ = rtl_credit(6, depth, 0.0, 0.0, 1, cycles=100)
    readies = [ready for ready, _, _, _ in trace]
    assert readies == [False] + (period * 99)[:99]


@pytest.mark.parametrize("depth, copies", [(3, 4), (5, 2), (10, 4), (16, 7)])
def test_every_copy_of_ready_is_the_binary_credit(depth, copies):
    """``copies`` registers (up to 2 * (depth - 1): pairs of equal functions of the flags,
    one of each stored inverted), each ready in the same cycles as the binary credit."""
    trace, refused_words = rtl_credit(6, depth, 0.2, 0.5, depth + copies, copies=copies)
    readies, accepts, handed, _ = zip(*trace)
    reference = ref_ready(depth, accepts, handed)
    assert [set(r) for r in readies] == [{want} for want in reference]
    assert refused_words == []
    assert len(set(reference)) == 2                  # both closed and open


def test_refuses_a_depth_below_three():
    with refused(DptbdError, r"^depth must be an integer in \[3, inf\), got 2$"):
        InputCredit(2)


@pytest.mark.parametrize("copies", [0, 9])
def test_refuses_copies_outside_the_flags_pairs(copies):
    with refused(DptbdError, rf"^copies must be an integer in \[1, 8\], got {copies}$"):
        InputCredit(5, copies=copies)
