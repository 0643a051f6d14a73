"""cocotb test of the generated ``dptbd_axi`` (the AXI top level) with cocotbext-axi, against
the golden model bit for bit.

Run through :func:`dptbd.sim.icarus.simulate` on a build made with ``build(cfg,
design="axi")``; never imported outside a simulator. The job (``DPTBD_SIM_JOB``) carries the
input beats (:class:`dptbd.sim.axi.stimulus.Beats`, faults included) and a list of *steps*;
for each step the bench

1. waits until every earlier beat was accepted, then ``settle`` cycles (default: latency
   plus two histogram scans, so every event of those beats has been counted),
2. reads every register of the step's ``check`` (``{name: value}``) and compares,
3. performs the step's register ``writes`` (``[[name, value], …]``) through
   ``AxiLiteMaster``, each answered OKAY when the value is in the register's range and
   SLVERR otherwise, and read back (unchanged after a refusal),
4. writes the step's ``lut_codes`` through the LUT window, entry by entry,
5. queues the beats up to the step's ``stop`` on ``AxiStreamSource`` (one line per
   AXI-Stream frame: ``tlast`` where the beats have ``last``; ``tuser`` = ``first``).

``m_axis_cand`` goes to ``AxiStreamSink``; every word is scored in order against
:func:`dptbd.sim.axi.stimulus.expected_outputs` (the golden model of the accepted stream, from
reset and after every soft reset, with the settings written and LUT changes at their beat),
and ``tuser[0]`` / ``tlast`` are checked on every word. At the end the FRAMES, SEGMENTS,
LISTS and SATURATED counters must read what the model gives. A step with ``soft_reset`` writes
``CONTROL.soft_reset`` after the earlier beats have drained. Both streams take the
job's ``valid_pause`` / ``ready_pause`` (:func:`dptbd.sim.benches.drivers.pause_generator`). At
the end the ``final_check`` registers are read. The summary lists the cycles at which
``irq`` rose and fell and the cycle each beat was accepted.

With ``state_output`` in the job (a top built with ``m_axis_state``, runner design
``axi-state``), a second ``AxiStreamSink`` takes ``m_axis_state`` with the job's
``state_pause``, and every (E, d) word is scored in order against the same model
(:class:`dptbd.sim.scoreboard.Scoreboard`), ``tuser[0]`` checked on every word.

The cocotbext-axi drivers and watchers both tests share with
:mod:`dptbd.sim.benches.axi_store` are in :mod:`dptbd.sim.benches.bus_drivers`.
"""

from __future__ import annotations

import json
import time

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import Event, First, RisingEdge, Timer

from dptbd.hw.candidate_layout import unpack_candidate
from dptbd.hw.register_map import constants_namespace
from dptbd.sim.axi.stimulus import Beats, expected_outputs
from dptbd.sim.candidate_scoreboard import CandidateScoreboard
from dptbd.hw.layouts import pack_states
from dptbd.sim.benches.drivers import pause_probability
from dptbd.sim.scoreboard import Scoreboard
from dptbd.sim.benches.soft_reset_check import PortWatch, score_iteration, score_state_iteration
from dptbd.sim.benches.bus_drivers import OKAY, AxiBench, line_frames
from dptbd.sim.benches.dp import PERIOD_NS, load_job


