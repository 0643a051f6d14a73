"""cocotb tests of the generated ``dptbd_dp`` module against the golden model, bit for bit.

Run through :func:`dptbd.sim.icarus.simulate` (which builds with ``cocotb_tools.runner``);
never imported outside a simulator. The job comes from the environment:

``DPTBD_SIM_JOB``
    JSON file: the :class:`~dptbd.config.DPConfig` (``config``), the latency from the
    manifest, pause specs, an optional run-time LUT, reset and cycle-count options, and
    where to write the summary (see :func:`dptbd.sim.icarus.write_job`).
``DPTBD_SIM_SCENE``
    ``.npy`` of integer frames ``(T, H, W)``.

Tests:

``run_scene``
    Optionally write a LUT through the LUT port, then stream every frame with the
    configured input gaps and output back-pressure, score every output word against
    :func:`dptbd.sim.scoreboard.expected_words`, count cycles from the first accepted pixel
    to the last output (inclusive) and, with ``exact_cycles``, assert
    ``T * W * H + latency`` exactly.
    ``corrupt_expected`` (``{"index", "xor"}``) flips bits of one expected word: the
    self-check that the comparison really fails the test.
``mid_frame_reset``
    Stream ``pre_frames`` frames and part of the next, assert ``rst`` while pixels are
    still being offered, then stream the remaining frames: every output before the reset
    must be a prefix of the model's stream, every output after it must match the model run
    on the post-reset frames from a segment start, with the LUT kept across the reset
    (``docs/gateware.md``, "Reset and resynchronisation").
``truncated_frame_resync``
    Stream ``pre_frames`` frames, only the first ``keep_pixels`` of the next, then whole
    frames starting with ``first``: the gateware resynchronises to a new segment.
"""

from __future__ import annotations

import json
import os
import time
import warnings

import numpy as np

import cocotb
from cocotb.triggers import Event, First, RisingEdge, Timer

from dptbd.config import DPConfig, EnergyWidthWarning
from dptbd.sim.benches.drivers import (
    Cycles,
    StreamMonitor,
    StreamSink,
    StreamSource,
    optional_pauses,
    pause_generator,
    pause_probability,
    start_in_reset,
    write_lut,
)
from dptbd.sim.scoreboard import Scoreboard, expected_words
from dptbd.sim.stimulus import lut_writes, pack_pixels

PERIOD_NS = 10


def load_job() -> tuple[dict, DPConfig, np.ndarray]:
    """The job, its configuration and its frames, from the environment."""
    with open(os.environ["DPTBD_SIM_JOB"]) as fh:
        job = json.load(fh)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        cfg = DPConfig.from_mapping(job["config"])
    frames = np.load(os.environ["DPTBD_SIM_SCENE"])
    if frames.ndim != 3 or frames.shape[1:] != (cfg.height, cfg.width):
        raise ValueError(f"scene has shape {frames.shape}, expected (T, {cfg.height}, {cfg.width})")
    return job, cfg, frames


