"""Window: cell (i, j) holds the previous state of (y + r - i, x + r - j); edge flags per move."""

import random

import pytest

from dptbd.config import DPConfig
from dptbd.hw.controller import inside_flags
from dptbd.hw.layouts import pack_state_word
from dptbd.hw.window import Window
from helpers.hw_harness import simulate


@pytest.mark.parametrize("width, height, radius", [(5, 4, 1), (7, 6, 2), (3, 5, 2)])
def test_cells_and_edge_flags(width, height, radius):
    cfg = DPConfig(width=width, height=height, radius=radius, energy_bits=12)
    dut = Window(cfg)
    side = 2 * radius + 1
    rng = random.Random(width * height)
    pixels = width * height
    # The state stream V[n] of two frames and a bit; position n of the stream holds word(n).
    words = [pack_state_word(cfg, rng.randrange(4096), rng.randrange(cfg.n_moves + 1))
             for _ in range(3 * pixels)]
    centres = list(range(pixels, 2 * pixels))  # every pixel of the middle frame
    moves = cfg.moves

    async def bench(ctx):
        for p in centres:
            y, x = divmod(p % pixels, width)
            for i in range(side):  # column x + r, rows y + r - i
                ctx.set(dut.column[i].as_value(), words[p + radius * (width + 1) - i * width])
            ctx.set(dut.shift, 1)
            ctx.set(dut.row_inside, inside_flags(y, height, radius))
            ctx.set(dut.col_inside, inside_flags(x, width, radius))
            await ctx.tick()
            ctx.set(dut.shift, 0)
            inside = ctx.get(dut.inside)
            cells = [ctx.get(dut.cells[m].as_value()) for m in range(cfg.n_moves)]
            if rng.random() < 0.3:  # an idle cycle must hold the window
                await ctx.tick()
                assert ctx.get(dut.inside) == inside
            for m, (dy, dx) in enumerate(moves):
                qy, qx = y - dy, x - dx
                expected_inside = 0 <= qy < height and 0 <= qx < width
                assert (inside >> m) & 1 == expected_inside, f"pixel {(y, x)} move {m}"
                if p - pixels >= side * width and expected_inside:  # window fully loaded
                    assert cells[m] == words[pixels + qy * width + qx], f"pixel {(y, x)} move {m}"
            centre = (side * side) // 2
            assert (inside >> centre) & 1

    simulate(dut, bench)
