"""``FrameMonitor`` against a Python reference of its rule, and against the core's
``Controller`` (both must agree on every restart).

Glasgow's pattern: ``cases()`` yields beat sequences ``[(first, last), …]`` for a W x H
raster, each with one kind of fault (or none); ``ref_faults`` is the rule of
``docs/integration.md`` written in Python; ``rtl_faults`` runs the gateware with random
gaps between beats.
"""

import random

import pytest
from amaranth.hdl import Elaboratable, Module

from dptbd.hw.controller import Controller
from dptbd.hw.frame_monitor import FrameMonitor
from dptbd.hw.register_map import FAULTS
from hw_harness import simulate
from seg_harness import make_config

W, H = 5, 3


def frame(width=W, height=H, sof=True):
    beats = [(0, c == width - 1) for _r in range(height) for c in range(width)]
    beats[0] = (int(sof), beats[0][1])
    return beats


def cases():
    """(name, beats, faults expected in total)."""
    clean = frame() * 3
    yield "clean", clean, {}
    yield "cut mid-line", frame()[:7] + frame(), {"sof_unexpected": 1, "line_length": 0}
    yield "whole lines missing", frame()[:W] + frame(), {"frame_short": 1}
    yield "missing sof", frame() + frame(sof=False) + frame(), {"frame_long": 1}
    yield "starts without sof", frame(sof=False) + frame(), {"frame_long": 1}
    early = frame()
    early[2] = (0, 1)                                        # tlast on column 2
    yield "early tlast", early + frame(), {"line_length": 1}
    late = frame()
    late[W - 1] = (0, 0)                                     # no tlast on column W-1
    yield "missing tlast", late + frame(), {"line_length": 1}
    longer = frame() + [(0, 0), (0, 0)] + frame()            # two extra beats
    yield "two beats too many", longer, {"frame_long": 1, "sof_unexpected": 1}


def ref_faults(beats, width=W, height=H):
    """Fault pulses per beat (dicts), by the controller's counting rule."""
    col = row = 0
    at_start = True
    out = []
    for first, last in beats:
        restart = first and not at_start
        faults = {"sof_unexpected": restart and col != 0, "frame_short": restart and col == 0,
                  "frame_long": at_start and not first}
        if restart:
            col = row = 0
        faults["line_length"] = bool(last) != (col == width - 1)
        out.append({k: int(v) for k, v in faults.items()})
        end = col == width - 1 and row == height - 1
        col, row = (0, 0 if row == height - 1 else row + 1) if col == width - 1 else (col + 1, row)
        at_start = end
    return out


def rtl_faults(beats, seed=0):
    """Fault pulses of the gateware per accepted beat, with random idle cycles between
    beats; also the controller's ``resync`` per beat."""
    cfg = make_config(width=W, height=H)
    dut = FrameMonitor(cfg)
    ctl = Controller(cfg)
    rng = random.Random(seed)
    got, resyncs = [], []

    class Both(Elaboratable):
        def elaborate(self, platform):
            m = Module()
            m.submodules.mon, m.submodules.ctl = dut, ctl
            m.d.comb += [ctl.accept.eq(dut.accept), ctl.first.eq(dut.first)]
            return m

    async def bench(ctx):
        for first, last in beats:
            ctx.set(dut.accept, 0)
            while rng.random() < 0.3:                      # idle cycles: no fault pulses
                await ctx.tick()
                assert not any(ctx.get(dut.faults[k]) for k in FAULTS)
            ctx.set(dut.accept, 1)
            ctx.set(dut.first, first)
            ctx.set(dut.last, last)
            resyncs.append(ctx.get(ctl.resync))
            await ctx.tick()                               # the pulses of this beat
            got.append({k: ctx.get(dut.faults[k]) for k in FAULTS})

    simulate(Both(), bench)
    return got, resyncs


@pytest.mark.parametrize("name,beats,total", list(cases()), ids=[c[0] for c in cases()])
def test_frame_monitor_matches_reference(name, beats, total):
    want = ref_faults(beats)
    sums = {k: sum(f[k] for f in want) for k in FAULTS}
    assert sums == {k: total.get(k, 0) for k in FAULTS}, name
    got, resyncs = rtl_faults(beats, seed=len(beats))
    assert got == want
    # the monitor restarts exactly where the core's controller resynchronises
    assert resyncs == [f["sof_unexpected"] | f["frame_short"] for f in want]
