"""``FrameMonitor`` against a Python reference of its rule, and against the core's
``Controller`` (both must agree on every restart).

Glasgow's pattern: ``cases()`` yields beat sequences ``[(first, last), …]`` for a W x H
raster, each with one kind of fault (or none); ``ref_faults`` is the rule of
``docs/integration.md`` written in Python (``dptbd.sim.axi.stimulus``); ``rtl_faults`` runs the gateware with random
gaps between beats.
"""

import random

import numpy as np

import pytest
from amaranth.hdl import Elaboratable, Module

from dptbd.hw.controller import Controller
from dptbd.hw.frame_monitor import FrameMonitor
from dptbd.hw.register_map import FAULTS
from dptbd.sim.axi.stimulus import fault_counts, fault_pulses, fault_stretches, with_fault
from helpers.hw_harness import simulate
from helpers.seg_harness import make_config

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
    early[2] = (0, 1)                  # a stray tlast on column 2 splits line 0 in two
    yield "early tlast", early + frame(), {"line_length": 2}     # lines of 3 and 2 beats
    late = frame()
    late[W - 1] = (0, 0)                                     # no tlast on column W-1
    yield "missing tlast", late + frame(), {"line_length": 1}
    longer = frame() + [(0, 0), (0, 0)] + frame()            # two extra beats
    yield "two beats too many", longer, {"frame_long": 1, "sof_unexpected": 1}
    # one line too long / too short: one line_length event, not one per shifted line after
    wide = frame()
    wide[W - 1] = (0, 0)
    wide[W:W] = [(0, 1)]                                     # line 0 has W + 1 beats
    yield "one line a beat long", wide + frame(), {"line_length": 1, "frame_long": 1,
                                                   "sof_unexpected": 1}
    narrow = frame()
    del narrow[W - 1]
    narrow[W - 2] = (0, 1)                                   # line 0 has W - 1 beats
    yield "one line a beat short", narrow + frame(), {"line_length": 1, "sof_unexpected": 1}
    much = frame()
    much[W - 1] = (0, 0)
    much[W:W] = [(0, 0)] * (2 * W) + [(0, 1)]                # line 0 has 3W + 1 beats
    yield "one line far too long", much + frame(), {"line_length": 1, "frame_long": 1,
                                                    "sof_unexpected": 1}
    no_tlast = [(f, 0) for f, _ in frame() * 2]              # tlast never driven: one line
    yield "no tlast at all", no_tlast + frame(), {"line_length": 2}   # per frame (sof ends it)


def ref_faults(beats, no_sof=False):
    """Fault pulses per beat (dicts): :func:`dptbd.sim.axi.stimulus.fault_pulses`, the
    controller's counting rule written in Python."""
    first, last = zip(*beats)
    return fault_pulses(make_config(width=W, height=H), first, last, no_sof=no_sof)


def rtl_faults(beats, seed=0, no_sof=False, registered=False, width=W, height=H):
    """Fault pulses of the gateware per accepted beat, with random idle cycles between
    beats; also the controller's ``resync`` per beat. ``registered``: the ECP5 build's
    monitor (its comparisons as flags in registers)."""
    cfg = make_config(width=width, height=height)
    dut = FrameMonitor(cfg, registered=registered)
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
            ctx.set(dut.no_sof, no_sof)
            ctx.set(dut.first, first)
            ctx.set(dut.last, last)
            resyncs.append(ctx.get(ctl.resync))
            await ctx.tick()                               # the pulses of this beat
            got.append({k: ctx.get(dut.faults[k]) for k in FAULTS})

    simulate(Both(), bench)
    return got, resyncs


@pytest.mark.parametrize("registered", [False, True], ids=["generic", "registered"])
@pytest.mark.parametrize("name,beats,total", list(cases()), ids=[c[0] for c in cases()])
def test_frame_monitor_matches_reference(name, beats, total, registered):
    want = ref_faults(beats)
    sums = {k: sum(f[k] for f in want) for k in FAULTS}
    assert sums == {k: total.get(k, 0) for k in FAULTS}, name
    got, resyncs = rtl_faults(beats, seed=len(beats), registered=registered)
    assert got == want
    # the monitor restarts exactly where the core's controller resynchronises
    assert resyncs == [f["sof_unexpected"] | f["frame_short"] for f in want]


