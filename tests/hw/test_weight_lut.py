"""Weight LUT: default codes, M lookups per cycle, the write port and its timing.

Every behavioural test runs for both storage styles (``lut_style`` "bram" and "logic"),
which must behave identically.
"""

import random
import shutil

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.weights import plain_weights
from dptbd.hw.weight_lut import LUT_STYLES, WeightLUT, resolve_lut_style
from helpers.hw_harness import assert_verilator_lints_clean, refused, simulate
from helpers.refusals import whole

STYLES = ("bram", "logic")


async def lookup(ctx, dut, cfg, directions):
    """Issue one lookup per move and return the codes one cycle later."""
    for move in range(cfg.n_moves):
        ctx.set(dut.direction[move], directions[move])
    await ctx.tick()
    return [ctx.get(dut.code[move]) for move in range(cfg.n_moves)]


@pytest.mark.parametrize("style", STYLES)
@pytest.mark.parametrize("radius, frac", [(1, 8), (2, 3)])
def test_default_contents_are_the_config_codes(radius, frac, style):
    cfg = DPConfig(radius=radius, weight_frac_bits=frac)
    dut = WeightLUT(cfg, lut_style=style)
    assert dut.lut_style == style
    codes = cfg.weight_codes
    rng = random.Random(radius)

    async def bench(ctx):
        for row in range(cfg.n_moves + 1):
            got = await lookup(ctx, dut, cfg, [row] * cfg.n_moves)
            assert got == codes[row].tolist(), f"row {row}"
        for _ in range(20):  # each move looks up its own row independently
            rows = [rng.randrange(cfg.n_moves + 1) for _ in range(cfg.n_moves)]
            got = await lookup(ctx, dut, cfg, rows)
            assert got == [int(codes[r, m]) for m, r in enumerate(rows)]

    simulate(dut, bench)


@pytest.mark.parametrize("style", STYLES)
@pytest.mark.parametrize("radius", [1, 2])
def test_direction_above_m_reads_the_start_row(radius, style):
    """Codes M+1 … 2**B_d − 1 (never written by the pipeline; an external store may hold
    them) read row M, the START row: c[min(d, M), m] (``docs/arithmetic.md`` §3)."""
    moves = (2 * radius + 1) ** 2
    weights = np.random.default_rng(radius).random((moves + 1, moves))
    cfg = DPConfig(radius=radius, weight_frac_bits=6, weights=weights)
    dut = WeightLUT(cfg, lut_style=style)
    codes = cfg.weight_codes
    assert len(np.unique(codes[:, 0])) > 2      # rows differ: a wrong row would show
    top = (1 << cfg.direction_bits) - 1         # 15 for r = 1, 31 for r = 2
    rng = random.Random(10 + radius)

    async def bench(ctx):
        for d in range(moves + 1, top + 1):
            got = await lookup(ctx, dut, cfg, [d] * moves)
            assert got == codes[moves].tolist(), f"direction {d}"
        for _ in range(20):   # mixed in-range and out-of-range codes, per move
            rows = [rng.randrange(top + 1) for _ in range(moves)]
            got = await lookup(ctx, dut, cfg, rows)
            assert got == [int(codes[min(r, moves), m]) for m, r in enumerate(rows)]

    simulate(dut, bench)