class Bench:
    """Clock, reset, drivers, monitor and timing of one test."""

    def __init__(self, dut, job: dict, cfg: DPConfig):
        self.dut, self.job, self.cfg = dut, job, cfg
        self.period_ns = int(job.get("period_ns", PERIOD_NS))
        self.cycles = Cycles(1)                     # replaced by start()
        self.log = cocotb.log
        self.wall_start = time.perf_counter()
        self.frame_words = cfg.width * cfg.height
        self.target = None                          # current scoreboard
        self.chain: list[Scoreboard] = []           # the ones after it
        self.finished = Event()

    async def start(self) -> None:
        dut = self.dut
        self.cycles = await start_in_reset(dut, self.period_ns, dut.states__ready,
                                           {"segment_frames": self.cfg.segment_frames})
        self.source = StreamSource(
            dut.clk, dut.pixels__valid, dut.pixels__ready, dut.pixels__payload,
            cycles=self.cycles, reset=dut.rst, pause=pause_generator(self.job.get("valid_pause")))
        self.sink = StreamSink(dut.clk, dut.states__ready,
                               pause=optional_pauses(self.job.get("ready_pause")))
        self.monitor = StreamMonitor(
            dut.clk, dut.states__valid, dut.states__ready, dut.states__payload, self._received,
            cycles=self.cycles, reset=dut.rst)

    def _progress(self, scoreboard: Scoreboard, label: str) -> None:
        frames = scoreboard.total // self.frame_words
        every = max(1, frames // 100)
        t0 = time.perf_counter()

        def on_frame(t: int) -> None:
            if (t + 1) % every == 0 or t + 1 == frames:
                wall = time.perf_counter() - t0
                self.log.info("%sframe %d/%d bit-exact (sim cycle %d, %.1f s wall)",
                              label, t + 1, frames, self.cycles.now(), wall)

        scoreboard._on_frame = on_frame

    def score_with(self, scoreboard: Scoreboard, label: str = "",
                   then: list[tuple[Scoreboard, str]] = ()) -> None:
        """Send the following outputs to ``scoreboard``, then (once it is complete) to each
        scoreboard of ``then`` in turn; log progress per frame."""
        self._progress(scoreboard, label)
        for board, board_label in then:
            self._progress(board, board_label)
        self.target = scoreboard
        self.chain = [board for board, _ in then]
        self.finished = Event()

    def _received(self, word: int, cycle: int) -> None:
        sb = self.target
        if sb is None:
            return
        if sb.done and self.chain:
            sb = self.target = self.chain.pop(0)
        sb.receive(word)
        if sb.failed or (sb.done and not self.chain):
            self.finished.set()

    def budget_cycles(self, words: int) -> int:
        """Generous cycle limit for ``words`` pixels through the pauses."""
        pv = pause_probability(self.job.get("valid_pause"))
        pr = pause_probability(self.job.get("ready_pause"))
        return int((words + 500) / max(0.02, (1 - pv) * (1 - pr)) * 3) + 2000

    async def wait_done(self, scoreboard: Scoreboard, words: int) -> bool:
        """Wait for the scoreboard to finish; False on timeout."""
        if scoreboard.done or scoreboard.failed:
            return True
        timeout = Timer(self.budget_cycles(words) * self.period_ns, unit="ns")
        fired = await First(self.finished.wait(), timeout)
        return fired is not timeout

    def write_summary(self, summary: dict) -> None:
        path = self.job.get("summary")
        wall = time.perf_counter() - self.wall_start
        sim_cycles = self.cycles.now()
        summary.update(wall_seconds=wall, sim_cycles_total=sim_cycles,
                       latency=self.job.get("latency"))
        summary.setdefault("sim_cycles_per_second", sim_cycles / wall if wall > 0 else None)
        if path:
            with open(path, "w") as fh:
                json.dump(summary, fh, indent=2)


@cocotb.test()
async def run_scene(dut):
    """Stream a whole scene (optionally after a run-time LUT write) and score every word."""
    job, cfg, frames = load_job()
    bench = Bench(dut, job, cfg)
    await bench.start()
    model_cfg = await _lut_setup(bench, cfg)
    expected = expected_words(model_cfg, frames)
    corrupt = job.get("corrupt_expected")
    if corrupt is not None:
        # self-check of the checker: a wrong expectation must make this test fail
        flat = expected.reshape(-1)
        flat[int(corrupt["index"])] ^= np.uint64(int(corrupt["xor"]))
        bench.log.warning("expected word %d deliberately corrupted (xor %#x)",
                          corrupt["index"], corrupt["xor"])
    scoreboard = Scoreboard(model_cfg, expected)
    bench.score_with(scoreboard, "")
    words = pack_pixels(cfg, frames)
    bench.log.info("streaming %d frames of %dx%d (%d pixels), K=%d", len(frames), cfg.width,
                   cfg.height, len(words), cfg.segment_frames)
    stream_start, cycle_start = time.perf_counter(), bench.cycles.now()
    bench.source.send(words)
    finished = await bench.wait_done(scoreboard, len(words))
    stream_seconds = time.perf_counter() - stream_start
    stream_cycles = bench.cycles.now() - cycle_start

    first_in = bench.source.accept_cycles[0] if bench.source.accept_cycles else None
    last_out = bench.monitor.last_cycle
    cycles = None if first_in is None or last_out is None else last_out - first_in + 1
    latency = job.get("latency")
    summary = {
        "test": "run_scene",
        "verdict": "bit-exact" if scoreboard.done else ("mismatch" if scoreboard.failed else
                                                        "timeout"),
        "report": scoreboard.report() if finished else
        f"timeout: {scoreboard.report()}; {bench.source.accepted} of {len(words)} pixels accepted",
        "frames": int(len(frames)),
        "pixels": len(words),
        "outputs": bench.monitor.count,
        "first_accept_cycle": first_in,
        "first_output_cycle": bench.monitor.first_cycle,
        "last_output_cycle": last_out,
        "cycles": cycles,
        "cycles_per_pixel": cycles / len(words) if cycles else None,
        "expected_cycles": len(words) + latency if latency is not None else None,
        "lut_written": job.get("lut_codes") is not None,
        # simulator speed while streaming (the model's expectation is computed before)
        "stream_cycles": stream_cycles,
        "stream_seconds": stream_seconds,
        "sim_cycles_per_second": stream_cycles / stream_seconds if stream_seconds > 0 else None,
    }
    if scoreboard.done:
        # a few more cycles: nothing may follow the last expected word
        for _ in range(latency or 20):
            await RisingEdge(dut.clk)
        summary["outputs"] = bench.monitor.count
        if scoreboard.extra:
            summary.update(verdict="mismatch", report=scoreboard.report())
    bench.write_summary(summary)
    bench.log.info("%s; %s cycles from first input to last output (%.4f cycles/pixel)",
                   summary["report"], cycles, summary["cycles_per_pixel"] or float("nan"))
    assert summary["verdict"] == "bit-exact", summary["report"]
    if job.get("exact_cycles"):
        assert first_in is not None and bench.monitor.first_cycle - first_in == latency, (
            f"first output {bench.monitor.first_cycle - first_in} cycles after the first "
            f"input, latency is {latency}")
        assert cycles == len(words) + latency, (
            f"{cycles} cycles from first input to last output, expected "
            f"T*W*H + latency = {len(words)} + {latency} = {len(words) + latency}")


async def _lut_setup(bench: Bench, cfg: DPConfig) -> DPConfig:
    """Write the job's run-time LUT (if any) through the LUT port; the model's config."""
    codes = bench.job.get("lut_codes")
    if codes is None:
        return cfg
    dut = bench.dut
    n = await write_lut(dut.clk, dut.lut_addr, dut.lut_data, dut.lut_we, lut_writes(cfg, codes))
    bench.log.info("wrote %d LUT entries through the LUT port before the first frame", n)
    return cfg.with_weight_codes(codes)


@cocotb.test()
async def mid_frame_reset(dut):
    """Reset in the middle of a frame; outputs match the model from the next frame start.

    ``docs/gateware.md`` ("Reset and resynchronisation"): ``rst`` empties the pipeline and
    the FIFO and resets the counters, so the next accepted pixel is (0, 0) of frame 0 of a
    new segment; the LUT keeps what was written (a run-time LUT is written before the first
    frame and must still apply after the reset); ``pixels.ready`` is low during reset and in
    the first cycle after it.
    """
    job, cfg, frames = load_job()
    spec = job["reset"]
    pre_frames, cut, hold = int(spec["pre_frames"]), int(spec["cut_pixel"]), int(spec["hold_cycles"])
    if not 0 < cut < cfg.width * cfg.height or pre_frames + 2 > len(frames) or hold < 1:
        raise ValueError(f"bad reset spec {spec} for {len(frames)} frames")
    bench = Bench(dut, job, cfg)
    await bench.start()
    model_cfg = await _lut_setup(bench, cfg)
    before, after = frames[: pre_frames + 1], frames[pre_frames + 1:]
    reset_at = pre_frames * cfg.width * cfg.height + cut     # accepted pixels before reset
    reset_now = Event()

    def on_accept(index: int, cycle: int) -> None:
        if index + 1 == reset_at:
            reset_now.set()

    bench.source._on_accept = on_accept
    pre = Scoreboard(model_cfg, expected_words(model_cfg, before))
    bench.score_with(pre, "before reset: ")
    bench.source.send(pack_pixels(cfg, before))
    timeout = Timer(bench.budget_cycles(reset_at) * bench.period_ns, unit="ns")
    fired = await First(reset_now.wait(), timeout)
    assert fired is not timeout, f"timeout before reset: {bench.source.accepted} pixels accepted"
    dut.rst.value = 1                       # sampled at the next edge: mid-frame
    bench.source.clear()                    # the word on offer at that edge is discarded
    reset_cycle = bench.cycles.now() + 1
    ready_seen = []
    await RisingEdge(dut.clk)               # the edge that samples rst = 1
    for _ in range(hold - 1):
        await RisingEdge(dut.clk)
        ready_seen.append(str(dut.pixels__ready.value))
    dut.rst.value = 0
    await RisingEdge(dut.clk)               # first cycle after reset
    ready_seen.append(str(dut.pixels__ready.value))
    pre_outputs = pre.count
    bench.log.info("reset at cycle %d after %d accepted pixels (pixel %d of frame %d), "
                   "%d outputs before it; pixels.ready during and after reset: %s",
                   reset_cycle, reset_at, cut, pre_frames, pre_outputs, "".join(ready_seen))
    summary = {"test": "mid_frame_reset", "reset_after_pixels": reset_at,
               "outputs_before_reset": pre_outputs, "frames_after_reset": int(len(after)),
               "lut_written": job.get("lut_codes") is not None}
    problem = None
    if pre.failed:
        problem = "before reset: " + pre.report()
    elif pre_outputs >= reset_at:
        problem = (f"before reset: {pre_outputs} outputs for {reset_at} accepted pixels: "
                   f"nothing can have been in flight")
    elif any(v != "0" for v in ready_seen):
        problem = (f"pixels.ready must be low during reset and in the first cycle after it, "
                   f"sampled {''.join(ready_seen)}")
    if problem is not None:
        summary.update(verdict="mismatch", report=problem)
        bench.write_summary(summary)
        assert False, problem

    post = Scoreboard(model_cfg, expected_words(model_cfg, after))
    bench.score_with(post, "after reset: ")
    words = pack_pixels(cfg, after)
    bench.source.send(words)
    finished = await bench.wait_done(post, len(words))
    summary.update(
        verdict="bit-exact" if post.done else ("mismatch" if post.failed else "timeout"),
        report=("after reset: " + post.report()) if finished else
        f"timeout after reset: {post.report()}",
        frames=int(len(after)), pixels=len(words), outputs=bench.monitor.count)
    bench.write_summary(summary)
    assert post.done, summary["report"]


@cocotb.test()
async def truncated_frame_resync(dut):
    """A frame cut short, then whole frames with ``first``: resynchronisation, no reset.

    ``docs/gateware.md``: a ``first`` where the counters do not expect a frame start makes
    that pixel (0, 0) of frame 0 of a new segment; the interrupted frame's accepted pixels
    come out normally but without ``end_of_frame``/``end_of_segment`` (a prefix of the
    frame never contains its last pixel, so it is a prefix of the model's stream).
    """
    job, cfg, frames = load_job()
    spec = job["truncate"]
    pre_frames, keep = int(spec["pre_frames"]), int(spec["keep_pixels"])
    if not 0 < keep < cfg.width * cfg.height or pre_frames + 2 > len(frames):
        raise ValueError(f"bad truncate spec {spec} for {len(frames)} frames")
    bench = Bench(dut, job, cfg)
    await bench.start()
    model_cfg = await _lut_setup(bench, cfg)
    before, after = frames[: pre_frames + 1], frames[pre_frames + 1:]
    n_before = pre_frames * cfg.width * cfg.height + keep
    pre = Scoreboard(model_cfg, expected_words(model_cfg, before).ravel()[:n_before])
    post = Scoreboard(model_cfg, expected_words(model_cfg, after))
    bench.score_with(pre, "before the cut: ", then=[(post, "after resync: ")])
    words = pack_pixels(cfg, before)[:n_before] + pack_pixels(cfg, after)
    bench.source.send(words)
    finished = await bench.wait_done(post, len(words))
    failed = pre if pre.failed else post
    summary = {
        "test": "truncated_frame_resync", "cut_after_pixels": n_before,
        "verdict": "bit-exact" if post.done else ("mismatch" if failed.failed else "timeout"),
        "report": (("before the cut: " if failed is pre else "after resync: ") + failed.report())
        if finished else f"timeout: {pre.report()}; {post.report()}",
        "frames": int(len(frames)), "pixels": len(words), "outputs": bench.monitor.count,
    }
    bench.write_summary(summary)
    assert post.done, summary["report"]
