"""AxiReadPrefetcher: its bursts against a reference of the issue rule, the words it hands
out, and a restart, behind the strict AXI4 memory model."""

import pytest

from dptbd.config import DPConfig
from dptbd.hw.axi_store.prefetcher import AxiReadPrefetcher
from dptbd.hw.schedule import read_ahead_distance
from dptbd.sim.axi4_memory import Axi4Memory, OneSided
from helpers.dp16kd_model import DP16KDModel
from helpers.hw_harness import refused, simulate


def ref_bursts(store, written):
    """The bursts the prefetcher issues with nothing taken and ``written`` words answered:
    from word D on, aligned bursts while the beat FIFO has room and every word's write is
    answered (word i needs written >= i + 1 + D - W*H/P; words of P states, D the
    read-ahead of the beat configuration)."""
    cfg = store.frame.beat_config()
    pixels, per_beat = store.frame_words, store.words_per_beat
    ahead = read_ahead_distance(cfg) % pixels
    beat, skip, index, reserved, out = ahead // per_beat, ahead % per_beat, 0, 0, []
    depth = store.outstanding * store.burst_beats
    while True:
        length = min(store.burst_beats - beat % store.burst_beats, store.frame_beats - beat)
        need = index + length * per_beat - skip + read_ahead_distance(cfg) - pixels
        if need > written or reserved + length > depth:
            return out
        out.append(("AR", store.base_address + beat * store.beat_bytes, length))
        index += length * per_beat - skip
        reserved += length
        beat, skip = (beat + length) % store.frame_beats, 0


def run_prefetch(store, *, written, takes=None, seed=0, latency=(0, 0), cycles=400,
                 style="memory"):
    """Hold ``written``; in the cycles listed in ``takes`` (cycle -> restart flag) take a
    word if one is available; return the memory and the words taken. ``style="dp16kd"``:
    the beat FIFO in (behavioural) DP16KDs."""
    dut = AxiReadPrefetcher(store, style=style,
                            dp16kd=DP16KDModel if style == "dp16kd" else None)
    top = OneSided(dut, store)
    memory = Axi4Memory(top.axi, store, seed=seed, latency=latency)
    taken = []

    async def bench(ctx):
        ctx.set(dut.written, written)
        for cycle in range(cycles):
            restart = (takes or {}).get(cycle)
            take = restart is not None and ctx.get(dut.available)
            ctx.set(dut.take, take)
            ctx.set(dut.restart, take and restart)
            if take:
                taken.append(ctx.get(dut.word.as_value()))
            await ctx.tick()

    simulate(top, bench, background=[memory.process()])
    return memory, taken


def memory_word(memory, store, addr):
    slot_bytes = store.slot_bits // 8
    start = store.base_address + addr * slot_bytes
    value = int.from_bytes(bytes(memory.byte(start + k) for k in range(slot_bytes)), "little")
    return value & ((1 << store.frame.state_bits) - 1)


@pytest.mark.parametrize("fields, written", [
    (dict(data_bits=128, burst_beats=4, outstanding=16), 0),     # the order rule stops it
    (dict(data_bits=128, burst_beats=4, outstanding=16), 40),
    (dict(data_bits=64, burst_beats=2, outstanding=3), 175),       # the FIFO stops it
    (dict(data_bits=32, burst_beats=16, outstanding=2, base_address=0x1000), 0),
    (dict(data_bits=128, burst_beats=4, outstanding=16, p=2), 20),  # words of 2 states
    (dict(data_bits=64, burst_beats=2, outstanding=3, p=4), 40),
    (dict(data_bits=64, burst_beats=4, outstanding=16, p=4), 0),
])
@pytest.mark.parametrize("style", ["memory", "dp16kd"])
def test_bursts_follow_the_issue_rule(fields, written, style):
    fields = dict(fields)
    p = fields.pop("p", 1)
    cfg = DPConfig(width=16, height=12, pixels_per_clock=p)
    store = (cfg.build_config() if p > 1 else cfg).axi_store(**fields)   # 16-bit slots at P > 1
    memory, _ = run_prefetch(store, written=written, style=style)
    assert memory.bursts == ref_bursts(store, written)
    assert memory.bursts                                   # it did prefetch


@pytest.mark.parametrize("style", ["memory", "dp16kd"])
def test_words_come_out_in_read_ahead_order_and_restart_at_d_plus_one(style):
    """Take 30 words (addresses 17 …), restart on the 31st, then take 10 more: the
    restart's own word is the 31st of the old sequence; the next ones are 18, 19, …; with
    the beat FIFO in either style."""
    store = DPConfig(width=16, height=12).axi_store(data_bits=64, burst_beats=4)
    takes = {c: False for c in range(20, 50)}
    takes[50] = True
    takes.update({c: False for c in range(51, 200)})
    memory, taken = run_prefetch(store, written=300, takes=takes, latency=(0, 9), style=style)
    words = [memory_word(memory, store, a) for a in range(192)]
    assert taken[:31] == words[17:48]
    assert taken[31:41] == words[18:28]


@pytest.mark.parametrize("style", ["memory", "dp16kd"])
@pytest.mark.parametrize("p", [2, 4])
def test_a_word_of_p_states_is_p_consecutive_slots(p, style):
    """At P pixels per clock a word is the P states of slots ``P*a`` … ``P*a + P - 1`` (the
    P = 1 byte layout), state 0 in the low bits; the restart rule counts words."""
    cfg = DPConfig(width=16, height=12, pixels_per_clock=p).build_config()   # 16-bit slots
    store = cfg.axi_store(data_bits=64, burst_beats=2)
    ahead = read_ahead_distance(cfg.beat_config())
    takes = {c: False for c in range(20, 40)}
    takes[40] = True
    takes.update({c: False for c in range(41, 120)})
    memory, taken = run_prefetch(store, written=300, takes=takes, latency=(0, 5), style=style)
    bits = cfg.state_bits
    words = [sum(memory_word(memory, store, a * p + k) << (k * bits) for k in range(p))
             for a in range(store.frame_words)]
    n = len(words)
    # the restart's word (the take in cycle 40, after those the latency allowed) ends the
    # first run of the read-ahead sequence; the next run starts at word D + 1
    cut = next(i for i in range(1, len(taken)) if taken[i] != words[(ahead + i) % n])
    assert 10 <= cut <= 21 and len(taken) > cut + 40       # it wrapped past the frame's end
    assert taken == ([words[(ahead + i) % n] for i in range(cut)]
                     + [words[(ahead + 1 + i) % n] for i in range(len(taken) - cut)])


def test_refuses_an_unknown_fifo_style():
    with refused(ValueError, match=r"^style must be one of \('memory', 'dp16kd'\), got 'bram'$"):
        AxiReadPrefetcher(DPConfig(width=16, height=12).axi_store(), style="bram")
