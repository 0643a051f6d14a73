"""Long runs of the AXI top level ``dptbd_axi`` on Verilator, scored against the golden model.

:func:`run_axi` streams input beats (pixel, ``tuser[0]``, ``tlast``; injected faults
included, :mod:`dptbd.sim.axi.stimulus`) through a ``design="axi"`` build of
:mod:`dptbd.sim.verilator.cache` (harness ``sim/harness/dptbd_axi_harness.cpp``) with seeded
``tvalid`` gaps and ``tready`` back-pressure, performing AXI4-Lite writes, reads and idle
waits before given beats. :func:`check_axi` turns the steps of the cocotb bench
(:mod:`dptbd.sim.benches.axi`: register ``writes``, ``lut_codes``, ``soft_reset``, ``check`` and
``stop``) into such operations, runs them, and scores every candidate word in order with
:class:`~dptbd.sim.candidate_scoreboard.CandidateScoreboard` against
:func:`~dptbd.sim.axi.stimulus.expected_outputs` (the same model as the cocotb bench), the
``tuser[0]`` / ``tlast`` of every word, every write's response, every ``check`` read and, at
the end, the FRAMES / SEGMENTS / LISTS / SATURATED counters and the fault counters against
the model. Nothing runs in Python per cycle.

A build with the state store in external memory (``build(cfg, "axi", state_store=store)``)
runs with the harness's AXI4 memory model on ``m_axi_state_*``; ``run_axi(memory=...)``
sets it (:data:`MEMORY_KEYS`) and the run's ``counters`` then also hold the model's
``read_bursts``, ``write_bursts``, ``violations`` (AXI4 rules broken; the first in
``first_violation``), ``read_error_beats``, ``write_error_bursts`` and ``memory_idle``; the
bursts of an error window (``read_error`` / ``write_error``, ``error_cycles``) are answered
with ``error_response`` (``"SLVERR"``, the default, or ``"DECERR"``; ``read_decerrs`` /
``write_decerrs`` count the error beats / responses whose RRESP / BRESP read DECERR on the
port).
"""

from __future__ import annotations

import dataclasses
import pathlib
import subprocess
import tempfile

import numpy as np

from dptbd.hw.register_map import FAULTS, constants_namespace, register_map
from dptbd.sim.axi.stimulus import Beats, expected_outputs, fault_pulses, stream_pieces
from dptbd.sim.axi.scoring import (delivered_lists, flag_problems, score_exact,
                                   score_in_parts, undrained_cuts)
from dptbd.sim.candidate_scoreboard import CandidateScoreboard
from dptbd.sim.verilator import _check_probability, cycle_budget
from dptbd.sim.verilator.cache import VerilatorBuild

__all__ = ["OKAY", "SLVERR", "DECERR", "ERROR_RESPONSES", "CUT_COUNTERS", "MEMORY_KEYS",
           "AxiRun", "AxiCheck", "beat_words", "step_operations", "run_axi", "check_axi",
           "fault_pulse_array", "no_sof_mask"]

OKAY, SLVERR, DECERR = 0, 2, 3

#: The responses the memory model's errors can carry (its ``error_response``).
ERROR_RESPONSES = ("SLVERR", "DECERR")

#: The counters of the core's events, which a reset with words in flight leaves at a count
#: that depends on timing: read right after every ``soft_reset: "now"`` (the base of their
#: check at the end) and LISTS checked there against the lists delivered.
CUT_COUNTERS = ("FRAMES", "SEGMENTS", "LISTS", "SATURATED")

#: The bit of an ``m`` operation's data that makes the write's W late (``"w-late"``).
BUS_LATE_BIT = 36

#: The AXI4 memory model's settings (``sim/harness/axi4_memory.h``) ``run_axi`` takes in
#: ``memory``: two-number ranges (latency, write_latency: cycles; error_cycles: [from, to)),
#: probabilities (axi_ready, axi_valid, read_error, write_error), the base address, the span
#: and the errors' response (error_response: one of :data:`ERROR_RESPONSES`).
MEMORY_KEYS = {"latency": 2, "write_latency": 2, "error_cycles": 2, "axi_ready": 1,
               "axi_valid": 1, "read_error": 1, "write_error": 1, "base": 1, "span": 1,
               "error_response": 1}