@pytest.mark.parametrize("kind", FAULTS)
def test_injected_faults_raise_one_pulse_of_their_class(kind):
    """``with_fault`` (the cocotb scenes' injector) raises exactly one pulse, of its class,
    on the gateware too."""
    cfg = make_config(width=W, height=H)
    frames = np.arange(3 * H * W).reshape(3, H, W) % 200
    beats = with_fault(cfg, frames, kind)
    assert fault_counts(cfg, beats) == {k: int(k == kind) for k in FAULTS}
    got, _ = rtl_faults([(int(f), int(lst)) for f, lst in zip(beats.first, beats.last)])
    assert {k: sum(g[k] for g in got) for k in FAULTS} == {k: int(k == kind) for k in FAULTS}


def test_with_fault_refusals():
    cfg = make_config(width=W, height=H)
    frames = np.zeros((2, H, W), dtype=int)
    with pytest.raises(ValueError, match=r"^fault kind must be one of \('sof_unexpected', "
                                         r"'frame_short', 'frame_long', 'line_length'\), "
                                         r"got 'nope'$"):
        with_fault(cfg, frames, "nope")
    with pytest.raises(ValueError, match=r"^a fault needs at least 2 frames, got 1$"):
        with_fault(cfg, frames[:1], "frame_long")


@pytest.mark.parametrize("registered", [False, True], ids=["generic", "registered"])
@pytest.mark.parametrize("name,beats,total", list(cases()), ids=[c[0] for c in cases()])
def test_no_sof_silences_frame_long_only(name, beats, total, registered):
    """With ``no_sof`` set, the same beats raise the same pulses but ``frame_long``."""
    want = ref_faults(beats, no_sof=True)
    assert want == [{**f, "frame_long": 0} for f in ref_faults(beats)]
    got, _ = rtl_faults(beats, seed=len(beats), no_sof=True, registered=registered)
    assert got == want


@pytest.mark.parametrize("width,height", [(3, 3), (4, 3), (3, 5), (5, 3)])
def test_registered_monitor_on_random_beats(width, height):
    """The registered monitor raises the reference's pulses on random beats (random start
    of frame and end of line bits) at the smallest raster sizes (W, H >= 3)."""
    rng = random.Random(width * 10 + height)
    beats = [(int(rng.random() < 0.15), int(rng.random() < 0.3)) for _ in range(300)]
    want = fault_pulses(make_config(width=width, height=height), *zip(*beats))
    assert sum(sum(p.values()) for p in want) > 0
    got, _ = rtl_faults(beats, seed=width + height, registered=True, width=width,
                        height=height)
    assert got == want


def test_source_without_tuser_raises_nothing_with_no_sof():
    """Frames without any start of frame: one frame_long per frame after the first W x H
    beats (and the very first beat) unless ``no_sof``; with it, none."""
    beats = frame(sof=False) * 4
    assert sum(f["frame_long"] for f in ref_faults(beats)) == 4
    got, _ = rtl_faults(beats, no_sof=True)
    assert sum(sum(g.values()) for g in got) == 0


def test_fault_stretches_give_one_pulse_of_each_class_in_its_own_stretch():
    cfg = make_config(width=W, height=H)
    frames = np.arange(4 + 2 * len(FAULTS))[:, None, None] * np.ones((1, H, W), dtype=np.int64)
    beats, starts = fault_stretches(cfg, frames)
    assert starts[0] == 4 * H * W and len(starts) == len(FAULTS)
    assert beats.pixel[:starts[0]].tolist() == np.repeat(np.arange(4), H * W).tolist()
    pulses = fault_pulses(cfg, beats.first, beats.last)
    fired = [(i, k) for i, p in enumerate(pulses) for k, v in p.items() if v]
    bounds = [*starts, len(beats)]
    assert [k for _, k in fired] == list(FAULTS)
    assert all(bounds[j] <= i < bounds[j + 1] for j, (i, _) in enumerate(fired))
