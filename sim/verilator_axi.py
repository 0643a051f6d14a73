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
from dptbd.hw.register_map import FAULTS, register_map
from dptbd.sim.axi_stimulus import (Beats, CutList, expected_outputs, fault_pulses,
                                    stream_pieces)
from dptbd.sim.candidate_scoreboard import CandidateScoreboard, list_words
from dptbd.sim.verilator import _check_probability, cycle_budget
from dptbd.sim.verilator_build import VerilatorBuild

__all__ = ["OKAY", "SLVERR", "AxiRun", "AxiCheck", "beat_words", "step_operations", "run_axi",
           "check_axi", "fault_pulse_array", "no_sof_mask"]

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
    op_cycles: np.ndarray = None  # int64 per w/r/m/b operation: the cycle it completed

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
    None)``. Each step waits ``settle`` cycles before its ``check`` reads or soft reset (as
    :mod:`dptbd.sim.tb_axi` does), then writes; ``final_reads`` are read after the last beat
    and ``settle`` idle cycles.

    ``soft_reset`` may be ``"now"``: no settle before it (``soft_reset_wait`` idle cycles
    if given), and then a wait until ``STATUS.soft_reset_busy`` reads 0 (check
    ``("wait", "STATUS", beat)``). ``aresetn``
    (cycles) holds ``aresetn`` low after the settle and the check reads.
    Besides the bench's keys a step may hold ``clear_counters`` (a ``CONTROL.clear_counters``
    pulse after the settle and the check reads, before a soft reset), ``lut_writes``
    (``[p, m, code, wstrb]``: single LUT entries, after ``lut_codes``; refused unless
    ``wstrb`` = 0xF and the code is in [0, 2**F]) and ``bus`` (raw accesses, last:
    ``["w", address, data, wstrb, response]`` or ``["r", address, response, value or
    None]``; what is to be checked is given)."""
    regs, regmap = constants_namespace(cfg), register_map(cfg)
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
                or step.get("aresetn")):
            ops.append((start, "i", settle, 0))
        for name, want in (step.get("check") or {}).items():
            read(start, name, want)
        if step.get("aresetn"):
            ops.append((start, "a", int(step["aresetn"]), 0))
        if step.get("clear_counters"):
            write(start, regs.REG_CONTROL, regs.CONTROL_CLEAR_COUNTERS_MASK, OKAY, "CONTROL")
        if step.get("soft_reset") == "now" and step.get("soft_reset_wait"):
            ops.append((start, "i", int(step["soft_reset_wait"]), 0))
        if step.get("soft_reset"):
            write(start, regs.REG_CONTROL, regs.CONTROL_SOFT_RESET_MASK, OKAY, "CONTROL")
        if step.get("soft_reset") == "now":
            ops.append((start, "b", regs.REG_STATUS, 0))
            checks.append(("wait", "STATUS", start))
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
            if kind == "w":
                data, strobe, want = rest
                ops.append((start, "m", int(address), int(data) | int(strobe) << 32))
                checks.append(("write", f"{int(address):#05x}", want))
            else:
                ops.append((start, "r", int(address), 0))
                checks.append(("bus-read", f"{int(address):#05x}", tuple(rest)))
        start = step["stop"]
    ops.append((start, "i", settle, 0))
    for name in final_reads:
        read(start, name)
    return ops, checks


def run_axi(sim: VerilatorBuild, beats: Beats, ops: list[tuple], *, valid_gap: float = 0.0,
            ready_pause: float = 0.0, seed: int = 1, drain: int | None = None,
            max_cycles: int | None = None, coverage=None) -> AxiRun:
    """Stream ``beats`` through a ``design="axi"`` build with the operations ``ops``
    (``(beat index, "w" | "r" | "i" | "m" | "b", address or idle cycles, data)``, performed
    in order before that beat is offered; ``"m"`` is a write with ``wstrb`` = data >> 32,
    ``"b"`` reads the address until its bit 0 is 0, ``"a"`` holds ``aresetn`` low for the
    given cycles; see the harness's header); ``coverage``: write the run's coverage data to
    that file (a build with ``coverage=True``)."""
    if sim.design != "axi":
        raise ValueError(f"run_axi needs a build of design 'axi', got {sim.design!r}")
    if coverage is not None and not sim.coverage:
        raise ValueError("coverage needs a build made with coverage=True")
    valid_gap = _check_probability("valid_gap", valid_gap)
    ready_pause = _check_probability("ready_pause", ready_pause)
    words = beat_words(beats)
    for index, kind, *_ in ops:
        if not 0 <= index <= len(words) or kind not in ("w", "r", "i", "m", "b", "a"):
            raise ValueError(f"operation {kind!r} before beat {index}: kinds are w, r, i, m, "
                             f"b, a and beats 0 … {len(words)}")
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
            op_cycles=(done >> np.uint64(34)).astype(np.int64),
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
    lists: tuple = ()            # the model's lists (cut lists included)

    @property
    def passed(self) -> bool:
        return self.run.status == "done" and self.board.done and not self.problems

    def report(self) -> str:
        return "; ".join([self.run.status, self.board.report(), *self.problems[:10]])


def _flag_problems(cfg, lists, flags: np.ndarray) -> list[str]:
    """``tuser[0]`` on a list's first word, ``tlast`` on its trailer, for each word."""
    sizes = np.asarray([len(words) for words in list_words(cfg, lists)], dtype=np.int64)
    closed = np.asarray([getattr(lst, "closed", True) for lst in lists], dtype=bool)
    first = np.zeros(sum(sizes), dtype=bool)
    trailer = np.zeros(sum(sizes), dtype=bool)
    ends = np.cumsum(sizes)                         # int64 also with no list
    first[(ends - sizes)[sizes > 0]] = True
    trailer[(ends - 1)[closed & (sizes > 0)]] = True
    n = min(len(flags), len(first))
    got_first = (flags[:n] & np.uint64(1)).astype(bool)
    got_last = (flags[:n] >> np.uint64(1) & np.uint64(1)).astype(bool)
    bad = np.flatnonzero((got_first != first[:n]) | (got_last != trailer[:n]))
    return [f"list word {int(i)}: tuser[0] = {int(got_first[i])}, tlast = {int(got_last[i])}"
            for i in bad[:5]]


def check_axi(sim: VerilatorBuild, beats: Beats, steps: list[dict], *,
              valid_gap: float = 0.0, ready_pause: float = 0.0, seed: int = 1,
              pulses: np.ndarray | None = None, coverage=None) -> AxiCheck:
    """Run the bench's ``steps`` on Verilator and score everything (see the module doc);
    ``pulses``: :func:`fault_pulse_array` of these beats and steps if already known;
    ``coverage``: write the run's coverage data to that file."""
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
    ops, checks = step_operations(cfg, steps, settle_cycles(sim, ready_pause), list(final))
    run = run_axi(sim, beats, ops, valid_gap=valid_gap, ready_pause=ready_pause, seed=seed,
                  coverage=coverage)
    cuts = _undrained_cuts({piece.start for piece in stream_pieces(cfg, steps)}, checks, run)
    if cuts:                            # the counters lose the words in flight there
        final.update({k: None for k in ("FRAMES", "SEGMENTS", "LISTS", "SATURATED")
                      if any(beat > since for beat, _ in cuts)})
        board, problems = _score_in_parts(cfg, expected, run, cuts)
    else:
        board, problems = _score_exact(cfg, expected.lists, expected.open_records,
                                       run.out_words)
        problems += _flag_problems(cfg, expected.lists, run.out_flags[:board.count])
    if len(run.op_resp) != len(checks):
        problems.append(f"{len(run.op_resp)} of {len(checks)} register operations completed")
    reads = {}
    for (kind, name, want), data, resp in zip(checks, run.op_data, run.op_resp):
        if kind == "write" and resp != want:
            problems.append(f"write {name}: response {int(resp)}, expected {want}")
        elif kind == "wait" and resp != OKAY:
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
    every soft reset (:func:`~dptbd.sim.axi_stimulus.stream_pieces`) and raises no
    ``frame_long`` while ``no_sof`` is 1 (:func:`no_sof_mask`)."""
    out = np.zeros((len(beats), len(FAULTS)), dtype=np.int64)
    for piece in stream_pieces(cfg, steps):
        a, b = piece.start, min(piece.stop, len(beats))
        pulses = fault_pulses(cfg, beats.first[a:b], beats.last[a:b])
        if pulses:
            out[a:b] = [[p[k] for k in FAULTS] for p in pulses]
    out[no_sof_mask(beats, steps), FAULTS.index("frame_long")] = 0
    return out


def _score_exact(cfg, lists: list, open_records: tuple, words: np.ndarray):
    """The scoreboard of ``words`` against ``lists`` and the problem if the words after them
    are not ``open_records`` (the records of a list the stream's end leaves open)."""
    board = CandidateScoreboard(cfg, lists)
    n = sum(len(w) for w in list_words(cfg, lists))
    board.receive_array(words[:n])
    tail = [int(w) for w in words[n:]]
    problems = []
    if len(words) >= n and tail != list(open_records):
        problems.append(f"after the last list: {len(tail)} words {[hex(w) for w in tail[:4]]}, "
                        f"the open list's records {[hex(w) for w in open_records[:4]]}")
    return board, problems


def _undrained_cuts(starts: set, checks: list, run: AxiRun) -> list[tuple[int, int]]:
    """(beat, cycle) of each ``soft_reset: "now"`` that starts a piece of the model (a beat
    of ``starts``): the cycle its wait for ``STATUS.soft_reset_busy`` = 0 ended (the old
    piece's words all came before it, the new piece's after: the input is held until then)."""
    waits = {}
    for index, (kind, _name, beat) in enumerate(checks):
        if kind == "wait" and beat not in waits and index < len(run.op_cycles):
            waits[beat] = int(run.op_cycles[index])
    return sorted((beat, cycle) for beat, cycle in waits.items() if beat > 0 and beat in starts)


def _score_in_parts(cfg, expected, run: AxiRun, cuts: list[tuple[int, int]]):
    """Score the words in parts split at the undrained soft resets ``cuts``: each part but
    the last is its lists whole, then at most one list's first records closed by the cut
    trailer (``pack_cut_trailer``) or nothing more; the last part exactly
    (:class:`CandidateScoreboard`). ``tuser[0]`` on each list's first word, ``tlast`` on
    each list's trailer (a list abandoned by ``aresetn`` has none)."""
    from dptbd.hw.candidate_layout import pack_cut_trailer

    problems, flags = [], []           # flags: (tuser[0], tlast) the words must carry

    def packet(words, closed=True):
        flags.extend((i == 0, closed and i == len(words) - 1) for i in range(len(words)))

    starts = np.asarray(expected.list_starts, dtype=np.int64)
    bounds = [0, *(beat for beat, _ in cuts)]
    edges = [0, *(cycle for _, cycle in cuts)]
    cycles = np.asarray(run.out_cycles, dtype=np.int64)
    got_flags = np.asarray(run.out_flags, dtype=np.uint64)
    for part, (lo_beat, hi_beat) in enumerate(zip(bounds, bounds[1:])):
        lists = [lst for lst, s0 in zip(expected.lists, starts) if lo_beat <= s0 < hi_beat]
        here = (cycles >= edges[part]) & (cycles < edges[part + 1])
        got = [int(w) for w in run.out_words[here]]
        open_list = None                 # the list the soft reset found open, if any
        if lists and isinstance(lists[-1], CutList) and not lists[-1].drained:
            open_list = lists.pop()
        want = list_words(cfg, lists)
        i = k = 0
        while k < len(want) and got[i:i + len(want[k])] == want[k]:
            packet(want[k], getattr(lists[k], "closed", True))
            i, k = i + len(want[k]), k + 1
        rest = got[i:]
        records = (want[k][:-1] if k < len(want) else
                   list_words(cfg, [open_list])[0][:-1] if open_list is not None else [])
        ok = not rest or (len(rest) - 1 <= len(records) and rest[:-1] == records[:len(rest) - 1]
                          and rest[-1] == pack_cut_trailer(cfg, len(rest) - 1))
        if ok:
            packet(rest)
        else:
            problems.append(f"before the soft reset at beat {hi_beat}: after {k} whole lists "
                            f"of {len(want)}, words {[hex(w) for w in rest[:4]]} are not a "
                            "list's first records closed by the cut trailer")
            flags.extend((bool(f & np.uint64(1)), bool(f >> np.uint64(1) & np.uint64(1)))
                         for f in got_flags[here][i:])
    last = [lst for lst, s0 in zip(expected.lists, starts) if s0 >= bounds[-1]]
    board, more = _score_exact(cfg, last, expected.open_records,
                               run.out_words[cycles >= edges[-1]])
    problems += more
    for lst, words in zip(last, list_words(cfg, last)):
        packet(words, getattr(lst, "closed", True))
    packet(list(expected.open_records), False)
    n = min(len(flags), len(got_flags))
    first = (got_flags[:n] & np.uint64(1)).astype(bool)
    tlast = (got_flags[:n] >> np.uint64(1) & np.uint64(1)).astype(bool)
    want = np.asarray(flags[:n], dtype=bool).reshape(-1, 2)
    bad = np.flatnonzero((first != want[:, 0]) | (tlast != want[:, 1]))
    problems += [f"word {int(j)}: tuser[0] = {int(first[j])}, tlast = {int(tlast[j])}"
                 for j in bad[:5]]
    return board, problems