@dataclasses.dataclass(frozen=True)
class AxiRun:
    """What one run of the AXI harness reported."""

    status: str                  # "done" or "timeout"
    cycles: int
    out_words: np.ndarray        # uint64 m_axis_cand tdata of every transfer
    out_flags: np.ndarray        # uint64 tuser[0] | tlast << 1
    out_cycles: np.ndarray
    accept_cycles: np.ndarray    # uint64 cycle each beat was accepted (2**64-1: never)
    op_data: np.ndarray          # int64 per w/r operation: read data (0 for writes)
    op_resp: np.ndarray          # int64 per w/r operation: BRESP / RRESP
    counters: dict               # accepted, outputs, stalled_input_cycles, irq_rises, …
    sim_seconds: float
    op_cycles: np.ndarray = None  # int64 per w/r/m/b operation: the cycle it completed
    irq_cycles: np.ndarray = None  # uint64 cycle of every change of irq: rises, falls in turn
    first_violation: str | None = None  # the memory model's first AXI4 rule broken (store builds)
    bursts: np.ndarray = None    # store builds: (n, 3) int64 cycle, is_write, address per burst

    @property
    def cycles_per_second(self) -> float:
        return self.cycles / self.sim_seconds if self.sim_seconds > 0 else float("nan")


def beat_words(beats: Beats) -> np.ndarray:
    """The harness's input words: ``tdata | tuser[0] << 32 | tlast << 33``."""
    return (np.asarray(beats.pixel, dtype=np.uint64)
            | np.asarray(beats.first, dtype=np.uint64) << np.uint64(32)
            | np.asarray(beats.last, dtype=np.uint64) << np.uint64(33))


def wide_beat_words(cfg, beats: Beats) -> np.ndarray:
    """The harness's input words at P = 2 or 4 pixels per clock: every P consecutive pixels
    of ``beats`` (one pixel each, as at P = 1) in one ``s_axis_video`` beat, pixel k in
    byte lane k of ``tdata`` (:func:`~dptbd.hw.wide.axis_video.lane_bits`), ``tuser[0]``
    of its first pixel, ``tlast`` of its last. Refused: a pixel count that is not a
    multiple of P, or ``tuser[0]`` / ``tlast`` inside a beat."""
    from dptbd.hw.wide.axis_video import lane_bits

    p = cfg.pixels_per_clock
    if len(beats) % p:
        raise ValueError(f"{len(beats)} pixels do not fill beats of pixels_per_clock={p}")
    pixel = np.asarray(beats.pixel, dtype=np.uint64).reshape(-1, p)
    first = np.asarray(beats.first, dtype=bool).reshape(-1, p)
    last = np.asarray(beats.last, dtype=bool).reshape(-1, p)
    if first[:, 1:].any() or last[:, :-1].any():
        raise ValueError(f"at pixels_per_clock={p} tuser[0] (start of frame) may be set on "
                         f"the first pixel of a beat of {p} and tlast (end of line) on its "
                         f"last only")
    lane = lane_bits(cfg)
    tdata = np.zeros(len(pixel), dtype=np.uint64)
    for k in range(p):
        tdata |= pixel[:, k] << np.uint64(lane * k)
    return beat_words(Beats(tdata, first[:, 0], last[:, -1]))


def _beat_index(p: int, index: int, kind: str) -> int:
    """The beat before which an operation given before pixel ``index`` is performed."""
    if index % p:
        raise ValueError(f"operation {kind!r} before pixel {index}: at pixels_per_clock={p} "
                         f"operations come between beats, before a pixel index that is a "
                         f"multiple of {p}")
    return index // p


def settle_cycles(sim: VerilatorBuild, ready_pause: float) -> int:
    """Idle cycles after the last beat before reading counters or a soft reset: the latency
    plus two histogram scans, stretched by the output back-pressure."""
    scan = int(sim.manifest.get("scan_cycles", 0))
    return int((sim.latency + 2 * scan + 64) * (1 + 3 * ready_pause))


