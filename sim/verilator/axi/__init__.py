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

The package is split by concept: :mod:`~dptbd.sim.verilator.axi.harness` (one run of the
harness: :func:`run_axi`, :class:`AxiRun`, the input words), :mod:`~dptbd.sim.verilator.axi.steps`
(the bench's steps as harness operations, the expected fault pulses) and this package (the
scoring, :func:`check_axi`); every name is importable from here.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from dptbd.hw.register_map import FAULTS, constants_namespace
from dptbd.sim.axi.stimulus import Beats, expected_outputs, stream_pieces
from dptbd.sim.axi.scoring import (delivered_lists, flag_problems, score_exact,
                                   score_in_parts, undrained_cuts)
from dptbd.sim.candidate_scoreboard import CandidateScoreboard
from dptbd.sim.verilator.axi.harness import (ERROR_RESPONSES, MEMORY_KEYS, AxiRun, beat_words,
                                             run_axi, settle_cycles, wide_beat_words)
from dptbd.sim.verilator.axi.steps import (BUS_LATE_BIT, CUT_COUNTERS, DECERR, OKAY, SLVERR,
                                           fault_pulse_array, no_sof_mask, step_operations)
from dptbd.sim.verilator.cache import VerilatorBuild

__all__ = ["OKAY", "SLVERR", "DECERR", "ERROR_RESPONSES", "CUT_COUNTERS", "MEMORY_KEYS",
           "AxiRun", "AxiCheck", "beat_words", "step_operations", "run_axi", "check_axi",
           "fault_pulse_array", "no_sof_mask", "wide_beat_words", "settle_cycles",
           "BUS_LATE_BIT"]


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
