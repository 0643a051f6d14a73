"""AxiStateStore against a one-cycle SRAM, behind the strict random-latency AXI4 memory.

A Python stand-in for DPCore's store traffic drives the adaptor: it accepts a pixel only
with ``ready``, reads ``(p + D) mod W*H`` for the pixel at raster position ``p``, writes
a random state to its own address exactly ``write_latency`` cycles later, and may
resynchronise (restart at position 0). Every read whose value the pipeline uses must
equal what a one-cycle SRAM would return.
"""

import random

import pytest

from dptbd.config import DPConfig
from dptbd.hw.axi_store import AxiStateStore
from dptbd.hw.axi_store.bus import RESP_DECERR, RESP_SLVERR
from dptbd.hw.schedule import read_ahead_distance
from dptbd.sim.axi4_memory import Axi4Memory
from helpers.dp16kd_model import DP16KDModel
from helpers.hw_harness import simulate

LATENCY = 14


def run_store(store, *, pixels, seed, latency=(0, 0), ready=1.0, valid=1.0, offer=1.0,
              resync_at=(), errors=None, base=None, write_latency=None, style="memory"):
    """Drive ``pixels`` accepted pixels through an AxiStateStore; returns (mismatches,
    checked reads, cycles, memory, error pulses)."""
    cfg = store.frame
    words = cfg.width * cfg.height
    ahead = read_ahead_distance(cfg)
    dut = AxiStateStore(store, write_latency=LATENCY, style=style,
                        dp16kd=DP16KDModel if style == "dp16kd" else None)
    memory = Axi4Memory(dut.axi, store, seed=seed, latency=latency, ready=ready, valid=valid,
                        errors=errors or {}, write_latency=write_latency)
    rng = random.Random(seed)
    # `ready` against the prefetcher's `available` and the write-behind's `room` (with
    # style "dp16kd" a register of the two a cycle ahead, low after a restart): "unsafe"
    # cycles it is high without them, "held" cycles it is low with them, "restarts"
    out = {"mismatches": [], "checked": 0, "cycles": 0, "errors": [0, 0], "unsafe": 0,
           "held": 0, "restarts": 0}
    width = len(dut.bus.read_data.as_value())

    async def bench(ctx):
        sram = [None] * words
        writes = {}                           # cycle -> (addr, data)
        position, write_addr, accepted, cycle = 0, -1, 0, 0
        unchecked_until = words - ahead       # first frame: reads unused below this
        if base is not None:
            ctx.set(dut.base, base)
        while accepted < pixels or writes:
            if cycle > 4 * pixels * (1 + latency[1]) + 20 * (write_latency or (0, 0))[1] + 2000:
                raise AssertionError(f"hang: {accepted}/{pixels} accepted after {cycle} cycles")
            offering = accepted < pixels and rng.random() < offer
            take = offering and ctx.get(dut.ready)
            gate = ctx.get(dut._reader.available) & ctx.get(dut._writer.room)
            out["unsafe"] += ctx.get(dut.ready) & ~gate & 1
            out["held"] += gate & ~ctx.get(dut.ready) & 1
            restart = take and accepted in resync_at and position != 0
            if restart:                       # a start frame: its reads are unused
                position, unchecked_until = 0, words - ahead   # until they wrap
            elif take and position == 0:
                unchecked_until = 0
            ctx.set(dut.bus.read_en, take)
            ctx.set(dut.restart, restart)
            out["restarts"] += restart
            if take:
                addr = (position + ahead) % words
                ctx.set(dut.bus.read_addr, addr)
                expected = sram[addr] if position >= unchecked_until else None
                writes[cycle + LATENCY] = (0 if position == 0 else write_addr + 1,
                                           rng.randrange(1 << width))
                write_addr = writes[cycle + LATENCY][0]
            write = writes.pop(cycle, None)
            ctx.set(dut.bus.write_en, write is not None)
            if write is not None:
                ctx.set(dut.bus.write_addr, write[0])
                ctx.set(dut.bus.write_data.as_value(), write[1])
            out["errors"][0] += ctx.get(dut.read_error)
            out["errors"][1] += ctx.get(dut.write_error)
            await ctx.tick()
            cycle += 1
            if take and expected is not None:     # a one-cycle read
                out["checked"] += 1
                got = ctx.get(dut.bus.read_data.as_value())
                if got != expected:
                    out["mismatches"].append((addr, expected, got))
            if write is not None:
                sram[write[0]] = write[1]
            if take:
                accepted += 1
                position = (position + 1) % words
        out["cycles"] = cycle
        out["sram"] = sram

    simulate(dut, bench, background=[memory.process()])
    return out, memory


