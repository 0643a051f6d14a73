"""cocotb test of ``dptbd_dp`` built with ``--state-store axi`` (``DPPipelineAxi``) on Icarus,
its state in cocotbext-axi's ``AxiRam``, scored against the golden model bit for bit.

Never imported outside a simulator; the job comes from the environment as for
:mod:`dptbd.sim.benches.dp` (``DPTBD_SIM_JOB``: ``config``, ``store`` (the
:meth:`DPConfig.axi_store` fields), ``pause`` (probability of a pause on every AXI channel
of the RAM and on the input and output streams), ``seed``, ``summary``;
``DPTBD_SIM_SCENE``: the frames).

``run_scene_axi_ram``
    Stream every frame with random pauses on the video input, the state output and all
    five AXI channels, score every output word, and check in every cycle after reset that
    the AXI valid / ready outputs, ``pixels__ready`` and ``states__valid`` are 0 or 1 (no X:
    Icarus is 4-state) and that ``read_error`` / ``write_error`` stay 0. ``AxiRam`` itself
    asserts that no burst crosses a 4 KB boundary. At P = 2 or 4 pixels per clock the
    input is beats of P pixels and each output beat is scored per pixel
    (:func:`dptbd.sim.rtl.check.beat_state_words`).
"""

from __future__ import annotations

import cocotb
from cocotb.triggers import RisingEdge
from cocotbext.axi import AxiBus, AxiRam

from dptbd.sim.benches import dp as tb_dp
from dptbd.sim.benches.drivers import (StreamMonitor, StreamSink, StreamSource, pause_generator,
                                     start_in_reset)
from dptbd.sim.scoreboard import Scoreboard, expected_words
from dptbd.sim.stimulus import pack_pixels

#: Outputs that must never be X or Z after reset.
CHECKED_OUTPUTS = ("pixels__ready", "states__valid", "m_axi_state_arvalid",
                   "m_axi_state_awvalid", "m_axi_state_wvalid", "m_axi_state_rready",
                   "m_axi_state_bready", "read_error", "write_error")


def _pauses(probability: float, seed: int):
    """A seeded random pause generator (never pausing at probability 0)."""
    return pause_generator({"kind": "random", "probability": probability, "seed": seed}
                           if probability else None)


@cocotb.test()
async def run_scene_axi_ram(dut):
    """The scene through the AXI-store build with AxiRam, bit-exact and X-free."""
    job, cfg, frames = tb_dp.load_job()
    store = cfg.axi_store(**job["store"])
    pause, seed = float(job.get("pause", 0.0)), int(job.get("seed", 0))
    ram = AxiRam(AxiBus.from_prefix(dut, "m_axi_state"), dut.clk, dut.rst,
                 size=store.base_address + store.frame_bytes)
    channels = (ram.write_if.aw_channel, ram.write_if.w_channel, ram.write_if.b_channel,
                ram.read_if.ar_channel, ram.read_if.r_channel)
    for k, channel in enumerate(channels):
        if pause:
            channel.set_pause_generator(_pauses(pause, seed * 10 + k))
    bench = tb_dp.Bench(dut, job, cfg)
    bench.cycles = await start_in_reset(
        dut, bench.period_ns, dut.states__ready,
        {"segment_frames": cfg.segment_frames, "state_base": store.base_address})
    bench.source = StreamSource(dut.clk, dut.pixels__valid, dut.pixels__ready,
                                dut.pixels__payload, cycles=bench.cycles, reset=dut.rst,
                                pause=_pauses(pause, seed * 10 + 7))
    bench.sink = StreamSink(dut.clk, dut.states__ready,
                            pause=_pauses(pause, seed * 10 + 8) if pause else None)
    bench.monitor = StreamMonitor(dut.clk, dut.states__valid, dut.states__ready,
                                  dut.states__payload, _per_pixel(cfg, bench._received),
                                  cycles=bench.cycles, reset=dut.rst)
    bad = []

    async def watch():
        while True:
            await RisingEdge(dut.clk)
            for name in CHECKED_OUTPUTS:
                value = getattr(dut, name).value
                if not value.is_resolvable:
                    bad.append(f"{name} = {value} in cycle {bench.cycles.now()}")
                elif name.endswith("_error") and int(value):
                    bad.append(f"{name} high in cycle {bench.cycles.now()}")

    cocotb.start_soon(watch())
    scoreboard = Scoreboard(cfg, expected_words(cfg, frames))
    bench.score_with(scoreboard)
    words = _input_words(cfg, frames)
    bench.source.send(words)
    finished = await bench.wait_done(scoreboard, 20 * len(words))
    summary = {
        "test": "run_scene_axi_ram",
        "verdict": "bit-exact" if scoreboard.done and not bad else
        ("mismatch" if scoreboard.failed or bad else "timeout"),
        "report": scoreboard.report() if finished else f"timeout: {scoreboard.report()}",
        "x_or_error": bad[:10],
        "pixels": len(words) * cfg.pixels_per_clock,
        "outputs": bench.monitor.count,
    }
    bench.write_summary(summary)
    assert not bad, bad[:10]
    assert summary["verdict"] == "bit-exact", summary["report"]


def _input_words(cfg, frames) -> list[int]:
    """The ``pixels`` payloads: one per pixel at P = 1, one per beat of P pixels at P > 1."""
    p = cfg.pixels_per_clock
    if p == 1:
        return pack_pixels(cfg, frames)
    from dptbd.hw.wide import pack_beat
    flat = [[int(v) for v in frame.ravel()] for frame in frames]
    return [pack_beat(cfg, frame[i:i + p], i == 0) for frame in flat
            for i in range(0, len(frame), p)]


def _per_pixel(cfg, receive):
    """``receive(word, cycle)`` per pixel: at P > 1 each ``states`` beat split into the P
    states a P = 1 design would give."""
    if cfg.pixels_per_clock == 1:
        return receive
    import numpy as np
    from dptbd.sim.rtl.check import beat_state_words
    from dptbd.sim.verilator import beat_words

    def split(word: int, cycle: int) -> None:
        per_beat = max(1, -(-int(word).bit_length() // 64))
        rows = beat_words([int(word)], per_beat)
        for state in np.asarray(beat_state_words(cfg, rows)).reshape(-1):
            receive(int(state), cycle)
    return split