def step_operations(cfg, steps: list[dict], settle: int, final_reads: list[str],
                    store=None) -> tuple[list[tuple], list[tuple]]:
    """The harness operations of the bench's ``steps`` and, per w/r operation, what to
    check: ``("write", name, expected response)`` or ``("read", name, expected value or
    None)``. Each step waits ``settle`` cycles before its ``check`` reads or soft reset (as
    :mod:`dptbd.sim.benches.axi` does), then writes; ``final_reads`` are read after the last beat
    and ``settle`` idle cycles.

    ``soft_reset`` may be ``"now"``: no settle before it (``soft_reset_wait`` idle cycles
    if given), then a wait until ``STATUS.soft_reset_busy`` reads 0 (check
    ``("wait", "STATUS", beat)``), then reads of :data:`CUT_COUNTERS` (checks ``("cut",
    name, beat)``). ``aresetn`` (cycles) holds ``aresetn`` low after the settle and the
    check reads; with ``aresetn_wait`` (idle cycles, may be 0) instead of the settle, with
    words in flight, and then a read of STATUS (``("mark", "STATUS", beat)``: the cycle
    of the cut).
    Besides the bench's keys a step may hold ``clear_counters`` (a ``CONTROL.clear_counters``
    pulse after the settle and the check reads, before a soft reset), ``lut_writes``
    (``[p, m, code, wstrb]``: single LUT entries, after ``lut_codes``; refused unless
    ``wstrb`` = 0xF and the code is in [0, 2**F]) and ``bus`` (raw accesses, last:
    ``["w", address, data, wstrb, response]`` or ``["r", address, response, value or
    None]``; what is to be checked is given; ``"w-late"`` offers W only from the cycle
    after the AW handshake and changes ``awaddr`` then, ``"r-probe"`` changes ``araddr``
    after the AR handshake, offers AR while the read is pending (``"r-probe-all"`` AW and
    W too; none may be taken: the harness counts ``axil_violations``) and holds ``rready``
    low for 3 cycles of ``rvalid``). ``store``: the build's state store, whose
    registers a ``check`` may then read."""
    regs, regmap = constants_namespace(cfg, store), register_map(cfg, store)
    ops, checks, start = [], [], 0

    def read(at, name, want=None):
        ops.append((at, "r", getattr(regs, f"REG_{name}"), 0))
        checks.append(("read", name, want))

    def write(at, address, value, want, name):
        ops.append((at, "w", address, int(value)))
        checks.append(("write", name, want))

    unity = 1 << cfg.weight_frac_bits
    for step in steps:
        if (step.get("check") or step.get("soft_reset") is True or step.get("clear_counters")
                or (step.get("aresetn") and "aresetn_wait" not in step)):
            ops.append((start, "i", settle, 0))
        for name, want in (step.get("check") or {}).items():
            read(start, name, want)
        if step.get("aresetn"):
            if step.get("aresetn_wait"):
                ops.append((start, "i", int(step["aresetn_wait"]), 0))
            ops.append((start, "a", int(step["aresetn"]), 0))
        if step.get("aresetn") and "aresetn_wait" in step:   # the cycle of the cut
            ops.append((start, "b", regs.REG_STATUS, 0))
            checks.append(("mark", "STATUS", start))
        if step.get("clear_counters"):
            write(start, regs.REG_CONTROL, regs.CONTROL_CLEAR_COUNTERS_MASK, OKAY, "CONTROL")
        if step.get("soft_reset") == "now" and step.get("soft_reset_wait"):
            ops.append((start, "i", int(step["soft_reset_wait"]), 0))
        if step.get("soft_reset"):
            write(start, regs.REG_CONTROL, regs.CONTROL_SOFT_RESET_MASK, OKAY, "CONTROL")
        if step.get("soft_reset") == "now":
            ops.append((start, "b", regs.REG_STATUS, 0))
            checks.append(("wait", "STATUS", start))
            for name in CUT_COUNTERS:           # what the cut left: the base of the end check
                ops.append((start, "r", getattr(regs, f"REG_{name}"), 0))
                checks.append(("cut", name, start))
        for name, value in step.get("writes", []):
            reg = regmap[name]
            limits = reg.fields[0].limits if reg.kind == "setting" else (0, 2**32 - 1)
            taken = reg.access != "ro" and limits[0] <= value <= limits[1]
            write(start, getattr(regs, f"REG_{name}"), value, OKAY if taken else SLVERR, name)
        if step.get("lut_codes") is not None:
            for p, row in enumerate(step["lut_codes"]):
                for m, code in enumerate(row):
                    write(start, regs.LUT_BASE + 4 * cfg.lut_address(p, m), code, OKAY, "LUT")
        for p, m, code, strobe in step.get("lut_writes", []):
            taken = strobe == 0xF and 0 <= code <= unity
            ops.append((start, "m", regs.LUT_BASE + 4 * cfg.lut_address(p, m),
                        int(code) | int(strobe) << 32))
            checks.append(("write", f"LUT[{p}, {m}]", OKAY if taken else SLVERR))
        for kind, address, *rest in step.get("bus", []):
            if kind in ("w", "w-late"):
                data, strobe, want = rest
                late = (kind == "w-late") << BUS_LATE_BIT
                ops.append((start, "m", int(address), int(data) | int(strobe) << 32 | late))
                checks.append(("write", f"{int(address):#05x}", want))
            else:
                probe = {"r-probe": 1, "r-probe-all": 3}.get(kind, 0)
                ops.append((start, "r", int(address), probe))
                checks.append(("bus-read", f"{int(address):#05x}", tuple(rest)))
        start = step["stop"]
    ops.append((start, "i", settle, 0))
    for name in final_reads:
        read(start, name)
    return ops, checks


