"""On-chip state store read a pixel ahead: raster reads one cycle after ``read_en`` from a
register, the word of a read off the raster, the DP16KD build's structure and the refusals."""

import random
import re

import pytest
from amaranth.back import rtlil

from dptbd.config import DPConfig
from dptbd.errors import ConfigError
from dptbd.hw.dp_pipeline import DPPipeline
from dptbd.hw.layouts import pack_state_word
from dptbd.hw.read_ahead_store import ReadAheadStore, check_read_ahead_store
from helpers.dp16kd_model import DP16KDModel
from helpers.hw_harness import simulate
from helpers.refusals import whole


def run_reads(dut, cfg, addresses, seed):
    """Read ``addresses`` in order (``next_read_addr`` = address + 1 mod W*H, as the
    controller gives it), ``read_en`` 70 % of the cycles, random writes among those
    addresses that never touch the word read ahead and not yet delivered (the pipeline
    writes a word long before it is read ahead, ``check_read_ahead_store``). Returns
    (got, model word at the read's cycle) per read."""
    rng = random.Random(seed)
    words = cfg.width * cfg.height
    model = [0] * words
    pairs = []
    targets = sorted(set(addresses))            # writes land where the reads will look

    async def bench(ctx):
        pending = None
        index = 0
        ahead = None                    # the address whose word is read ahead, not delivered
        while index < len(addresses) or pending is not None:
            read_en = index < len(addresses) and rng.random() < 0.7
            addr = addresses[index] if read_en else rng.randrange(words)
            following = (addr + 1) % words
            busy = {ahead, following if read_en else None}
            write_en = rng.random() < 0.5
            write_addr = rng.choice([a for a in targets if a not in busy])
            word = pack_state_word(cfg, rng.randrange(1 << cfg.energy_bits), rng.randrange(10))
            ctx.set(dut.bus.read_en, read_en)
            ctx.set(dut.bus.read_addr, addr)
            ctx.set(dut.next_read_addr, following)
            ctx.set(dut.bus.write_en, write_en)
            ctx.set(dut.bus.write_addr, write_addr)
            ctx.set(dut.bus.write_data.as_value(), word)
            if pending is not None:
                pairs.append((ctx.get(dut.bus.read_data.as_value()), pending))
                pending = None
            if read_en:
                pending = model[addr]
                ahead = following
                index += 1
            await ctx.tick()
            if write_en:
                model[write_addr] = word

    simulate(dut, bench)
    return pairs


def test_raster_reads_return_the_word_one_cycle_later():
    cfg = DPConfig(width=5, height=4, energy_bits=10)
    words = cfg.width * cfg.height
    addresses = [(7 + n) % words for n in range(3 * words)]   # wraps past the frame end
    pairs = run_reads(ReadAheadStore(cfg), cfg, addresses, seed=3)
    assert len(pairs) == len(addresses)
    # The first read has no read ahead (the store's power-up word, 0); every other follows
    # the raster and gets its own word.
    assert pairs[0][0] == 0
    for n, (got, want) in enumerate(pairs[1:], 1):
        assert got == want, f"read {n}: got {got:#x}, expected {want:#x}"


def test_off_raster_read_delivers_the_announced_word():
    cfg = DPConfig(width=5, height=4, energy_bits=10)
    dut = ReadAheadStore(cfg)
    words = [pack_state_word(cfg, 100 + a, a % 9) for a in range(20)]
    got = []

    async def bench(ctx):
        for a, w in enumerate(words):                      # fill the store
            ctx.set(dut.bus.write_en, 1)
            ctx.set(dut.bus.write_addr, a)
            ctx.set(dut.bus.write_data.as_value(), w)
            await ctx.tick()
        ctx.set(dut.bus.write_en, 0)
        for addr, following in [(3, 4), (4, 5), (12, 13), (13, 14), (14, 15)]:
            ctx.set(dut.bus.read_en, 1)
            ctx.set(dut.bus.read_addr, addr)
            ctx.set(dut.next_read_addr, following)
            await ctx.tick()
            got.append(ctx.get(dut.bus.read_data.as_value()))
        ctx.set(dut.bus.read_en, 0)
        for _ in range(3):                                  # held while no read
            await ctx.tick()
            assert ctx.get(dut.bus.read_data.as_value()) == got[-1]

    simulate(dut, bench)
    # The first read had nothing read ahead (0); 12 gets 5's word, announced by the read of 4.
    assert got == [0, words[4], words[5], words[13], words[14]]


