"""Line buffers: tap k delays the entry stream by (k + 1) * depth advances."""

import random
import re

import pytest
from amaranth.back import rtlil
from amaranth.hdl import unsigned

from dptbd.hw.line_buffer import RAM_STYLES, LineBuffer
from helpers.dp16kd_model import DP16KDModel
from helpers.hw_harness import refused, simulate


def check_taps(dut, depth, taps, back_to_back):
    """Random advances, at most every other cycle or (``back_to_back``) also in consecutive
    cycles, as the pipeline advances at full rate: tap k is the entry (k + 1) * depth
    advances earlier, 0 before."""
    rng = random.Random(depth * 10 + taps)
    entries = [rng.randrange(1 << 10) for _ in range(depth * (taps + 3))]
    seen = []

    async def bench(ctx):
        index = 0
        advanced = False
        while index < len(entries) or advanced:
            if advanced:  # the cycle after an advance: present the entry, read the taps
                ctx.set(dut.data_in, entries[index])
                seen.append([ctx.get(dut.taps[k]) for k in range(taps)])
                index += 1
            else:
                ctx.set(dut.data_in, rng.randrange(1 << 10))  # ignored
            advance = (index < len(entries) and (back_to_back or not advanced)
                       and rng.random() < 0.8)
            ctx.set(dut.advance, advance)
            advanced = advance
            await ctx.tick()

    simulate(dut, bench)
    assert len(seen) == len(entries)
    for n, taps_out in enumerate(seen):
        for k, value in enumerate(taps_out):
            back = n - (k + 1) * depth
            assert value == (entries[back] if back >= 0 else 0), f"entry {n}, tap {k}"


@pytest.mark.parametrize("ram_style, registered_read, banked_read", [
    *[(style, registered, False) for style in RAM_STYLES if style != "dp16kd"
      for registered in (False, True)],
    ("distributed", False, True)])
@pytest.mark.parametrize("depth, taps, back_to_back", [
    (5, 2, False), (7, 4, False), (3, 1, False), (3, 2, True), (4, 1, True), (128, 2, True),
    (37, 3, True)])
def test_taps_are_delayed_rows(depth, taps, back_to_back, registered_read, ram_style,
                               banked_read):
    """The same taps with a registered read and with the memory in LUT RAM (a synthesis
    attribute only) or in registered banks."""
    check_taps(LineBuffer(unsigned(10), depth=depth, taps=taps, registered_read=registered_read,
                          ram_style=ram_style, banked_read=banked_read),
               depth, taps, back_to_back)


@pytest.mark.parametrize("depth, taps, back_to_back", [
    (4, 1, True), (6, 2, False), (8, 2, True), (10, 1, True), (34, 3, True), (64, 1, True),
    (96, 2, True), (128, 2, True), (128, 2, False)])
def test_interleaved_read_gives_the_same_taps(depth, taps, back_to_back):
    """The interleaved read ahead: halves of one bank (depth 4 … 10, a power of two or not),
    of several banks with a short last one (34: 16 + 1 words per half), of whole banks (64,
    96: three per half, 128: four per half)."""
    check_taps(LineBuffer(unsigned(10), depth=depth, taps=taps, ram_style="distributed",
                          interleaved_read=True),
               depth, taps, back_to_back)


@pytest.mark.parametrize("depth, taps, back_to_back", [
    (3, 1, True), (3, 2, False), (5, 2, True), (37, 3, True), (128, 2, True), (128, 2, False),
    (1030, 1, True)])
def test_dp16kd_style_with_a_model_of_the_block_ram_gives_the_same_taps(depth, taps,
                                                                        back_to_back):
    """ECP5 DP16KDs read a cycle ahead through their output register, with a behavioural
    DP16KD: 18 x 1024 (one or two side by side for 10 to 30 bits) and, at 1030 words,
    9 x 2048."""
    check_taps(LineBuffer(unsigned(10), depth=depth, taps=taps, ram_style="dp16kd",
                          dp16kd=DP16KDModel),
               depth, taps, back_to_back)