def run_axi(sim: VerilatorBuild, beats: Beats, ops: list[tuple], *, valid_gap: float = 0.0,
            ready_pause: float = 0.0, seed: int = 1, drain: int | None = None,
            max_cycles: int | None = None, coverage=None, repeat: int = 1,
            memory: dict | None = None) -> AxiRun:
    """Stream ``beats`` through a ``design="axi"`` build with the operations ``ops``
    (``(beat index, "w" | "r" | "i" | "m" | "b", address or idle cycles, data)``, performed
    in order before that beat is offered; ``"m"`` is a write with ``wstrb`` = data >> 32,
    ``"b"`` reads the address until its bit 0 is 0, ``"a"`` holds ``aresetn`` low for the
    given cycles, ``"p"`` loads counter ``address``
    (:func:`~dptbd.sim.mutation.presets.preset_counters`' index) with ``data`` in one cycle,
    in mutant builds only; see the harness's header); ``coverage``: write the run's coverage
    data to that file (a build with ``coverage=True``); ``repeat``: offer ``beats`` that many times
    over (``len(beats) * repeat`` beats; operation indices count them all; long runs:
    ``accept_cycles`` is then empty); ``memory``: the AXI4 memory model's settings
    (:data:`MEMORY_KEYS`; a build with ``state_store`` only, whose base address the model
    takes by default)."""
    if sim.design != "axi":
        raise ValueError(f"run_axi needs a build of design 'axi', got {sim.design!r}")
    if coverage is not None and not sim.coverage:
        raise ValueError("coverage needs a build made with coverage=True")
    valid_gap = _check_probability("valid_gap", valid_gap)
    ready_pause = _check_probability("ready_pause", ready_pause)
    if isinstance(repeat, bool) or not isinstance(repeat, int) or repeat < 1:
        raise ValueError(f"repeat must be an integer of at least 1, got {repeat!r}")
    store = getattr(sim, "state_store", None)
    if memory is not None and store is None:
        raise ValueError("memory applies to a build with state_store only")
    memory = dict(memory or {})
    for key in memory:
        if key not in MEMORY_KEYS:
            raise ValueError(f"memory key {key!r}: the keys are {', '.join(MEMORY_KEYS)}")
    if memory.get("error_response", "SLVERR") not in ERROR_RESPONSES:
        raise ValueError(f"memory error_response {memory['error_response']!r}: the "
                         f"responses are {', '.join(ERROR_RESPONSES)}")
    if store is not None:
        memory.setdefault("base", store.base_address)
    p = sim.cfg.pixels_per_clock
    if p > 1:                           # P pixels per beat: indices of pixels, as at P = 1
        words = wide_beat_words(sim.cfg, beats)
        ops = [(_beat_index(p, index, kind), kind, *rest) for index, kind, *rest in ops]
    else:
        words = beat_words(beats)
    total = len(words) * repeat
    for index, kind, *_ in ops:
        if not 0 <= index <= total or kind not in ("w", "r", "i", "m", "b", "a", "p"):
            raise ValueError(f"operation {kind!r} before beat {index}: kinds are w, r, i, m, "
                             f"b, a, p and beats 0 … {total}")
        if kind == "p" and not sim.mutant:
            raise ValueError("operation 'p' (a counter preset) needs a mutant build")
    slow, rate = 0, 1.0                 # the memory's latency and handshake rate
    if store is not None:
        slow = max(memory.get("latency", (0, 0))[1],
                   memory.get("write_latency", memory.get("latency", (0, 0)))[1])
        rate = max(0.05, float(memory.get("axi_ready", 1.0)) * float(memory.get("axi_valid", 1.0)))
    if drain is None:                   # with a store: its writes answered too
        drain = settle_cycles(sim, 0.0) + (0 if store is None else int(
            store.outstanding * (slow + 2 * store.burst_beats) / rate))
    if max_cycles is None:
        max_cycles = cycle_budget(total, valid_gap, ready_pause,
                                  drain + sum(o[2] if o[1] == "i" else 8 for o in ops))
        max_cycles = int(max_cycles * (1 + slow / 8) / rate)
    with tempfile.TemporaryDirectory(prefix="dptbd-verilator-axi-") as job_dir:
        job = pathlib.Path(job_dir)
        np.ascontiguousarray(words, dtype="<u8").tofile(job / "in.bin")
        lines = [f"words {total}", f"valid_gap {valid_gap!r}",
                 f"ready_pause {ready_pause!r}", f"seed {int(seed)}",
                 f"max_cycles {int(max_cycles)}", f"drain {int(drain)}"]
        lines += [f"op {int(i)} {k} {int(a)} {int(d)}" for i, k, a, d in ops]
        if repeat > 1:
            lines.append(f"period {len(words)}")
        for key, value in memory.items():
            if key == "error_response":
                lines.append(f"{key} {value}")
                continue
            values = value if MEMORY_KEYS[key] == 2 else (value,)
            lines.append(f"{key} " + " ".join(str(int(v) if key in ("latency", "write_latency",
                                                                    "error_cycles", "base",
                                                                    "span")
                                                  else float(v)) for v in values))
        if coverage is not None:
            lines.append(f"coverage {pathlib.Path(coverage).resolve()}")
        (job / "job.txt").write_text("\n".join(lines) + "\n")
        out = subprocess.run([str(sim.executable), str(job)], capture_output=True, text=True,
                             check=False)
        if out.returncode != 0:
            raise RuntimeError(f"{sim.executable} failed (exit {out.returncode}): "
                               f"{(out.stderr or out.stdout).strip()[-2000:]}")
        result = dict(line.partition(" ")[::2]
                      for line in (job / "result.txt").read_text().splitlines())
        violation = result.pop("first_violation", None)
        done = np.fromfile(job / "ops.bin", dtype="<u8")
        accepts = np.fromfile(job / "accept_cycles.bin", dtype="<u8")
        if p > 1:                       # per pixel: a beat's P pixels share its cycle
            accepts = np.repeat(accepts, p)
            result["accepted"] = str(int(result["accepted"]) * p)
        return AxiRun(
            status=result.pop("status"), cycles=int(result.pop("cycles")),
            out_words=np.fromfile(job / "out.bin", dtype="<u8"),
            out_flags=np.fromfile(job / "out_flags.bin", dtype="<u8"),
            out_cycles=np.fromfile(job / "out_cycles.bin", dtype="<u8"),
            accept_cycles=accepts,
            op_data=(done & np.uint64(0xFFFFFFFF)).astype(np.int64),
            op_resp=((done >> np.uint64(32)) & np.uint64(3)).astype(np.int64),
            op_cycles=(done >> np.uint64(34)).astype(np.int64),
            irq_cycles=np.fromfile(job / "irq_cycles.bin", dtype="<u8"),
            counters={k: int(v) for k, v in result.items() if k != "seconds"},
            sim_seconds=float(result["seconds"]),
            first_violation=None if violation in (None, "none") else violation,
            bursts=_bursts(job / "bursts.bin"))