def cells(dut):
    """The parameters and connections of every DP16KD cell in the RTLIL of ``dut``."""
    text = rtlil.convert(dut)
    return re.findall(r"cell \\DP16KD \S+\n(.*?)\n\s*end", text, flags=re.S)


@pytest.mark.parametrize("width, height, data_width, count", [
    (128, 128, 1, 14), (160, 128, 1, 28), (64, 64, 4, 4), (32, 32, 18, 1)])
def test_dp16kd_style_builds_the_widest_configuration_with_its_output_register(
        width, height, data_width, count):
    """One DP16KD per 14-bit word's share of the configuration that holds the frame
    (16384 x 1 at 128 x 128: 14; two banks at 160 x 128; 4096 x 4 at 64 x 64: 4)."""
    cfg = DPConfig(width=width, height=height).build_config()
    assert len(ReadAheadStore(cfg).bus.read_data.as_value()) == 14
    found = cells(ReadAheadStore(cfg, style="dp16kd"))
    assert len(found) == count
    for body in found:
        assert 'parameter \\REGMODE_B "OUTREG"' in body
        assert 'parameter \\REGMODE_A "NOREG"' in body
        assert (f"parameter \\DATA_WIDTH_B {data_width}" in body
                and f"parameter \\DATA_WIDTH_A {data_width}" in body)
        # The address register and the output register both advance with the read.
        assert "connect \\CEB \\bus__read_en" in body and "connect \\OCEB \\bus__read_en" in body
    assert cells(ReadAheadStore(cfg)) == []


@pytest.mark.parametrize("width, height, start", [(5, 4, 7), (64, 64, 4000),
                                                  (160, 128, 16384 - 30)])
def test_dp16kd_style_with_a_model_of_the_block_ram(width, height, start):
    """The DP16KD build's wiring (address and data bits, enables, the bank multiplexer of
    160 x 128 = 20480 words across its 16384-word boundary) with a behavioural DP16KD."""
    cfg = DPConfig(width=width, height=height, energy_bits=10)
    words = width * height
    addresses = [(start + n) % words for n in range(60)]
    pairs = run_reads(ReadAheadStore(cfg, style="dp16kd", dp16kd=DP16KDModel), cfg,
                      addresses, seed=5)
    assert len(pairs) == len(addresses) and pairs[0][0] == 0
    for n, (got, want) in enumerate(pairs[1:], 1):
        assert got == want, f"read {n}: got {got:#x}, expected {want:#x}"


def test_refuses_an_unknown_style():
    with pytest.raises(ValueError, match=whole(
            "style must be one of ('memory', 'dp16kd'), got 'bram'")):
        ReadAheadStore(DPConfig(width=8, height=8), style="bram")


def test_refuses_a_frame_without_a_cycle_for_the_read_ahead():
    # 7 x 3 at r = 1: 21 - 8 = 13 > 12, enough for DPCore; 13 - 1 = 12 is not for this store.
    cfg = DPConfig(width=7, height=3, radius=1)
    message = ("width=7 x height=3 is too small for the on-chip state store's read-ahead at "
               "radius=1: it needs width*height - radius*(width+1) - 1 > write latency 12 "
               "cycles, but it is 12; use a larger frame or the state store outside")
    with pytest.raises(ConfigError, match=whole(message)):
        check_read_ahead_store(cfg, 12)
    with pytest.raises(ConfigError, match=whole(message)):
        DPPipeline(cfg)
    check_read_ahead_store(cfg, 11)
