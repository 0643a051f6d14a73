"""AxiWriteBehind: packing, burst cutting, the jump of a resynchronisation, ``written`` and
``room``, behind the strict AXI4 memory model."""

import random

import pytest

from dptbd.config import DPConfig
from dptbd.hw.axi_store.bus import RESP_SLVERR
from dptbd.hw.axi_store.write_behind import AxiWriteBehind
from dptbd.sim.axi4_memory import Axi4Memory, OneSided
from helpers.hw_harness import simulate


def run_writes(store, addresses, *, seed=0, latency=(0, 0), ready=1.0, valid=1.0, errors=None,
               base=None, tail=60, staged=False):
    """Write a random state to each address in turn, one per cycle while ``room`` allows,
    then idle ``tail`` cycles; return the memory, the data written and ``written`` /
    ``room`` / error pulses per cycle, the cycles of AW and W handshakes (``aw``, ``w``:
    (cycle, WLAST)) and, with
    ``staged``, ``room_next`` per cycle."""
    dut = AxiWriteBehind(store, in_flight=4, staged=staged)
    top = OneSided(dut, store)
    memory = Axi4Memory(top.axi, store, seed=seed, latency=latency, ready=ready, valid=valid,
                        errors=errors or {})
    rng = random.Random(seed)
    width = len(dut.write_data.as_value())
    data = [rng.randrange(1 << width) for _ in addresses]
    trace = {"written": [], "room": [], "room_next": [], "errors": 0, "aw": [], "w": []}

    async def bench(ctx):
        # like the pipeline: a write is "accepted" only while room is high and arrives
        # in_flight - 1 = 3 cycles later
        if base is not None:
            ctx.set(dut.base, base)
        due, accepted, step, idle = {}, 0, 0, 0
        while idle < tail:
            room = ctx.get(dut.room)
            trace["room"].append(room)
            if room and accepted < len(addresses):
                due[step + 3] = accepted
                accepted += 1
            k = due.pop(step, None)
            ctx.set(dut.write_en, k is not None)
            if k is not None:
                ctx.set(dut.write_addr, addresses[k])
                ctx.set(dut.write_data.as_value(), data[k])
            trace["errors"] += ctx.get(dut.error)
            if ctx.get(dut.aw.awvalid) and ctx.get(dut.aw.awready):
                trace["aw"].append(step)
            if ctx.get(dut.w.wvalid) and ctx.get(dut.w.wready):
                trace["w"].append((step, ctx.get(dut.w.wlast)))
            if staged:
                trace["room_next"].append(ctx.get(dut.room_next))
            await ctx.tick()
            trace["written"].append(ctx.get(dut.written))
            step += 1
            idle = idle + 1 if accepted == len(addresses) and not due else 0

    simulate(top, bench, background=[memory.process()])
    return memory, data, trace


def stored(memory, store, addr):
    """The state in slot ``addr`` of the memory."""
    slot_bytes = store.slot_bits // 8
    start = store.base_address + addr * slot_bytes
    value = int.from_bytes(bytes(memory.byte(start + k) for k in range(slot_bytes)), "little")
    return value


@pytest.mark.parametrize("staged", [False, True])
@pytest.mark.parametrize("data_bits, burst_beats", [(32, 2), (64, 4), (128, 16)])
def test_a_frame_is_written_in_aligned_bursts_and_slots(data_bits, burst_beats, staged):
    store = DPConfig(width=16, height=12).axi_store(data_bits=data_bits, burst_beats=burst_beats,
                                                    base_address=0x2000)
    memory, data, trace = run_writes(store, list(range(192)), seed=data_bits, staged=staged)
    beats = store.frame_beats
    expected = [("AW", 0x2000 + b * store.beat_bytes, min(burst_beats, beats - b))
                for b in range(0, beats, burst_beats)]
    assert memory.bursts == expected
    assert [stored(memory, store, a) for a in range(192)] == data
    assert trace["written"][-1] == 192                 # every pixel's write answered
    # staged, the AWs of 2-beat bursts a cycle later: the W FIFO of the same depth fills
    assert all(trace["room"]) != (staged and burst_beats == 2)


