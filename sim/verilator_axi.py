"""Long runs of the AXI top level ``dptbd_axi`` on Verilator, scored against the golden model.

:func:`run_axi` streams input beats (pixel, ``tuser[0]``, ``tlast``; injected faults
included, :mod:`dptbd.sim.axi_stimulus`) through a ``design="axi"`` build of
:mod:`dptbd.sim.verilator_build` (harness ``sim/harness/dptbd_axi_harness.cpp``) with seeded
``tvalid`` gaps and ``tready`` back-pressure, performing AXI4-Lite writes, reads and idle
waits before given beats. :func:`check_axi` turns the steps of the cocotb bench
(:mod:`dptbd.sim.tb_axi`: register ``writes``, ``lut_codes``, ``soft_reset``, ``check`` and
``stop``) into such operations, runs them, and scores every candidate word in order with
:class:`~dptbd.sim.candidate_scoreboard.CandidateScoreboard` against
:func:`~dptbd.sim.axi_stimulus.expected_outputs` (the same model as the cocotb bench), the
``tuser[0]`` / ``tlast`` of every word, every write's response, every ``check`` read and, at
the end, the FRAMES / SEGMENTS / LISTS / SATURATED counters and the fault counters against
the model. Nothing runs in Python per cycle.
"""

from __future__ import annotations

import dataclasses
import pathlib
import subprocess
import tempfile

import numpy as np

from dptbd.hw.flow.register_export import constants_namespace
from dptbd.sim.axi_stimulus import Beats, expected_outputs, fault_counts
from dptbd.sim.candidate_scoreboard import CandidateScoreboard, list_words
from dptbd.sim.verilator import _check_probability, cycle_budget
from dptbd.sim.verilator_build import VerilatorBuild

__all__ = ["OKAY", "SLVERR", "AxiRun", "AxiCheck", "beat_words", "step_operations", "run_axi",
           "check_axi"]

OKAY, SLVERR = 0, 2


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

    @property
    def cycles_per_second(self) -> float:
        return self.cycles / self.sim_seconds if self.sim_seconds > 0 else float("nan")


def beat_words(beats: Beats) -> np.ndarray:
    """The harness's input words: ``tdata | tuser[0] << 32 | tlast << 33``."""
    return (np.asarray(beats.pixel, dtype=np.uint64)
            | np.asarray(beats.first, dtype=np.uint64) << np.uint64(32)
            | np.asarray(beats.last, dtype=np.uint64) << np.uint64(33))


def settle_cycles(sim: VerilatorBuild, ready_pause: float) -> int:
    """Idle cycles after the last beat before reading counters or a soft reset: the latency
    plus two histogram scans, stretched by the output back-pressure."""
    scan = int(sim.manifest.get("scan_cycles", 0))
    return int((sim.latency + 2 * scan + 64) * (1 + 3 * ready_pause))