@cocotb.test()
async def run_stream(dut):
    """Drive the steps of the job and score every candidate word and register check."""
    job, cfg, _frames = load_job()
    wall_start = time.perf_counter()
    beats = Beats.from_json(job["beats"])
    steps = job["steps"]
    bench = AxiBench(dut, job, cfg)
    await bench.start()

    expected = expected_outputs(cfg, beats, steps)
    lists = expected.lists
    board = CandidateScoreboard(cfg, lists)
    finished = Event()
    if board.total == 0:
        finished.set()
    settle = int(job.get("settle", bench_settle(job, cfg)))

    async def score():
        while True:
            frame = await bench.sink.recv()
            for i, word in enumerate(frame.tdata):
                user = frame.tuser[i] if isinstance(frame.tuser, list) else frame.tuser
                if int(user) & 1 != int(i == 0):
                    bench.problems.append(f"list word {board.count}: tuser[0] = {user}")
                kind = unpack_candidate(cfg, int(word))[0]
                if (kind == "trailer") != (i == len(frame.tdata) - 1):
                    bench.problems.append(f"list word {board.count}: a {kind} with tlast = "
                                          f"{int(i == len(frame.tdata) - 1)}")
                board.receive(int(word))
            if board.failed or board.done:
                finished.set()

    cocotb.start_soon(score())
    states = None
    if bench.state_sink is not None:
        states = Scoreboard(cfg, expected.state_words, positions=expected.state_positions)
        cocotb.start_soon(score_states(bench, cfg, states, expected.state_first))
    start = 0
    for index, step in enumerate(steps):
        await bench.source.wait()
        if step.get("check") or step.get("soft_reset"):
            await bench.settle(settle)
        if step.get("check"):
            await bench.check(step["check"], f"before step {index}")
        if step.get("soft_reset"):
            await bench.write(bench.regs.REG_CONTROL, bench.regs.CONTROL_SOFT_RESET_MASK, OKAY,
                              "CONTROL")
        for name, value in step.get("writes", []):
            await bench.write_register(name, int(value))
        if step.get("lut_codes") is not None:
            codes = step["lut_codes"]
            for p, row in enumerate(codes):
                for m, code in enumerate(row):
                    await bench.write(bench.regs.LUT_BASE + 4 * cfg.lut_address(p, m), code,
                                      OKAY, "LUT")
        for frame in line_frames(beats, start, step["stop"]):
            await bench.source.send(frame)
        start = step["stop"]

    pv = pause_probability(job.get("valid_pause"))
    pr = pause_probability(job.get("ready_pause"))
    budget = int((len(beats) + 500) / max(0.02, (1 - pv) * (1 - pr)) * 3) + 4000 \
        + len(lists) * (cfg.n_bins + 4) * 3
    timeout = Timer(budget * bench.period, unit="ns")
    fired = await First(finished.wait(), timeout)
    while states is not None and not (states.done or states.failed) and fired is not timeout:
        fired = await First(RisingEdge(dut.aclk), timeout)
    timed_out = fired is timeout and not (board.done and (states is None or states.done))
    await bench.source.wait()
    await bench.settle(settle)
    if job.get("final_check"):
        await bench.check(job["final_check"], "at the end")
    counters = {name: await bench.read(name) for name in
                ("FRAMES", "SEGMENTS", "LISTS", "SATURATED", "INPUT_STALLS", "OUTPUT_STALLS",
                 "ERROR", "IRQ_STATUS")}
    for name, want in expected.counters().items():
        if counters[name] != want:
            bench.problems.append(f"at the end: {name} = {counters[name]}, the model gives "
                                  f"{want}")
    ok = board.done and not bench.problems and (states is None or states.done)
    summary = {
        "test": "run_stream",
        "design": "axi",
        "verdict": "bit-exact" if ok else ("timeout" if timed_out else "mismatch"),
        "report": "; ".join([board.report(), *([states.report()] if states else []),
                             *bench.problems[:10]]),
        "state_words": None if states is None else states.count,
        "problems": bench.problems,
        "beats": len(beats),
        "accepted": len(bench.accept_cycles),
        "lists": len(lists),
        "counts": [lst.count for lst in lists],
        "expected_counters": expected.counters(),
        "counters": counters,
        "stalls_seen": bench.stalls,
        "irq_edges": bench.irq_edges,
        "accept_cycles": bench.accept_cycles,
        "wall_seconds": time.perf_counter() - wall_start,
        "sim_cycles_total": bench.cycles.now(),
    }
    bench.log.info("%s", summary["report"])
    if job.get("summary"):
        with open(job["summary"], "w") as fh:
            json.dump(summary, fh, indent=2)
    assert summary["verdict"] == "bit-exact", summary["report"]


