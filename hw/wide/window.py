"""The P-pixel pipeline's window: r + 2 beats of each of the 2r + 1 rows, from which each lane
reads the P + 2r columns it needs."""

from __future__ import annotations

from amaranth.hdl import Cat, Module, Signal
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

from dptbd.config import DPConfig
from dptbd.hw.layouts import state_word_layout
from dptbd.hw.wide.layouts import beat_word_layout


def lane_column(cfg: DPConfig, lane: int, j: int) -> tuple[int, int]:
    """Where lane ``lane``'s window column j (predecessor column ``gP + lane + r - j``)
    sits in :class:`WideWindow`'s beat registers: ``(slot, word)``, slot 0 the newest beat
    (g + r), slot r + 1 the oldest (g - 1)."""
    p, r = cfg.pixels_per_clock, cfg.radius
    offset = p + lane + r - j           # columns from the first of beat g - 1, >= 0 as r <= P
    return r + 1 - offset // p, offset % p


class WideWindow(wiring.Component):
    """The window of P lanes: a shift register of r + 2 beat columns and the lanes'
    per-move image-edge flags.

    Members
    -------
    column : In(beat_word_layout(cfg)).array(2r+1)
        The new beat column: ``column[i]`` holds the P states of row ``y + r - i`` at beat
        ``g + r`` (the store's word and the line buffer's taps).
    shift : In(1)
        Shift ``column`` in at this cycle's edge.
    row_inside : In(2r+1)
        As :class:`~dptbd.hw.window.Window`'s: bit i set when row ``y + r - i`` is inside.
    first_beat, last_beat : In(1)
        Beat g is its row's first (g = 0) / last (g = W/P - 1).
    cells : Out(state_word_layout(cfg)).array(P, M)
        ``cells[k][m]``: the predecessor state of move m of lane k (pixel ``(y, gP + k)``),
        wires from the beat registers.
    inside : Out(M).array(P)
        Registered: bit m of ``inside[k]`` is set when that predecessor is inside the image.
    """

    def __init__(self, cfg: DPConfig):
        self._cfg = cfg
        side = 2 * cfg.radius + 1
        word = state_word_layout(cfg)
        super().__init__({
            "column": In(beat_word_layout(cfg)).array(side),
            "shift": In(1),
            "row_inside": In(side),
            "first_beat": In(1),
            "last_beat": In(1),
            "cells": Out(word).array(cfg.pixels_per_clock, side * side),
            "inside": Out(side * side).array(cfg.pixels_per_clock),
        })

    def elaborate(self, platform):
        m = Module()
        cfg = self._cfg
        p, r = cfg.pixels_per_clock, cfg.radius
        side = 2 * r + 1
        beats = [[Signal(beat_word_layout(cfg), name=f"beat{slot}_row{i}")
                  for i in range(side)] for slot in range(r + 2)]
        with m.If(self.shift):
            for i in range(side):
                m.d.sync += beats[0][i].eq(self.column[i])
                for slot in range(1, r + 2):
                    m.d.sync += beats[slot][i].eq(beats[slot - 1][i])
            for lane in range(p):
                bits = []
                for i in range(side):
                    for j in range(side):
                        column = lane + r - j          # relative to the beat's first pixel
                        col_ok = (~self.first_beat if column < 0 else
                                  ~self.last_beat if column >= p else 1)
                        bits.append(self.row_inside[i] & col_ok)
                m.d.sync += self.inside[lane].eq(Cat(*bits))
        for lane in range(p):
            for i in range(side):
                for j in range(side):
                    slot, word = lane_column(cfg, lane, j)
                    m.d.comb += self.cells[lane][i * side + j].eq(beats[slot][i][word])
        return m