def step_operations(cfg, steps: list[dict], settle: int, final_reads: list[str]
                    ) -> tuple[list[tuple], list[tuple]]:
    """The harness operations of the bench's ``steps`` and, per w/r operation, what to
    check: ``("write", name, expected response)`` or ``("read", name, expected value or
    None)``, or ``("refused read", address, None)``. Each step waits ``settle`` cycles
    before its ``check`` reads or soft reset (as :mod:`dptbd.sim.tb_axi` does), then writes;
    its ``refused`` accesses (``[["w" | "r", byte address, data], ...]``: unaligned or
    unmapped addresses, a LUT read, a LUT code out of range) must be answered SLVERR;
    ``final_reads`` are read after the last beat and ``settle`` idle cycles."""
    regs = constants_namespace(cfg)
    ops, checks, start = [], [], 0

    def read(at, name, want=None):
        ops.append((at, "r", getattr(regs, f"REG_{name}"), 0))
        checks.append(("read", name, want))

    def write(at, address, value, want, name):
        ops.append((at, "w", address, int(value)))
        checks.append(("write", name, want))

    for step in steps:
        if step.get("check") or step.get("soft_reset"):
            ops.append((start, "i", settle, 0))
        for name, want in (step.get("check") or {}).items():
            read(start, name, want)
        if step.get("soft_reset"):
            write(start, regs.REG_CONTROL, regs.CONTROL_SOFT_RESET_MASK, OKAY, "CONTROL")
        for name, value in step.get("writes", []):
            lo = getattr(regs, f"{name}_{name}_MIN", None)
            hi = getattr(regs, f"{name}_{name}_MAX", None)
            taken = lo is None or lo <= value <= hi
            write(start, getattr(regs, f"REG_{name}"), value, OKAY if taken else SLVERR, name)
        for kind, address, data in step.get("refused", []):  # must answer SLVERR, change nothing
            if kind == "w":
                write(start, int(address), data, SLVERR, f"0x{int(address):x}")
            else:
                ops.append((start, "r", int(address), 0))
                checks.append(("refused read", f"0x{int(address):x}", None))
        if step.get("lut_codes") is not None:
            for p, row in enumerate(step["lut_codes"]):
                for m, code in enumerate(row):
                    write(start, regs.LUT_BASE + 4 * cfg.lut_address(p, m), code, OKAY, "LUT")
        start = step["stop"]
    ops.append((start, "i", settle, 0))
    for name in final_reads:
        read(start, name)
    return ops, checks


def run_axi(sim: VerilatorBuild, beats: Beats, ops: list[tuple], *, valid_gap: float = 0.0,
            ready_pause: float = 0.0, seed: int = 1, drain: int | None = None,
            max_cycles: int | None = None, coverage=None) -> AxiRun:
    """Stream ``beats`` through a ``design="axi"`` build with the operations ``ops``
    (``(beat index, "w" | "r" | "i", address or idle cycles, data)``, performed in order
    before that beat is offered; see the harness's header); ``coverage``: write the run's
    coverage data to that file (a build with ``coverage=True``)."""
    if sim.design != "axi":
        raise ValueError(f"run_axi needs a build of design 'axi', got {sim.design!r}")
    if coverage is not None and not sim.coverage:
        raise ValueError("coverage needs a build made with coverage=True")
    valid_gap = _check_probability("valid_gap", valid_gap)
    ready_pause = _check_probability("ready_pause", ready_pause)
    words = beat_words(beats)
    for index, kind, *_ in ops:
        if not 0 <= index <= len(words) or kind not in ("w", "r", "i"):
            raise ValueError(f"operation {kind!r} before beat {index}: kinds are w, r, i and "
                             f"beats 0 … {len(words)}")
    if drain is None:
        drain = settle_cycles(sim, 0.0)
    if max_cycles is None:
        max_cycles = cycle_budget(len(words), valid_gap, ready_pause,
                                  drain + sum(o[2] if o[1] == "i" else 8 for o in ops))
    with tempfile.TemporaryDirectory(prefix="dptbd-verilator-axi-") as job_dir:
        job = pathlib.Path(job_dir)
        np.ascontiguousarray(words, dtype="<u8").tofile(job / "in.bin")
        lines = [f"words {len(words)}", f"valid_gap {valid_gap!r}",
                 f"ready_pause {ready_pause!r}", f"seed {int(seed)}",
                 f"max_cycles {int(max_cycles)}", f"drain {int(drain)}"]
        lines += [f"op {int(i)} {k} {int(a)} {int(d)}" for i, k, a, d in ops]
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
        done = np.fromfile(job / "ops.bin", dtype="<u8")
        return AxiRun(
            status=result.pop("status"), cycles=int(result.pop("cycles")),
            out_words=np.fromfile(job / "out.bin", dtype="<u8"),
            out_flags=np.fromfile(job / "out_flags.bin", dtype="<u8"),
            out_cycles=np.fromfile(job / "out_cycles.bin", dtype="<u8"),
            accept_cycles=np.fromfile(job / "accept_cycles.bin", dtype="<u8"),
            op_data=(done & np.uint64(0xFFFFFFFF)).astype(np.int64),
            op_resp=((done >> np.uint64(32)) & np.uint64(3)).astype(np.int64),
            counters={k: int(v) for k, v in result.items() if k != "seconds"},
            sim_seconds=float(result["seconds"]))