@dataclasses.dataclass(frozen=True)
class AxiCheck:
    """The outcome of :func:`check_axi`: the run, the scoreboard and every problem found."""

    run: AxiRun
    board: CandidateScoreboard
    problems: list
    reads: dict                  # the final reads, {register: value}
    expected_counters: dict
    lists: tuple = ()            # the model's lists (cut lists included)

    @property
    def passed(self) -> bool:
        return self.run.status == "done" and self.board.done and not self.problems

    def report(self) -> str:
        return "; ".join([self.run.status, self.board.report(), *self.problems[:10]])


def check_axi(sim: VerilatorBuild, beats: Beats, steps: list[dict], *,
              valid_gap: float = 0.0, ready_pause: float = 0.0, seed: int = 1,
              pulses: np.ndarray | None = None, coverage=None,
              memory: dict | None = None) -> AxiCheck:
    """Run the bench's ``steps`` on Verilator and score everything (see the module doc);
    ``pulses``: :func:`fault_pulse_array` of these beats and steps if already known;
    ``coverage``: write the run's coverage data to that file; ``memory``: the AXI4 memory
    model's settings (a build with ``state_store``; :func:`run_axi`), whose AXI4 rule
    violations and bursts left in flight at the end are problems too."""
    cfg = sim.cfg
    expected = expected_outputs(cfg, beats, steps, cut_lists=True)
    cleared = [j for j, step in enumerate(steps)
               if step.get("clear_counters") or step.get("aresetn")]
    since = steps[cleared[-1] - 1]["stop"] if cleared and cleared[-1] > 0 else 0
    counters = expected.counters()
    if cleared:                         # the counters count from the last clear on
        before = (expected_outputs(cfg, beats, steps[:cleared[-1]], cut_lists=True).counters()
                  if since else {})
        counters = {k: v - before.get(k, 0) for k, v in counters.items()}
    if pulses is None:
        pulses = fault_pulse_array(cfg, beats, steps)
    faults = pulses[since:].sum(axis=0)
    final = {**counters, **{f"FAULT_{k.upper()}": int(v) for k, v in zip(FAULTS, faults)}}
    ops, checks = step_operations(cfg, steps, settle_cycles(sim, ready_pause), list(final),
                                  store=getattr(sim, "state_store", None))
    run = run_axi(sim, beats, ops, valid_gap=valid_gap, ready_pause=ready_pause, seed=seed,
                  coverage=coverage, memory=memory)
    cuts = undrained_cuts({piece.start for piece in stream_pieces(cfg, steps)}, checks, run)
    lost = _starts(steps, lambda step: step.get("aresetn") and "aresetn_wait" in step)
    if cuts:                            # words in flight lost there
        board, problems = score_in_parts(cfg, expected, run, cuts, lost)
        problems += _cut_counters(cfg, beats, steps, expected, run, ops, checks, since, final)
    else:
        board, problems = score_exact(cfg, expected.lists, expected.open_records,
                                      run.out_words)
        problems += flag_problems(cfg, expected.lists, run.out_flags[:board.count])
    if len(run.op_resp) != len(checks):
        problems.append(f"{len(run.op_resp)} of {len(checks)} register operations completed")
    reads = {}
    for (kind, name, want), data, resp in zip(checks, run.op_data, run.op_resp):
        if kind == "write" and resp != want:
            problems.append(f"write {name}: response {int(resp)}, expected {want}")
        elif kind in ("wait", "mark") and resp != OKAY:
            problems.append(f"wait for {name}: response {int(resp)}")
        elif kind == "bus-read":
            want_resp, want_value = want
            if resp != want_resp or (want_value is not None and data != want_value):
                problems.append(f"read {name} = {int(data)}, response {int(resp)}, expected "
                                f"{want_value} with response {want_resp}")
        elif kind == "read":
            reads[name] = int(data)
            if resp != OKAY:
                problems.append(f"read {name}: response {int(resp)}")
            elif want is not None and data != want:
                problems.append(f"read {name} = {int(data)}, expected {want}")
    for name, want in final.items():
        if name in reads and want is not None and reads[name] != want:
            problems.append(f"at the end: {name} = {reads[name]}, the model gives {want}")
    if run.counters.get("axil_violations"):
        problems.append(f"s_axil: {run.counters['axil_violations']} cycles with a ready high "
                        f"while a read was pending (one transaction at a time)")
    if run.counters.get("violations"):
        problems.append(f"{run.counters['violations']} AXI4 violations on m_axi_state, the "
                        f"first: {run.first_violation}")
    if run.counters.get("memory_idle") == 0:
        problems.append("m_axi_state: bursts still in flight at the end")
    if int(run.counters.get("accepted", -1)) != len(beats):
        problems.append(f"{run.counters.get('accepted')} of {len(beats)} beats accepted")
    return AxiCheck(run, board, problems, reads, final, tuple(expected.lists))