async def score_states(bench: AxiBench, cfg, board: Scoreboard, first) -> None:
    """Score every ``m_axis_state`` beat: (E, d) and the flags against the model's word,
    ``tuser[0]`` against ``first``."""
    e_mask, d_mask = (1 << cfg.energy_bits) - 1, (1 << cfg.direction_bits) - 1
    while not (board.done or board.failed):
        line = await bench.state_sink.recv()
        users = line.tuser if isinstance(line.tuser, list) else [line.tuser] * len(line.tdata)
        for i, (word, user) in enumerate(zip(line.tdata, users)):
            user = int(user)
            if board.count < len(first) and bool(user & 1) != bool(first[board.count]):
                bench.problems.append(f"state word {board.count}: tuser[0] = {user & 1}")
            packed = pack_states(cfg, energy=int(word) & e_mask,
                                 direction=(int(word) >> cfg.energy_bits) & d_mask,
                                 end_of_line=int(i == len(line.tdata) - 1),
                                 end_of_frame=(user >> 1) & 1, end_of_segment=(user >> 2) & 1)
            board.receive(int(packed))


def bench_settle(job: dict, cfg) -> int:
    """Cycles after the last accepted beat until all its events are counted: the latency
    plus two histogram scans, doubled under back-pressure."""
    slow = 1 + 3 * pause_probability(job.get("ready_pause"))
    return int((int(job.get("latency", 20)) + 2 * (cfg.n_bins + 4) + 8) * slow)


