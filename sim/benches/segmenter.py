"""cocotb test of the generated ``dptbd_seg`` module (DP pipeline + segmenter) against the
golden models, bit for bit.

Run through :func:`dptbd.sim.icarus.simulate` on a build made with
``build(cfg, design="segmenter")``; never imported outside a simulator. The job and scene come
from ``DPTBD_SIM_JOB`` / ``DPTBD_SIM_SCENE`` exactly as for :mod:`dptbd.sim.benches.dp`.

``run_scene``
    Optionally write a LUT through the LUT port, then stream every frame with the
    configured input gaps (``valid_pause``) and back-pressure on ``candidates``
    (``ready_pause``) and score every output word against
    :func:`dptbd.sim.candidate_scoreboard.expected_lists` (``dptbd.model.fixed`` for the DP,
    ``dptbd.model.segmentation.segment_sequence`` for the segmenter). The report names the
    first mismatching segment, record (or trailer) and field. After the last expected word
    the bench waits ``latency + 2 * scan_cycles`` more cycles: nothing may follow.
    ``exact_cycles`` asserts ``S*K*W*H + latency + 1`` cycles from the first accepted pixel to
    the last trailer (no bubble anywhere, K >= 2). ``corrupt_expected`` (``{"index",
    "xor"}``) flips bits of one expected word: the checker's self-check.
"""

from __future__ import annotations

import json
import time

import cocotb
from cocotb.triggers import Event, First, RisingEdge, Timer

from dptbd.hw.candidate_layout import bits_per_segment
from dptbd.sim.benches.drivers import StreamMonitor, StreamSink, StreamSource, write_lut
from dptbd.sim.benches.drivers import optional_pauses, pause_generator, pause_probability
from dptbd.sim.benches.drivers import start_in_reset
from dptbd.sim.candidate_scoreboard import CandidateScoreboard, expected_lists
from dptbd.sim.stimulus import lut_writes, pack_pixels
from dptbd.sim.benches.dp import PERIOD_NS, load_job


@cocotb.test()
async def run_scene(dut):
    """Stream a whole multi-segment scene and score every candidate record and trailer."""
    job, cfg, frames = load_job()
    wall_start = time.perf_counter()
    period = int(job.get("period_ns", PERIOD_NS))
    cycles = await start_in_reset(dut, period, dut.candidates__ready, {
        "segment_frames": cfg.segment_frames, "candidate_count": cfg.n_candidates,
        "histogram_shift": cfg.bin_shift})
    log = cocotb.log
    model_cfg = cfg
    if job.get("lut_codes") is not None:
        model_cfg = cfg.with_weight_codes(job["lut_codes"])
        n = await write_lut(dut.clk, dut.lut_addr, dut.lut_data, dut.lut_we,
                            lut_writes(cfg, job["lut_codes"]))
        log.info("wrote %d LUT entries before the first frame", n)
    lists = expected_lists(model_cfg, frames)
    board = CandidateScoreboard(model_cfg, lists)
    corrupt = job.get("corrupt_expected")
    if corrupt is not None:
        board.corrupt_word(int(corrupt["index"]), int(corrupt["xor"]))
        log.warning("expected word %d deliberately corrupted (xor %#x)", corrupt["index"],
                    corrupt["xor"])
    finished = Event()
    if board.total == 0:
        finished.set()
    last_segment = [0]

    def received(word: int, cycle: int) -> None:
        board.receive(word)
        if board.segments_done != last_segment[0]:
            last_segment[0] = board.segments_done
            lst = lists[board.segments_done - 1] if board.segments_done <= len(lists) else None
            if lst is not None:
                log.info("list %d/%d bit-exact: %d records, threshold bin %d%s (cycle %d)",
                         board.segments_done, len(lists), lst.count, lst.threshold,
                         ", overflow" if lst.overflow else "", cycle)
        if board.failed or board.done:
            finished.set()

    source = StreamSource(dut.clk, dut.pixels__valid, dut.pixels__ready, dut.pixels__payload,
                          cycles=cycles, reset=dut.rst,
                          pause=pause_generator(job.get("valid_pause")))
    StreamSink(dut.clk, dut.candidates__ready, pause=optional_pauses(job.get("ready_pause")))
    monitor = StreamMonitor(dut.clk, dut.candidates__valid, dut.candidates__ready,
                            dut.candidates__payload, received, cycles=cycles, reset=dut.rst)
    words = pack_pixels(cfg, frames)
    log.info("streaming %d frames of %dx%d, K=%d: %d lists, %d records expected (n=%d, C=%d, "
             "2^%d bins, shift %d)", len(frames), cfg.width, cfg.height, cfg.segment_frames,
             len(lists), board.records_expected, cfg.n_candidates, cfg.record_capacity,
             cfg.histogram_bits, cfg.bin_shift)
    source.send(words)
    pv = pause_probability(job.get("valid_pause"))
    pr = pause_probability(job.get("ready_pause"))
    budget = int((len(words) + 500) / max(0.02, (1 - pv) * (1 - pr)) * 3) + 2000 \
        + len(lists) * int(job.get("scan_cycles", cfg.n_bins + 4))
    timeout = Timer(budget * period, unit="ns")
    fired = await First(finished.wait(), timeout)
    timed_out = fired is timeout and not board.done
    if board.done:
        settle = int(job.get("latency", 20)) + 2 * (cfg.n_bins + 4)
        for _ in range(settle):
            await RisingEdge(dut.clk)
    first_in = source.accept_cycles[0] if source.accept_cycles else None
    last_out = monitor.last_cycle
    span = None if first_in is None or last_out is None else last_out - first_in + 1
    bits = bits_per_segment(cfg)
    verdict = "bit-exact" if board.done else ("timeout" if timed_out else "mismatch")
    summary = {
        "test": "run_scene",
        "design": "segmenter",
        "verdict": verdict,
        "report": board.report() if not timed_out else
        f"timeout: {board.report()}; {source.accepted} of {len(words)} pixels accepted",
        "frames": int(len(frames)),
        "pixels": len(words),
        "lists": len(lists),
        "records": board.records_expected,
        "counts": [lst.count for lst in lists],
        "thresholds": [lst.threshold for lst in lists],
        "overflows": sum(lst.overflow for lst in lists),
        "outputs": monitor.count,
        "first_accept_cycle": first_in,
        "first_output_cycle": monitor.first_cycle,
        "last_output_cycle": last_out,
        "cycles": span,
        "bits_image_per_segment": bits.image,
        "bits_lists_per_segment": (monitor.count * bits.word / len(lists)) if lists else None,
        "bits_nominal_per_segment": bits.nominal,
        "wall_seconds": time.perf_counter() - wall_start,
        "sim_cycles_total": cycles.now(),
        "latency": job.get("latency"),
    }
    if lists and summary["bits_lists_per_segment"]:
        summary["reduction"] = bits.image / summary["bits_lists_per_segment"]
    log.info("%s; %s cycles from first input to last output", summary["report"], span)
    if job.get("exact_cycles") and board.done:
        k, frame = cfg.segment_frames, cfg.width * cfg.height
        want = len(lists) * k * frame + int(job["latency"]) + 1
        if span != want:
            summary.update(verdict="mismatch", report=f"{span} cycles from the first input to "
                           f"the last trailer, expected S*K*W*H + latency + 1 = {want}")
    if job.get("summary"):
        with open(job["summary"], "w") as fh:
            json.dump(summary, fh, indent=2)
    assert summary["verdict"] == "bit-exact", summary["report"]
