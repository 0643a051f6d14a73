"""cocotb test of ``dptbd_axi`` built with ``--state-store axi``
(:class:`~dptbd.hw.axi_store.top.AXITopStore`) on Icarus (4-state), its state in
cocotbext-axi's ``AxiRam`` on ``m_axi_state_*``, the lists scored against the golden model.

Never imported outside a simulator; the job comes from the environment as for
:mod:`dptbd.sim.benches.axi` (``DPTBD_SIM_JOB``: ``config``, ``store`` (the
:meth:`DPConfig.axi_store` fields), ``pause`` (probability of a pause on every AXI channel of
the RAM and on both streams), ``seed``, ``summary``; ``DPTBD_SIM_SCENE``: the frames).

``run_store_stream``
    From ``aresetn`` (the beats queued before it ends, offered as soon as the source
    leaves reset), stream every frame (one AXI-Stream frame per line, ``tuser[0]`` on pixel (0, 0)), take every list,
    compare each with the model's, read ``STATE_READ_ERRORS`` / ``STATE_WRITE_ERRORS`` /
    ``ERROR`` (0) and ``STATE_BASE_ACTIVE``, and check in every cycle after reset that no
    handshake output, no valid payload and ``irq`` is X or Z. ``AxiRam`` asserts the 4 KB
    rule. At P = 2 or 4 pixels per clock every ``s_axis_video`` beat carries P pixels
    (:func:`~dptbd.sim.verilator.axi.wide_beat_words`: pixel 0 in the low lane, ``tuser[0]``
    on a frame's first beat, ``tlast`` on a row's last).
"""

from __future__ import annotations

import json

import cocotb
from cocotb.triggers import RisingEdge, with_timeout
from cocotbext.axi import AxiBus, AxiRam, AxiStreamFrame

from dptbd.hw.register_map import constants_namespace
from dptbd.sim.axi.stimulus import clean_beats, expected_outputs
from dptbd.sim.benches.bus_drivers import AxiBench, line_frames
from dptbd.sim.benches.dp import load_job
from dptbd.sim.benches.drivers import pause_generator
from dptbd.sim.candidate_scoreboard import list_words

#: Outputs that must never be X or Z after reset, and (valid, payloads) pairs.
LEVELS = ("s_axis_video_tready", "m_axis_cand_tvalid", "irq", "s_axil_awready",
          "s_axil_wready", "s_axil_bvalid", "s_axil_arready", "s_axil_rvalid",
          "m_axi_state_arvalid", "m_axi_state_awvalid", "m_axi_state_wvalid",
          "m_axi_state_rready", "m_axi_state_bready")
PAYLOADS = (("m_axis_cand_tvalid", ("m_axis_cand_tdata", "m_axis_cand_tlast")),
            ("m_axi_state_arvalid", ("m_axi_state_araddr", "m_axi_state_arlen")),
            ("m_axi_state_awvalid", ("m_axi_state_awaddr", "m_axi_state_awlen")),
            ("m_axi_state_wvalid", ("m_axi_state_wdata", "m_axi_state_wlast")))


def video_frames(cfg, beats) -> list[AxiStreamFrame]:
    """The input as AXI-Stream frames of one line each: one pixel per element at P = 1
    (:func:`~dptbd.sim.benches.bus_drivers.line_frames`), one beat of P pixels at P = 2 or 4."""
    if cfg.pixels_per_clock == 1:
        return line_frames(beats, 0, len(beats))
    from dptbd.sim.verilator.axi import wide_beat_words
    frames, line = [], []
    for word in (int(w) for w in wide_beat_words(cfg, beats)):
        line.append(word)
        if word >> 33 & 1:                                  # tlast: the row's last beat
            frames.append(AxiStreamFrame(tdata=[w & 0xFFFFFFFF for w in line],
                                         tuser=[w >> 32 & 1 for w in line]))
            line = []
    return frames


def _pauses(probability: float, seed: int):
    return pause_generator({"kind": "random", "probability": probability, "seed": seed}
                           if probability else None)


@cocotb.test()
async def run_store_stream(dut):
    """The scene through the store build with AxiRam: lists exact, outputs X-free."""
    job, cfg, frames = load_job()
    store = cfg.axi_store(**job["store"])
    pause, seed = float(job.get("pause", 0.0)), int(job.get("seed", 0))
    regs = constants_namespace(cfg, store)
    bench = AxiBench(dut, {**job, "valid_pause": None, "ready_pause": None}, cfg)
    ram = AxiRam(AxiBus.from_prefix(dut, "m_axi_state"), dut.aclk, dut.aresetn,
                 reset_active_level=False, size=store.base_address + store.frame_bytes)
    channels = (ram.write_if.aw_channel, ram.write_if.w_channel, ram.write_if.b_channel,
                ram.read_if.ar_channel, ram.read_if.r_channel)
    for k, channel in enumerate(channels):
        if pause:
            channel.set_pause_generator(_pauses(pause, seed * 10 + k))
    if pause:
        bench.source.set_pause_generator(_pauses(pause, seed * 10 + 7))
        bench.sink.set_pause_generator(_pauses(pause, seed * 10 + 8))
    beats = clean_beats(frames)
    for frame in video_frames(cfg, beats):           # queued before the reset ends
        bench.source.send_nowait(frame)
    bad = []

    async def watch():
        while True:
            await RisingEdge(dut.aclk)
            if not int(dut.aresetn.value):
                continue
            for name in LEVELS:
                if not getattr(dut, name).value.is_resolvable:
                    bad.append(f"{name} = {getattr(dut, name).value}")
            for valid, names in PAYLOADS:
                value = getattr(dut, valid).value
                if value.is_resolvable and int(value):
                    bad.extend(f"{n} = {getattr(dut, n).value} with {valid}" for n in names
                               if not getattr(dut, n).value.is_resolvable)

    cocotb.start_soon(watch())
    await bench.start()
    expected = list_words(cfg, expected_outputs(cfg, beats, [{"stop": len(beats)}]).lists)
    got = []
    for _ in expected:
        frame = await with_timeout(bench.sink.recv(), 40 * len(beats) * bench.period, "ns")
        got.append([int(w) for w in frame.tdata])
    reads = {}
    for name in ("ERROR", "STATE_READ_ERRORS", "STATE_WRITE_ERRORS", "STATE_BASE_ACTIVE"):
        reads[name] = await bench.axil.read_dword(getattr(regs, f"REG_{name}"))
    summary = {"test": "run_store_stream", "lists": len(got),
               "exact": [g == e for g, e in zip(got, expected)],
               "records": sum(len(e) - 1 for e in expected), "x": bad[:10], "reads": reads}
    with open(job["summary"], "w") as fh:
        json.dump(summary, fh)
    assert not bad, bad[:10]
    assert got == expected
    assert reads == {"ERROR": 0, "STATE_READ_ERRORS": 0, "STATE_WRITE_ERRORS": 0,
                     "STATE_BASE_ACTIVE": store.base_address}