@cocotb.test()
async def soft_reset_sweep(dut):
    """``CONTROL.soft_reset`` landing in every cycle of a list (or a state line) being sent.

    The job's ``beats`` (frames from reset, each a segment: an unprimed empty list, then
    lists with records) are sent again and again, one *iteration* each; every iteration but
    the last issues the soft-reset write ``issue[i]`` cycles after its start, and its
    iteration starts once the core has taken the soft reset (``s_axis_video_tready`` high
    after the write's response). The bench drives every port itself, cycle by cycle, so
    each iteration is the same stimulus up to its write: the source offers the beats back
    to back and stops when the write is issued (a beat it offers then and the core has not
    taken is withdrawn: the bench's own side), ``m_axis_cand_tready`` follows a random
    pattern restarted from ``ready_seed`` at every iteration (pause probability
    ``ready_pause``), the AXI4-Lite write is one AW+W beat. With ``state_output`` (a top
    built with ``m_axis_state``) ``m_axis_state_tready`` follows its own random pattern
    (``state_pause``, ``state_seed``). The summary holds each iteration's outcome
    (:func:`score_iteration`, and :func:`score_state_iteration` in ``state_outcomes``) and,
    for the last iteration, the cycles (from its start) in which ``m_axis_cand_tvalid``
    (``last_timeline``) and ``m_axis_state_tvalid`` (``last_state_timeline``) were high,
    with ``tready`` and ``tlast``.

    Checked on every cycle of each output: ``tvalid`` never drops and ``tdata`` / ``tuser``
    / ``tlast`` never change while a word waits for ``tready``. Checked per iteration: its
    words on ``m_axis_cand``, cut into packets at ``tlast``, are the model's lists (tuser[0]
    on each first word, tlast on each last), except that the last list may be a prefix of
    its words closed by the cut trailer (``pack_cut_trailer``: the records sent) or
    missing (the reset landed before it began); those on ``m_axis_state`` are lines of
    exactly W words, each ending with ``tlast``, the model's words in order (flags and
    ``tuser[0]`` included) but for the fillers that complete a cut last line; the last
    iteration gives every list and every state word whole.
    """
    from dptbd.hw.candidate_layout import pack_cut_trailer
    from dptbd.sim.candidate_scoreboard import list_words

    job, cfg, _frames = load_job()
    regs = constants_namespace(cfg)
    beats = Beats.from_json(job["beats"])
    issues = list(job["issue"]) + [None]
    expected = expected_outputs(cfg, beats, [{"stop": len(beats)}])
    want = list_words(cfg, expected.lists)
    period = int(job.get("period_ns", PERIOD_NS))
    Clock(dut.aclk, period, unit="ns").start(start_high=False)
    for name in ("s_axis_video_tvalid", "s_axil_awvalid", "s_axil_wvalid", "s_axil_bready",
                 "s_axil_arvalid", "s_axil_rready"):
        getattr(dut, name).value = 0
    for name in ("s_axis_video_tdata", "s_axis_video_tuser", "s_axis_video_tlast",
                 "s_axil_awaddr", "s_axil_wdata", "s_axil_awprot", "s_axil_arprot",
                 "s_axil_araddr"):
        getattr(dut, name).value = 0
    dut.s_axil_wstrb.value = 0xF
    problems, outcomes, state_outcomes = [], [], []
    cand = PortWatch(dut, "m_axis_cand", float(job["ready_pause"]), int(job["ready_seed"]),
                      problems)
    ports = [cand]
    state = None
    if job.get("state_output"):
        state = PortWatch(dut, "m_axis_state", float(job["state_pause"]),
                           int(job["state_seed"]), problems)
        ports.append(state)
    dut.aresetn.value = 0
    for _ in range(4):
        await RisingEdge(dut.aclk)
    dut.aresetn.value = 1
    cycles = 0

    def value(handle) -> int:
        v = handle.value
        if not v.is_resolvable:
            problems.append(f"cycle {cycles}: {handle._name} = {v}")
            return 0
        return int(v)

    def finished(index: int) -> bool:
        return (index == len(beats) and len(cand.words) >= sum(map(len, want))
                and (state is None or len(state.words) >= len(expected.state_words)))

    for iteration, issue in enumerate(issues):
        # wait for the core to take pixels: the iteration starts in that cycle
        while True:
            await RisingEdge(dut.aclk)
            cycles += 1
            if value(dut.s_axis_video_tready):
                break
        for port in ports:
            port.restart()
        n, index, writing, wrote, stopped = 0, 0, False, False, False
        dut.s_axis_video_tvalid.value = 0
        while True:
            # drive the cycle n (values take effect after this edge's sampling)
            offer = not stopped and index < len(beats)
            if offer:
                dut.s_axis_video_tdata.value = int(beats.pixel[index])
                dut.s_axis_video_tuser.value = int(beats.first[index])
                dut.s_axis_video_tlast.value = int(beats.last[index])
            dut.s_axis_video_tvalid.value = int(offer)
            for port in ports:
                port.drive()
            if issue is not None and n == issue:
                dut.s_axil_awaddr.value = regs.REG_CONTROL
                dut.s_axil_wdata.value = regs.CONTROL_SOFT_RESET_MASK
                dut.s_axil_awvalid.value = dut.s_axil_wvalid.value = 1
                dut.s_axil_bready.value = 1
                writing, stopped = True, True
            await RisingEdge(dut.aclk)
            cycles += 1
            # sample cycle n
            if offer and value(dut.s_axis_video_tready):
                index += 1
            for port in ports:
                port.sample(value, cycles, n)
            if writing:
                if value(dut.s_axil_awready) and value(dut.s_axil_wready):
                    dut.s_axil_awvalid.value = dut.s_axil_wvalid.value = 0
                if value(dut.s_axil_bvalid):
                    dut.s_axil_bready.value = 0
                    writing, wrote = False, True
                    if value(dut.s_axil_bresp) != OKAY:
                        problems.append(f"iteration {iteration}: CONTROL write refused")
            n += 1
            if wrote:
                break
            if issue is None and finished(index):
                break
            if n > 20 * len(beats) + 2000:
                problems.append(f"iteration {iteration}: no end after {n} cycles")
                break
        dut.s_axis_video_tvalid.value = 0
        if wrote:
            # the outputs are closed and the core reset once s_axis_video_tready is high
            # again; keep taking words (random tready) until then
            while True:
                for port in ports:
                    port.drive()
                await RisingEdge(dut.aclk)
                cycles += 1
                for port in ports:
                    port.sample(value, cycles, None)
                if value(dut.s_axis_video_tready):
                    break
            for port in ports:
                port.idle()
        outcomes.append(score_iteration(cfg, want, cand.words, issue is None,
                                        pack_cut_trailer, problems, iteration))
        if state is not None:
            state_outcomes.append(score_state_iteration(cfg, expected, state.words,
                                                        issue is None, problems, iteration))
    summary = {"test": "soft_reset_sweep", "problems": problems[:20], "outcomes": outcomes,
               "state_outcomes": state_outcomes, "cycles": cycles,
               "last_timeline": cand.timeline,
               "last_state_timeline": None if state is None else state.timeline,
               "verdict": "bit-exact" if not problems else "mismatch",
               "report": "; ".join(problems[:5]) or f"{len(outcomes)} iterations bit-exact"}
    if job.get("summary"):
        with open(job["summary"], "w") as fh:
            json.dump(summary, fh, indent=2)
    assert not problems, summary["report"]
