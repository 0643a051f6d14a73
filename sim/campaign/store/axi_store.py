"""The campaign's runs of the ``"axi_store"`` cases
(:func:`~dptbd.sim.campaign.store.cases.axi_store_cases`): they run the drop-in core
``dptbd_axi`` built with ``--state-store axi`` on Verilator (``dptbd.sim.verilator.build(cfg, "axi",
state_store=...)``, the harness's C++ memory model on its state port, which forgets every
burst in flight while ``aresetn`` is low, as AXI4 lets a reset abandon them): each run is an
``"axi"`` case's run of :func:`dptbd.sim.axi.runs.draw_run` — frame-sync faults, soft resets
(after the pipeline drained and with words in flight), ``aresetn`` pulses after the pipeline
drained and with words and bursts in flight at a beat drawn anywhere in a frame, run-time
settings, LUT writes, counter clears — with the memory of :func:`draw_memory` (a read
latency class in turn, write-response latency, random AXI ready / valid) and
:func:`dptbd.sim.verilator.axi.check_axi` scores every candidate word, flag, response and
counter, with no AXI4 rule broken and no burst left in flight at the end; their ``store``
bins are the memory model's observations; the refused bus accesses (``"bus"``) are drawn
on the store build's register map (:class:`~dptbd.sim.axi.actions.Drawer`: its registers
not unmapped, read by the checks, and refused ``STATE_BASE`` writes, unaligned or out of
range). An ``"axi_store"`` case with the faults ``"read_error"`` / ``"write_error"``
draws error runs instead (:func:`draw_error_window`): a clean hostile stream with input gaps
and back-pressure, the memory above, and every burst whose address handshake falls in a
window of cycles answered SLVERR or DECERR (reads, writes or both in turn by seed mod 3, the
response in turn by seed mod 2; the window spans 1 … 6 bursts from the first of its
direction after a drawn fraction of the run, found in a first run without errors:
:func:`window_cycles`); the run passes when the stream never stops (every beat taken, every
list sent), no AXI4 rule broke, ``STATE_READ_ERRORS`` / ``STATE_WRITE_ERRORS`` count what
the memory sent (at least one error), the ``ERROR`` bits are set exactly for the directions
that failed, ``LISTS`` counts every list, and every list of a segment that neither it nor
the segment before came near the window (its pixels accepted more than :func:`error_margin`
pixels away from those accepted in it) is the model's, the last segment's among them
(``docs/integration.md``, "State store in external memory").
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np

from dptbd.sim.campaign.store.cases import LATENCY_DRAW, STORE_FAULTS, store_config

__all__ = ["MemoryPlan", "draw_memory", "build_axi_store", "check_axi_store_run",
           "ErrorWindow", "draw_error_window", "window_cycles", "error_margin"]


@dataclasses.dataclass(frozen=True)
class MemoryPlan:
    """What run ``seed`` of an ``"axi_store"`` case drew for its memory (no errors)."""

    latency: tuple[int, int]
    write_latency: tuple[int, int]
    axi_ready: float
    axi_valid: float
    errors: tuple = ()

    def memory(self) -> dict:
        """:func:`dptbd.sim.verilator.axi.run_axi`'s ``memory``."""
        return dict(latency=self.latency, write_latency=self.write_latency,
                    axi_ready=self.axi_ready, axi_valid=self.axi_valid)

    @property
    def notes(self) -> tuple[str, ...]:
        return (f"read latency {self.latency[0]} … {self.latency[1]}, write response "
                f"{self.write_latency[0]} … {self.write_latency[1]}",
                f"AXI ready {self.axi_ready:.2f}, valid {self.axi_valid:.2f}")


def draw_memory(seed: int) -> MemoryPlan:
    """The memory of run ``seed``: a read latency class in turn (seed mod 4), a range inside
    it, a write-response range, the AXI ready and valid probabilities (as
    :func:`~dptbd.sim.campaign.store.dp_axi.draw_store_run`)."""
    rng = np.random.default_rng([seed, 0xA716])
    lo_c, hi_c = LATENCY_DRAW[seed % 4]
    lo, hi = sorted(int(v) for v in rng.integers(lo_c, hi_c + 1, size=2))
    wl = tuple(sorted(int(v) for v in rng.integers(0, max(hi, 1) + 1, size=2)))
    axi_ready, axi_valid = (1.0 if rng.random() < 0.3 else float(rng.uniform(0.3, 1.0))
                            for _ in range(2))
    return MemoryPlan((lo, hi), wl, axi_ready, axi_valid)


def build_axi_store(case, root=None):
    """The Verilator build of an ``"axi_store"`` case."""
    from dptbd.sim.verilator import build

    return build(case.cfg, "axi", root=root, state_store=store_config(case),
                 family=case.family)