def no_sof_mask(beats: Beats, steps: list[dict]) -> np.ndarray:
    """Per beat: ``VIDEO_INPUT.no_sof`` is 1 when the beat is accepted (the steps' taken
    ``writes`` of ``VIDEO_INPUT``, from the step's first beat on)."""
    mask = np.zeros(len(beats), dtype=bool)
    start, value = 0, False
    for step in steps:
        value = value and not step.get("aresetn")
        for name, written in step.get("writes", []):
            if name == "VIDEO_INPUT" and written in (0, 1):
                value = bool(written)
        mask[start:step["stop"]] = value
        start = step["stop"]
    mask[start:] = value
    return mask


def fault_pulse_array(cfg, beats: Beats, steps: list[dict]) -> np.ndarray:
    """The frame monitor's fault pulses, ``(beats, len(FAULTS))``: the monitor restarts at
    every soft reset (:func:`~dptbd.sim.axi.stimulus.stream_pieces`) and raises no
    ``frame_long`` while ``no_sof`` is 1 (:func:`no_sof_mask`)."""
    out = np.zeros((len(beats), len(FAULTS)), dtype=np.int64)
    for piece in stream_pieces(cfg, steps):
        a, b = piece.start, min(piece.stop, len(beats))
        pulses = fault_pulses(cfg, beats.first[a:b], beats.last[a:b])
        if pulses:
            out[a:b] = [[p[k] for k in FAULTS] for p in pulses]
    out[no_sof_mask(beats, steps), FAULTS.index("frame_long")] = 0
    return out