@pytest.mark.parametrize("staged", [False, True])
def test_a_resynchronisation_closes_the_open_burst_and_drops_the_partial_beat(staged):
    """Addresses 0 … 12 then, after a resync, 0 … 191: the burst of beats 4 … 5 (words 8 …
    11) is cut at 2 beats, word 12 (an unfinished beat) is never written, and the pixels
    answered count every write, the dropped one with the next burst."""
    store = DPConfig(width=16, height=12).axi_store(data_bits=64, burst_beats=4)
    addresses = list(range(13)) + list(range(192))
    memory, data, trace = run_writes(store, addresses, seed=4, staged=staged)
    assert memory.bursts[:3] == [("AW", 0, 4), ("AW", 32, 2), ("AW", 0, 4)]
    assert len(memory.bursts) == 2 + 96 // 4
    assert [stored(memory, store, a) for a in range(192)] == data[13:]
    assert trace["written"][-1] == 13 + 192


@pytest.mark.parametrize("staged", [False, True])
def test_random_latency_and_stalls_keep_every_word(staged):
    store = DPConfig(width=16, height=12).axi_store(data_bits=64, burst_beats=4, outstanding=2)
    memory, data, trace = run_writes(store, list(range(192)) * 2, seed=6, latency=(0, 80),
                                     ready=0.3, valid=0.5, tail=3000, staged=staged)
    assert [stored(memory, store, a) for a in range(192)] == data[192:]
    assert trace["written"][-1] == 384
    assert not all(trace["room"])                      # the FIFO did fill: room went low
    if staged:                                         # room_next is room a cycle ahead
        assert trace["room_next"][:-1] == trace["room"][1:]


def test_staged_descriptors_send_each_aw_one_cycle_later():
    """``staged`` (the ECP5 build's): the same bursts and bytes, each AW handshake exactly
    one cycle after the unstaged build's (a zero-latency memory, always ready)."""
    store = DPConfig(width=16, height=12).axi_store(data_bits=64, burst_beats=4)
    addresses = list(range(13)) + list(range(192))
    plain, data, plain_trace = run_writes(store, addresses, seed=4)
    staged, _, staged_trace = run_writes(store, addresses, seed=4, staged=True)
    assert staged.bursts == plain.bursts
    assert [stored(staged, store, a) for a in range(192)] == data[13:]
    assert len(plain_trace["aw"]) == 2 + 96 // 4
    assert staged_trace["aw"] == [cycle + 1 for cycle in plain_trace["aw"]]
    assert staged_trace["w"] == [(cycle + 1, last) for cycle, last in plain_trace["w"]]
    assert staged_trace["room"] == plain_trace["room"]


def test_an_error_response_is_flagged_once_per_burst():
    store = DPConfig(width=16, height=12).axi_store(data_bits=64, burst_beats=4)
    _, _, trace = run_writes(store, list(range(192)), errors={0x44: RESP_SLVERR})
    assert trace["errors"] == 1
    assert trace["written"][-1] == 192


@pytest.mark.parametrize("p, data_bits", [(2, 32), (2, 64), (4, 64), (4, 128)])
def test_a_word_of_p_states_fills_p_consecutive_slots(p, data_bits):
    """At P pixels per clock word ``a`` (P states, state 0 in the low bits) lands in slots
    ``P*a`` … ``P*a + P - 1``: the byte layout of P = 1, each state zero-extended in its
    slot; bursts as at P = 1."""
    cfg = DPConfig(width=16, height=12, pixels_per_clock=p).build_config()   # 16-bit slots
    store = cfg.axi_store(data_bits=data_bits, burst_beats=4, base_address=0x1000)
    words = store.frame_words
    memory, data, trace = run_writes(store, list(range(words)), seed=p)
    bits = cfg.state_bits
    assert [stored(memory, store, a) for a in range(192)] == [
        data[a // p] >> (a % p * bits) & ((1 << bits) - 1) for a in range(192)]
    assert memory.bursts == [("AW", 0x1000 + b * store.beat_bytes,
                              min(4, store.frame_beats - b))
                             for b in range(0, store.frame_beats, 4)]
    assert trace["written"][-1] == words