@pytest.mark.parametrize("style", ["memory", "dp16kd"])
@pytest.mark.parametrize("data_bits, burst_beats", [(32, 2), (64, 4), (128, 2)])
def test_reads_equal_a_one_cycle_sram_at_zero_latency(data_bits, burst_beats, style):
    """Either prefetch FIFO (an Amaranth FIFO, ECP5 DP16KDs modelled)."""
    store = DPConfig(width=16, height=12).axi_store(data_bits=data_bits,
                                                    burst_beats=burst_beats)
    out, memory = run_store(store, pixels=4 * 192 + 37, seed=data_bits, style=style)
    assert out["mismatches"] == []
    assert out["checked"] == 4 * 192 + 37 - (192 - 17)   # all but the first frame's own
    # the prefetch ran ahead of the last pixel, by at most its FIFO
    per_beat = store.states_per_beat
    prefetched = memory.stats["read_beats"] * per_beat - 17 % per_beat
    depth = store.outstanding * burst_beats * per_beat
    assert 4 * 192 + 37 < prefetched <= 4 * 192 + 37 + depth


@pytest.mark.parametrize("latency, ready, valid, offer, seed", [
    ((0, 30), 0.5, 0.5, 0.9, 1),
    ((0, 600), 0.7, 0.6, 1.0, 2),
    ((100, 100), 1.0, 1.0, 0.8, 3),
])
@pytest.mark.parametrize("style", ["memory", "dp16kd"])
def test_random_latency_and_stalls_change_no_read(latency, ready, valid, offer, seed, style):
    store = DPConfig(width=16, height=12).axi_store(data_bits=64, burst_beats=4,
                                                    outstanding=2)
    out, _ = run_store(store, pixels=3 * 192 + 5, seed=seed, latency=latency, ready=ready,
                       valid=valid, offer=offer, style=style)
    assert out["mismatches"] == []
    assert out["checked"] == 3 * 192 + 5 - (192 - 17)
    assert (out["unsafe"], out["held"]) == (0, 0)


def test_a_read_waits_for_the_response_of_the_write_it_depends_on():
    """Slow write responses, immediate reads, a prefetch as deep as the frame allows: a read
    issued before the previous frame's write of its words was answered could return the
    old contents (the memory model applies a write only with its response)."""
    store = DPConfig(width=16, height=12).axi_store(data_bits=128, burst_beats=4,
                                                    outstanding=16)
    out, memory = run_store(store, pixels=4 * 192, seed=5, write_latency=(150, 400))
    assert out["mismatches"] == []
    assert out["checked"] == 4 * 192 - (192 - 17)
    assert out["cycles"] > 4 * 192 + 150          # the reads did wait


@pytest.mark.parametrize("style", ["memory", "dp16kd"])
def test_resynchronisations_restart_the_prefetch(style):
    store = DPConfig(width=16, height=12).axi_store(data_bits=64, burst_beats=4)
    out, _ = run_store(store, pixels=5 * 192, seed=7, latency=(0, 50), ready=0.8,
                       resync_at={100, 101, 103, 300, 301 + 192, 700}, style=style)
    assert out["mismatches"] == []
    # with the ready register at most the cycle after each restart held back (when it
    # drops no beat: not here)
    assert out["unsafe"] == 0 and out["restarts"] == 6
    assert out["held"] <= (0 if style == "memory" else 6)
    # checked: positions 175 … 191 of each start frame (17 x 4), then every pixel up to
    # the next resynchronisation (5 + 1 + 15 + 68)
    assert out["checked"] == 17 * 4 + 5 + 1 + 15 + 68


@pytest.mark.parametrize("code", [RESP_SLVERR, RESP_DECERR])
def test_error_responses_are_flagged_and_never_hang(code):
    """Beat 5 (words 10, 11) answers with an error: its read each frame (pixels 185, 377,
    569, 761) and the write burst of beats 4 … 7 each frame are flagged once each."""
    store = DPConfig(width=16, height=12).axi_store(data_bits=64, burst_beats=4)
    out, memory = run_store(store, pixels=4 * 192, seed=9, latency=(0, 20),
                            errors={5 * 8 + 3: code})
    assert out["errors"] == [4, 4]
    assert memory.stats["write_bursts"] >= 4 * 192 // 8 - 1