@pytest.mark.parametrize("style", STYLES)
@pytest.mark.parametrize("frac", [4, 0])
def test_writes_clamp_and_ignore_bad_addresses(frac, style):
    """Codes 0 … 2**F in F+1 bits, a write above 2**F stored as 2**F (F = 4: 17 … 31);
    F = 0 (the binary-LUT build): both 1-bit codes are stored as written."""
    cfg = DPConfig(radius=1, weight_frac_bits=frac)
    dut = WeightLUT(cfg, lut_style=style)
    moves = cfg.n_moves
    rng = random.Random(3)
    table = cfg.weight_codes.astype(np.int64).copy()
    clamped = 0

    async def bench(ctx):
        nonlocal clamped
        for _ in range(60):
            address = rng.randrange((moves + 1) * moves + 5)
            code = rng.randrange(2 << frac)
            ctx.set(dut.write_en, 1)
            ctx.set(dut.write_addr, address) if address < 128 else None
            ctx.set(dut.write_data, code)
            await ctx.tick()
            if address < (moves + 1) * moves:
                table[address // moves, address % moves] = min(code, 1 << frac)
                clamped += code > 1 << frac
        ctx.set(dut.write_en, 0)
        await ctx.tick()
        for row in range(moves + 1):
            got = await lookup(ctx, dut, cfg, [row] * moves)
            assert got == table[row].tolist(), f"row {row}"
        assert (clamped > 0) == (frac > 0), "F > 0 must exercise the clamp"

    simulate(dut, bench)


@pytest.mark.skipif(shutil.which("verilator") is None, reason="needs Verilator")
@pytest.mark.parametrize("style", STYLES)
@pytest.mark.parametrize("radius, frac", [(1, 0), (1, 8), (2, 0)])
def test_verilog_lints_clean(tmp_path, radius, frac, style):
    """Verilator ``-Wall`` (the project's waivers) on the LUT alone. F = 0: the largest code
    2**F = 1 is the 1-bit write port's maximum, so the write has no clamp (a constant
    ``write_data > 1`` is Verilator's CMPCONST); F = 8 keeps its comparator."""
    from amaranth.back import rtlil, verilog

    lut = WeightLUT(DPConfig(radius=radius, weight_frac_bits=frac), lut_style=style)
    (tmp_path / "lut.v").write_text(verilog.convert(lut, name="weight_lut", emit_src=False))
    assert_verilator_lints_clean(tmp_path / "lut.v", "weight_lut")
    text = rtlil.convert(WeightLUT(DPConfig(radius=radius, weight_frac_bits=frac),
                                   lut_style=style))
    assert text.count("cell $gt ") == (frac > 0)


@pytest.mark.parametrize("style", STYLES)
def test_write_is_seen_by_lookups_two_cycles_later(style):
    """Write in cycle c; lookups issued in c and c+1 see the old code, c+2 the new one.

    The pipeline issues a pixel's lookups 2 cycles after accepting it, so a pixel accepted
    in cycle c or later uses the new code.
    """
    cfg = DPConfig(radius=1, weights=plain_weights(1))
    dut = WeightLUT(cfg, lut_style=style)
    address = cfg.lut_address(4, 7)

    async def bench(ctx):
        for move in range(cfg.n_moves):
            ctx.set(dut.direction[move], 4)
        seen = []
        for cycle in range(5):
            ctx.set(dut.write_en, cycle == 1)
            ctx.set(dut.write_addr, address)
            ctx.set(dut.write_data, 17)
            await ctx.tick()
            seen.append(ctx.get(dut.code[7]))  # lookup issued in `cycle`
        assert seen == [256, 256, 256, 17, 17]

    simulate(dut, bench)


def test_auto_style_is_logic_for_radius_1_and_bram_for_radius_2():
    assert LUT_STYLES == ("auto", "bram", "logic")
    assert resolve_lut_style(DPConfig(radius=1)) == "logic"        # 10 entries per column
    assert resolve_lut_style(DPConfig(radius=2)) == "bram"         # 26 entries per column
    assert resolve_lut_style(DPConfig(radius=2), "logic") == "logic"
    for radius, style in [(1, "logic"), (2, "bram")]:
        lut = WeightLUT(DPConfig(radius=radius), lut_style="auto")
        assert lut.lut_style == style

        async def bench(ctx):
            await ctx.tick()

        simulate(lut, bench)   # elaborated, so no UnusedElaboratable warning


@pytest.mark.parametrize("bad", ["BRAM", "registers", "", None, 1])
def test_unknown_style_is_refused_naming_the_parameter(bad):
    with refused(ValueError, match=whole(f"lut_style must be one of 'auto', 'bram', 'logic', "
                                         f"got {bad!r}")):
        WeightLUT(DPConfig(), lut_style=bad)


@pytest.mark.parametrize("style, read_ports, attribute", [("bram", 9, False),
                                                          ("logic", 90, True)])
def test_bram_style_reads_each_column_once_and_logic_style_every_code(style, read_ports,
                                                                      attribute):
    """"bram": one read port per column memory, at the direction; "logic": a column memory
    marked for logic, read at every row by constant-address ports (the read multiplexer is
    then logic of our own)."""
    from amaranth.back import rtlil

    text = rtlil.convert(WeightLUT(DPConfig(radius=1), lut_style=style))
    assert text.count("cell $memrd_v2 ") == read_ports
    assert ('ram_style "logic"' in text) == attribute

@pytest.mark.parametrize("radius, frac", [(1, 4), (1, 0), (2, 3)])
def test_predecoded_write_matches_the_case_every_cycle(radius, frac):
    """``write_decode="predecoded"`` (logic storage) against the case's LUT, driven by the
    same random writes (every address of the port, beyond the table too, the enable on
    and off) and lookups: the same codes in every cycle, through a reset that drops a
    pending write."""
    from amaranth.hdl import Module, ResetInserter, Signal
    cfg = DPConfig(radius=radius, weight_frac_bits=frac)
    m = Module()
    reset = Signal()
    case = WeightLUT(cfg, lut_style="logic")
    predecoded = WeightLUT(cfg, lut_style="logic", write_decode="predecoded")
    m.submodules.case = ResetInserter(reset)(case)
    m.submodules.predecoded = ResetInserter(reset)(predecoded)
    rng = random.Random(radius * 10 + frac)
    addresses = list(range(1 << len(case.write_addr)))
    addresses = addresses * (1 if radius == 2 else 3)
    rng.shuffle(addresses)

    async def bench(ctx):
        changed = 0
        for cycle, address in enumerate(addresses):
            enable, code = rng.random() < 0.7, rng.randrange(2 << frac)
            directions = [rng.randrange(1 << cfg.direction_bits) for _ in range(cfg.n_moves)]
            ctx.set(reset, cycle % 97 == 50)
            for dut in (case, predecoded):
                ctx.set(dut.write_en, enable)
                ctx.set(dut.write_addr, address)
                ctx.set(dut.write_data, code)
                for move, direction in enumerate(directions):
                    ctx.set(dut.direction[move], direction)
            await ctx.tick()
            got = [ctx.get(predecoded.code[k]) for k in range(cfg.n_moves)]
            want = [ctx.get(case.code[k]) for k in range(cfg.n_moves)]
            assert got == want, (cycle, address)
            changed += want != [int(cfg.weight_codes[min(d, cfg.n_moves), k])
                                for k, d in enumerate(directions)]
        assert changed > len(addresses) // 4            # the lookups see written codes

    simulate(m, bench)


def test_predecoded_write_is_the_case_with_block_ram_storage():
    from amaranth.back import rtlil
    cfg = DPConfig(radius=1)
    assert rtlil.convert(WeightLUT(cfg, lut_style="bram", write_decode="predecoded")) == (
        rtlil.convert(WeightLUT(cfg, lut_style="bram")))


@pytest.mark.parametrize("bad", ["table", None])
def test_unknown_write_decode_is_refused(bad):
    with refused(ValueError, match=whole(f"write_decode must be one of ('case', "
                                         f"'predecoded'), got {bad!r}")):
        WeightLUT(DPConfig(), write_decode=bad)