def test_dp16kd_style_reads_from_registers_through_the_output_register():
    """Every DP16KD reads through its output register (enabled every cycle), its read
    address from a register and its read enable the advance."""
    text = rtlil.convert(LineBuffer(unsigned(14), depth=640, taps=2, ram_style="dp16kd"))
    found = re.findall(r"cell \\DP16KD \S+\n(.*?)\n\s*end", text, flags=re.S)
    assert len(found) == 2                          # 28 bits: two 18 x 1024
    for body in found:
        assert 'parameter \\REGMODE_B "OUTREG"' in body
        assert "parameter \\DATA_WIDTH_B 18" in body
        assert "connect \\CEB \\advance" in body and "connect \\OCEB 1'1" in body
        assert "connect \\ADB4 \\ahead [0]" in body


def test_refuses_degenerate_sizes():
    with refused(ValueError, match=r"^depth must be an integer in \[2, inf\), got 1$"):
        LineBuffer(unsigned(4), depth=1, taps=2)
    with refused(ValueError, match=r"^depth must be an integer in \[3, inf\), got 2$"):
        LineBuffer(unsigned(4), depth=2, taps=2, registered_read=True)
    with refused(ValueError, match=r"^depth must be an integer in \[3, inf\), got 2$"):
        LineBuffer(unsigned(4), depth=2, taps=2, ram_style="distributed", banked_read=True)
    with refused(ValueError, match=r"^banked_read needs ram_style='distributed' and no "
                                   r"registered_read$"):
        LineBuffer(unsigned(4), depth=4, taps=1, banked_read=True)
    with refused(ValueError, match=r"^depth must be an even integer in \[4, inf\) with "
                                   r"interleaved_read, got 7$"):
        LineBuffer(unsigned(4), depth=7, taps=2, ram_style="distributed", interleaved_read=True)
    with refused(ValueError, match=r"^depth must be an even integer in \[4, inf\) with "
                                   r"interleaved_read, got 2$"):
        LineBuffer(unsigned(4), depth=2, taps=2, ram_style="distributed", interleaved_read=True)
    for options in ({}, {"ram_style": "distributed", "registered_read": True},
                    {"ram_style": "distributed", "banked_read": True}):
        with refused(ValueError, match=r"^interleaved_read needs ram_style='distributed', no "
                                       r"registered_read and no banked_read$"):
            LineBuffer(unsigned(4), depth=8, taps=1, interleaved_read=True, **options)
    with refused(ValueError, match=r"^taps must be an integer in \[1, inf\), got 0$"):
        LineBuffer(unsigned(4), depth=4, taps=0)
    with refused(ValueError, match=r"^depth must be an integer in \[3, inf\), got 2$"):
        LineBuffer(unsigned(4), depth=2, taps=2, ram_style="dp16kd")
    with refused(ValueError, match=r"^ram_style='dp16kd' reads through the block RAM's "
                                   r"output register: no registered_read$"):
        LineBuffer(unsigned(4), depth=8, taps=1, ram_style="dp16kd", registered_read=True)
    with refused(ValueError, match=r"^banked_read needs ram_style='distributed' and no "
                                   r"registered_read$"):
        LineBuffer(unsigned(4), depth=8, taps=1, ram_style="dp16kd", banked_read=True)
    with refused(ValueError, match=r"^interleaved_read needs ram_style='distributed', no "
                                   r"registered_read and no banked_read$"):
        LineBuffer(unsigned(4), depth=8, taps=1, ram_style="dp16kd", interleaved_read=True)
    with refused(ValueError, match=r"^ram_style must be one of \(None, 'distributed', "
                                   r"'dp16kd'\), got 'block'$"):
        LineBuffer(unsigned(4), depth=4, taps=1, ram_style="block")