def check_axi_store_run(case, seed: int, root=None):
    """Draw, run and check run ``seed`` of an ``"axi_store"`` case (see the module doc):
    the :class:`~dptbd.sim.campaign.results.RunOutcome` with its ``axi`` and ``store``
    bins."""
    import warnings

    from dptbd.config import EnergyWidthWarning
    from dptbd.sim.axi.runs import draw_run
    from dptbd.sim.campaign.results import RunOutcome
    from dptbd.sim.coverage.bins import axi_bins
    from dptbd.sim.coverage.bins.store import store_bins
    from dptbd.sim.verilator.axi import check_axi

    start = time.perf_counter()
    if any(f in STORE_FAULTS for f in case.faults):
        passed, report, words, cycles, seconds, flagged, counters, notes = _check_error_run(
            case, seed, root)
        memory = dataclasses.replace(draw_memory(seed), errors=flagged)
        return RunOutcome(case.name, seed, passed, f"seed {seed}: {report}" if report else "",
                          case.frames * case.cfg.width * case.cfg.height, words, cycles,
                          seconds, time.perf_counter() - start, notes,
                          store_bins(memory, passed=passed, observed=counters))
    sim = build_axi_store(case, root)
    plan = draw_run(case, seed)
    memory = draw_memory(seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        result = check_axi(sim, plan.beats, plan.steps, valid_gap=plan.valid_gap,
                           ready_pause=plan.ready_pause, seed=seed, pulses=plan.pulses,
                           memory=memory.memory())
        bins = axi_bins(case.cfg, plan.beats, plan.steps, passed=result.passed,
                        latency=sim.latency, valid_gap=plan.valid_gap,
                        ready_pause=plan.ready_pause, run=result.run, store=sim.state_store)
    if "bus" not in case.faults:
        # refusals only the raw accesses reach: not declared (a refused LUT strobe comes
        # from the LUT writes)
        from dptbd.sim.coverage.bins.groups import BUS_REASONS, key

        for reason in BUS_REASONS[1:]:
            bins.pop(key("register", reason), None)
    bins.update(store_bins(memory, passed=result.passed, observed=result.run.counters))
    report = "" if result.passed else f"seed {seed}: {result.report()}"
    return RunOutcome(case.name, seed, result.passed, report, len(plan.beats),
                      len(result.run.out_words) + len(result.run.op_resp), result.run.cycles,
                      result.run.sim_seconds, time.perf_counter() - start,
                      plan.notes + memory.notes, bins)


# ---- dptbd_axi --state-store axi: SLVERR / DECERR windows -------------------------------------

@dataclasses.dataclass(frozen=True)
class ErrorWindow:
    """The error window of an ``"axi_store"`` error run, as drawn: where it falls in the
    run's bursts (:func:`window_cycles`) and the response its bursts get."""

    directions: tuple[str, ...]     # "read", "write" or both
    at: float                       # the window opens at the first burst of a direction
    bursts: int                     # after the pixel at this fraction of the run, and
                                    # closes after this many bursts (any direction)
    valid_gap: float
    ready_pause: float
    response: str = "SLVERR"        # "SLVERR" or "DECERR"


def draw_error_window(case, seed: int) -> ErrorWindow:
    """Run ``seed``'s window: the directions in turn (seed mod 3: read, write, both), the
    response in turn (seed mod 2: SLVERR, DECERR; seeds 0 … 5 give each pair), input
    gaps and back-pressure (each 0 in 30 % of the runs, else uniform in [0, 0.5)), where it
    opens (uniform in [0.2, 0.6) of the run's pixels) and how many bursts it spans (1 … 6)."""
    rng = np.random.default_rng([seed, 0xE770])
    directions = (("read",), ("write",), ("read", "write"))[seed % 3]
    gap, pause = (0.0 if rng.random() < 0.3 else float(rng.uniform(0.0, 0.5))
                  for _ in range(2))
    return ErrorWindow(directions, float(rng.uniform(0.2, 0.6)), int(rng.integers(1, 7)),
                       gap, pause, ("SLVERR", "DECERR")[seed % 2])


def window_cycles(window: ErrorWindow, bursts: np.ndarray, accepted: np.ndarray
                  ) -> tuple[int, int]:
    """``[from, to)`` cycles of ``window`` in a run without errors whose address handshakes
    are ``bursts`` (rows cycle, is_write, address) and pixels were accepted in the cycles
    ``accepted``: from the first burst of one of its directions at or after the pixel at
    ``window.at`` of the run to just after ``window.bursts`` bursts. The memory model's
    errors draw from a generator of their own, so the run with the window is the same run."""
    after = int(accepted[int(window.at * len(accepted))])
    kinds = [d == "write" for d in window.directions]
    rows = np.flatnonzero((bursts[:, 0] >= after) & np.isin(bursts[:, 1], kinds))
    if not len(rows):
        raise ValueError(f"no {' or '.join(window.directions)} burst after cycle {after}")
    first = int(rows[0])
    last = min(first + window.bursts - 1, len(bursts) - 1)
    return int(bursts[first, 0]), int(bursts[last, 0]) + 1


def error_margin(store, latency: int) -> int:
    """Pixels, each side of those accepted in the window, whose states a failed transfer may
    touch: the read-ahead and write-behind (``2 · outstanding`` bursts of ``burst_states``,
    two bursts of packing) and the pipeline's ``latency``."""
    return 2 * (store.outstanding + 2) * store.burst_states + latency


def _check_error_run(case, seed: int, root):
    """An ``"axi_store"`` error run (see the module doc): (passed, report, words, cycles,
    sim seconds, errors flagged ((code, direction), …), memory counters, notes)."""
    from dptbd.hw.register_map import constants_namespace
    from dptbd.sim.axi.stimulus import clean_beats, expected_outputs
    from dptbd.sim.campaign.draw import hostile_frames
    from dptbd.sim.candidate_scoreboard import list_words
    from dptbd.sim.verilator.axi import run_axi

    sim = build_axi_store(case, root)
    cfg, store = sim.cfg, sim.state_store
    regs = constants_namespace(cfg, store)
    frames = hostile_frames(cfg, case.frames, np.random.default_rng([seed, 0xE771]))
    beats = clean_beats(frames)
    window = draw_error_window(case, seed)
    memory = draw_memory(seed)
    reads = ["ERROR", "STATE_READ_ERRORS", "STATE_WRITE_ERRORS", "LISTS"]
    ops = [(len(beats), "i", sim.latency + 64 + memory.latency[1] + memory.write_latency[1],
            0), *[(len(beats), "r", getattr(regs, f"REG_{name}"), 0) for name in reads]]
    stalls = dict(valid_gap=window.valid_gap, ready_pause=window.ready_pause, seed=seed)
    clean = run_axi(sim, beats, ops, memory=memory.memory(), **stalls)
    cycles = window_cycles(window, clean.bursts, clean.accept_cycles)
    setting = dict(memory.memory(), error_cycles=cycles, error_response=window.response,
                   **{f"{d}_error": 1.0 for d in window.directions})
    run = run_axi(sim, beats, ops, memory=setting, **stalls)
    c = run.counters
    got = dict(zip(reads, (int(v) for v in run.op_data)))
    sent = {"read": int(c.get("read_error_beats", 0)),
            "write": int(c.get("write_error_bursts", 0))}
    expected = list_words(cfg, expected_outputs(cfg, beats, [{"stop": len(beats)}]).lists)
    delivered, current = [], []
    for word, flag in zip(run.out_words, run.out_flags):
        current.append(int(word))
        if int(flag) & 2:
            delivered.append(current)
            current = []
    report = ""
    if run.status != "done" or int(c["accepted"]) != len(beats):
        report = f"status {run.status}: {c['accepted']} of {len(beats)} beats accepted"
    elif c.get("violations"):
        report = f"{c['violations']} AXI4 violations, the first: {run.first_violation}"
    elif not c.get("memory_idle"):
        report = "m_axi_state: bursts still in flight at the end"
    elif not any(sent[d] for d in window.directions):
        report = f"no burst in the window {cycles}: no error sent"
    elif (got["STATE_READ_ERRORS"], got["STATE_WRITE_ERRORS"]) != (sent["read"],
                                                                     sent["write"]):
        report = (f"STATE_READ_ERRORS {got['STATE_READ_ERRORS']}, STATE_WRITE_ERRORS "
                  f"{got['STATE_WRITE_ERRORS']}; the memory sent {sent['read']} error beats, "
                  f"{sent['write']} error responses")
    else:
        want_error = sum(getattr(regs, f"ERROR_STATE_{d.upper()}_MASK")
                         for d in ("read", "write") if sent[d])
        if got["ERROR"] != want_error:
            report = f"ERROR = {got['ERROR']:#x}, expected {want_error:#x}"
        elif not len(delivered) == len(expected) == got["LISTS"]:
            report = (f"{len(delivered)} lists delivered, LISTS = {got['LISTS']}, the model "
                      f"gives {len(expected)}")
    if not report:
        accepted = np.asarray(run.accept_cycles, dtype=np.int64)
        inside = np.flatnonzero((accepted >= cycles[0]) & (accepted < cycles[1]))
        lo = int(np.searchsorted(accepted, cycles[0]))
        hi = int(inside[-1]) if len(inside) else lo
        margin = error_margin(store, sim.latency)
        lo, hi = lo - margin, hi + margin
        segment = cfg.segment_frames * cfg.width * cfg.height
        clean = [(s + 1) * segment <= lo or s * segment > hi for s in range(len(expected))]
        exact = [j for j in range(len(expected)) if clean[j] and (j == 0 or clean[j - 1])]
        if not exact or exact[-1] != len(expected) - 1:
            report = (f"the window (pixels {lo} … {hi} with the margin) leaves no clean "
                      f"last segment of {len(expected)}: draw a shorter run")
        for j in exact:
            if not report and delivered[j] != expected[j]:
                report = f"list {j} (a segment clear of the window) differs from the model's"
    flagged = tuple((window.response, d) for d in ("read", "write") if sent[d])
    notes = (f"{window.response} on {' and '.join(window.directions)} bursts taken in cycles "
             f"[{cycles[0]}, {cycles[1]})",
             f"gaps {window.valid_gap:.2f}, back-pressure {window.ready_pause:.2f}",
             *memory.notes)
    return (not report, report, len(run.out_words) + len(run.op_resp), int(run.cycles),
            float(run.sim_seconds), flagged, c, notes)