def _starts(steps: list[dict], test) -> list[int]:
    """The first beats of the steps that pass ``test``."""
    out, start = [], 0
    for step in steps:
        if test(step):
            out.append(start)
        start = step["stop"]
    return out


def _cut_counters(cfg, beats: Beats, steps: list[dict], expected, run: AxiRun, ops: list,
                  checks: list, since: int, final: dict) -> list[str]:
    """The :data:`CUT_COUNTERS` across the soft resets of ``"now"`` (``final`` updated in
    place): at the end, the value read right after the last of them since the last counter
    clear or ``aresetn`` (beat ``since``) plus the model's counts of the beats after it (all
    of them drained); at each, LISTS against the lists delivered (trailers without ``cut``)
    since the previous one or the last counter clear or ``aresetn`` with words in flight
    (from 0; after an ``aresetn`` that has no cycle mark, not checked). The problems."""
    regs = constants_namespace(cfg)
    problems, reads, base, index = [], {}, (0, 0), 0      # base: (LISTS, cycle)
    for _at, kind, address, data in ops:
        if kind == "a":
            base = None
        if kind not in "wrmb":
            continue
        if index >= len(run.op_cycles):
            break
        (what, name, beat), cycle = checks[index], int(run.op_cycles[index])
        value, index = int(run.op_data[index]), index + 1
        if kind == "w" and address == regs.REG_CONTROL and data & regs.CONTROL_CLEAR_COUNTERS_MASK:
            base = (0, cycle)
        elif what == "mark":
            base = (0, cycle)
        elif what == "cut":
            reads.setdefault(beat, {})[name] = value
            if name == "LISTS" and base is not None:
                sent = delivered_lists(cfg, run, base[1], cycle)
                if value - base[0] != sent:
                    problems.append(f"after the soft reset at beat {beat}: LISTS went from "
                                    f"{base[0]} to {value}, {sent} lists were delivered")
            if name == "LISTS":
                base = (value, cycle)
    later = [beat for beat in sorted(reads) if beat > since]
    if later:
        beat = later[-1]
        j = next(j for j, start in enumerate(_starts(steps, lambda step: True))
                 if start == beat and steps[j].get("soft_reset") == "now")
        before = expected_outputs(cfg, beats, steps[:j], cut_lists=True).counters()
        total = expected.counters()
        for name in CUT_COUNTERS:
            final[name] = (reads[beat][name] + total[name] - before[name]
                           if name in reads[beat] else None)
    return problems


def _bursts(path: pathlib.Path) -> np.ndarray | None:
    """The memory model's log (``bursts.bin``) as ``(n, 3)``: cycle, is_write, address."""
    if not path.exists():
        return None
    raw = np.fromfile(path, dtype="<u8").reshape(-1, 2).astype(np.int64)
    return np.stack([raw[:, 0] >> 1, raw[:, 0] & 1, raw[:, 1]], axis=1)