@dataclasses.dataclass(frozen=True)
class AxiCheck:
    """The outcome of :func:`check_axi`: the run, the scoreboard and every problem found."""

    run: AxiRun
    board: CandidateScoreboard
    problems: list
    reads: dict                  # the final reads, {register: value}
    expected_counters: dict

    @property
    def passed(self) -> bool:
        return self.run.status == "done" and self.board.done and not self.problems

    def report(self) -> str:
        return "; ".join([self.run.status, self.board.report(), *self.problems[:10]])


def _flag_problems(cfg, lists, flags: np.ndarray) -> list[str]:
    """``tuser[0]`` on a list's first word, ``tlast`` on its trailer, for each word."""
    sizes = [len(words) for words in list_words(cfg, lists)]
    first = np.zeros(sum(sizes), dtype=bool)
    trailer = np.zeros(sum(sizes), dtype=bool)
    ends = np.cumsum(sizes)
    first[ends - np.asarray(sizes)] = True
    trailer[ends - 1] = True
    n = min(len(flags), len(first))
    got_first = (flags[:n] & np.uint64(1)).astype(bool)
    got_last = (flags[:n] >> np.uint64(1) & np.uint64(1)).astype(bool)
    bad = np.flatnonzero((got_first != first[:n]) | (got_last != trailer[:n]))
    return [f"list word {int(i)}: tuser[0] = {int(got_first[i])}, tlast = {int(got_last[i])}"
            for i in bad[:5]]


def check_axi(sim: VerilatorBuild, beats: Beats, steps: list[dict], *,
              valid_gap: float = 0.0, ready_pause: float = 0.0, seed: int = 1,
              coverage=None) -> AxiCheck:
    """Run the bench's ``steps`` on Verilator and score everything (see the module doc)."""
    cfg = sim.cfg
    expected = expected_outputs(cfg, beats, steps)
    faults = fault_counts(cfg, beats)
    final = {**expected.counters(), **{f"FAULT_{k.upper()}": v for k, v in faults.items()}}
    ops, checks = step_operations(cfg, steps, settle_cycles(sim, ready_pause), list(final))
    run = run_axi(sim, beats, ops, valid_gap=valid_gap, ready_pause=ready_pause, seed=seed,
                  coverage=coverage)
    board = CandidateScoreboard(cfg, expected.lists)
    board.receive_array(run.out_words)
    problems = _flag_problems(cfg, expected.lists, run.out_flags[:board.count])
    if len(run.op_resp) != len(checks):
        problems.append(f"{len(run.op_resp)} of {len(checks)} register operations completed")
    reads = {}
    for (kind, name, want), data, resp in zip(checks, run.op_data, run.op_resp):
        if kind == "write" and resp != want:
            problems.append(f"write {name}: response {int(resp)}, expected {want}")
        elif kind == "refused read" and resp != SLVERR:
            problems.append(f"read {name}: response {int(resp)}, expected {SLVERR}")
        elif kind == "read":
            reads[name] = int(data)
            if resp != OKAY:
                problems.append(f"read {name}: response {int(resp)}")
            elif want is not None and data != want:
                problems.append(f"read {name} = {int(data)}, expected {want}")
    for name, want in final.items():
        if name in reads and reads[name] != want:
            problems.append(f"at the end: {name} = {reads[name]}, the model gives {want}")
    if int(run.counters.get("accepted", -1)) != len(beats):
        problems.append(f"{run.counters.get('accepted')} of {len(beats)} beats accepted")
    return AxiCheck(run, board, problems, reads, final)
