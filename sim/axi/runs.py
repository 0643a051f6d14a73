"""Random runs of the AXI top level ``dptbd_axi`` for the verification campaign
(:mod:`dptbd.sim.campaign`, ``Case(design="axi")``), each drawn from its seed only.

:func:`draw_run` draws, from the seed,

* a video stream: :func:`~dptbd.sim.campaign.hostile_frames` cut into stretches of 1–4
  frames, about a quarter of them (two frames or more) carrying one frame-sync fault of a
  class drawn from :data:`~dptbd.sim.axi.stimulus.FAULT_KINDS`
  (:func:`~dptbd.sim.axi.stimulus.with_fault`);
* input gap and output back-pressure densities, each in a band of
  :data:`~dptbd.sim.coverage.bins.BANDS` (none: 0; light: uniform in (0, 0.35); heavy:
  uniform in [0.35, 0.7]), the pair of bands the seed modulo 9 (nine consecutive seeds
  draw every pair);
* steps (the bench's vocabulary, :func:`dptbd.sim.verilator.axi.step_operations`; the
  register traffic from :class:`~dptbd.sim.axi.actions.Drawer`) at beats
  drawn on frame starts, line starts, inside a frame's first or last row and anywhere,
  each with some of: run-time K / n / s writes (n often 0, 1, 2 or C, s mostly near the
  build's), refused setting writes (below or above every writable register's range, the
  all-ones word, a strobed byte that takes the word out of range),
  a write with no strobe (taken, nothing changes), ``VIDEO_INPUT.no_sof`` set and cleared,
  ``IRQ_ENABLE`` writes, a whole LUT (codes in [0, 2**F], 0 and 2**F included) or single
  entries (codes 0, 2**F, in between; refused: 2**F + 1, the field's maximum, all ones,
  strobes other than 1111), unaligned writes and reads, reads of the write-only LUT window
  and of unmapped addresses, writes to unmapped (half the time next to a register or the
  LUT window, with a code the LUT would take) and read-only registers (a
  constant, a counter or STATUS, a third each), soft resets at
  any beat of a frame (the model restarts at the soft reset's beat), half of them after the
  pipeline drained (a list left open in a scored frame is then closed by the cut trailer:
  :class:`~dptbd.sim.axi.stimulus.CutList`), half with words in flight and back-pressure
  (``soft_reset: "now"``, after ``soft_reset_wait`` idle cycles, 0 half the time, else up
  to :data:`NOW_WAIT`: the lists before it whole, then at most one list's first records
  closed by the cut trailer; FRAMES … SATURATED read right after it, the base of their
  check at the end), and in
  the runs without input gaps a sweep of :data:`NOW_SWEEP` more of these at beats drawn
  anywhere, with 0, 1, 2 … idle cycles before them (so that the campaign's soft resets
  find every number of words in flight, 0 … L),
  ``CONTROL.clear_counters`` (the counters then read 0), reads of every readable register
  with the value the model gives where it knows it (constants, settings, enables, ERROR,
  the fault counters, STATUS, CONTROL), W1C clears of ERROR and IRQ_STATUS bits.

:func:`check_run` runs one on Verilator (:func:`dptbd.sim.verilator.axi.check_axi`: every
candidate word, its ``tuser[0]`` / ``tlast``, every response and checked read, the end
counters). ``aresetn`` is held low for 1–4 cycles at some steps after the pipeline drained
(every register but the LUT back to its reset value, the counters 0; a list left open is
abandoned: its records sent, no trailer) and after some steps with words in flight
(``aresetn_wait``, :data:`ARESETN_NOW`: the lists before it whole, then at most one list's
first records, no trailer). Not drawn: ``m_axis_state`` (the Verilator build has none; the
cocotb bench :mod:`dptbd.sim.benches.axi` checks it).
"""

from __future__ import annotations

import collections
import dataclasses
import time

import numpy as np

from dptbd.config import DPConfig
from dptbd.hw.register_map import FAULTS
from dptbd.sim.axi.actions import ACTIONS, REFUSALS, Drawer, fill_checks
from dptbd.sim.axi.stimulus import FAULT_KINDS, Beats, clean_beats, with_fault
from dptbd.sim.verilator.axi import OKAY

__all__ = ["AXI_FAULTS", "ACTIONS", "REFUSALS", "NOW_SWEEP", "NOW_WAIT", "ARESETN_NOW",
           "AxiPlan",
           "draw_run", "check_run"]

#: What an AXI case's runs may draw (``Case.faults``): the frame-sync fault classes,
#: soft resets, ``aresetn`` pulses, run-time settings (with refused values,
#: ``VIDEO_INPUT``, ``IRQ_ENABLE``), LUT writes (whole tables, single entries, refused codes
#: and strobes), refused bus accesses, counter clears.
AXI_FAULTS = (*FAULT_KINDS, "soft_reset", "aresetn", "settings", "lut", "bus",
              "clear_counters")

@dataclasses.dataclass(frozen=True)
class AxiPlan:
    """One drawn run: the beats, the steps, the stall densities, what was drawn."""

    beats: Beats
    steps: list
    valid_gap: float
    ready_pause: float
    notes: tuple
    drawn: dict                  # ACTIONS and REFUSALS -> how many times
    pulses: np.ndarray = None    # the frame monitor's pulses (fault_pulse_array)


def _stream(cfg: DPConfig, frames: np.ndarray, kinds, rng, drawn
            ) -> tuple[Beats, list[int], list]:
    """The frames as beats with faults of ``kinds``; the beats where frames start; the
    notes."""
    parts, starts, notes, at, t = [], [], [], 0, 0
    while t < len(frames):
        n = int(min(len(frames) - t, rng.integers(1, 5)))
        if n >= 2 and rng.random() < 0.3 and kinds:
            kind = kinds[int(rng.integers(0, len(kinds)))]
            part = with_fault(cfg, frames[t:t + n], kind)
            drawn[kind] += 1
            notes.append(f"{kind} at beat {at}")
        else:
            part = clean_beats(frames[t:t + n])
        starts += [at + i for i in np.flatnonzero(part.first)] or [at]
        parts.append(part)
        at += len(part)
        t += n
    beats = Beats(*(np.concatenate(arrays) for arrays in
                    zip(*(dataclasses.astuple(part) for part in parts))))
    return beats, starts, notes


def _positions(cfg: DPConfig, n_beats: int, starts: list[int], rng) -> list[int]:
    """Sorted step boundaries: frame starts, line starts, inside a frame's first or last
    row, anywhere."""
    out = []
    for _ in range(int(rng.integers(4, 12))):
        pick = rng.random()
        start = int(starts[int(rng.integers(0, len(starts)))])
        if pick < 0.3:
            out.append(start)
        elif pick < 0.45:
            at = int(rng.integers(0, n_beats))
            out.append(at - at % cfg.width)
        elif pick < 0.6:                        # inside a frame's first or last row
            row = 0 if rng.random() < 0.5 else cfg.height - 1
            out.append(min(n_beats, start + row * cfg.width + int(rng.integers(1, cfg.width))))
        else:
            out.append(int(rng.integers(0, n_beats + 1)))
    return sorted(out)


#: Soft resets of ``"now"`` that a run without input gaps draws besides its steps' (at beats
#: drawn anywhere, each alone in its step), the j-th (from 0) after j idle cycles: at full
#: input speed the j-th finds L - j words in flight (0 from j = L on; the builds' L is 17).
NOW_SWEEP = 20
#: Probability of an ``aresetn`` with words in flight after a step (``aresetn_wait``: held
#: low 1–4 cycles at a beat drawn in the step's stretch, after 0 … :data:`NOW_WAIT` idle
#: cycles; its own random stream, so the rest of a seed's run is drawn as without it).
ARESETN_NOW = 0.1
#: Idle cycles before a soft reset of ``"now"``: 0 half the time, else uniform in
#: 1 … ``NOW_WAIT`` (the builds' L is 17), so that it finds every number of words in flight.
NOW_WAIT = 20


def _density(band: int, rng) -> float:
    """A stall density in band 0 (none: 0), 1 (light: below 0.35) or 2 (heavy: 0.35 up
    to :data:`~dptbd.sim.campaign.MAX_STALL`), the bands of
    :data:`dptbd.sim.coverage.bins.BANDS`."""
    from dptbd.sim.campaign import MAX_STALL
    from dptbd.sim.coverage.bins import BANDS

    _, lo, hi = BANDS[band]
    return 0.0 if band == 0 else float(rng.uniform(lo, min(hi, MAX_STALL)))


def _wait(rng) -> int:
    return 0 if rng.random() < 0.5 else int(rng.integers(1, NOW_WAIT + 1))


def draw_run(case, seed: int) -> AxiPlan:
    """Run ``seed`` of the AXI case ``case`` (a :class:`~dptbd.sim.campaign.Case`); an
    ``"axi_store"`` case's register traffic uses the store build's register map
    (:class:`~dptbd.sim.axi.actions.Drawer`)."""
    from dptbd.sim.campaign import hostile_frames

    cfg = case.cfg
    # at P pixels per clock the stream and the step positions are drawn in beats (the
    # beat configuration's W/P columns), then each beat widened to P pixels (_widen)
    geometry = cfg.beat_config()
    store = cfg.axi_store(**dict(case.store or {})) if case.design == "axi_store" else None
    rng = np.random.default_rng([seed, 0xA71])
    drawn = collections.Counter({k: 0 for k in (*ACTIONS, *REFUSALS, *FAULT_KINDS)})
    frames = hostile_frames(geometry, case.frames, rng)
    allowed = set(case.faults)
    beats, starts, notes = _stream(geometry, frames, [k for k in FAULT_KINDS if k in allowed],
                                   rng, drawn)
    gap, pause = (_density(band, rng) for band in divmod(seed % 9, 3))
    d = Drawer(cfg, rng, drawn, np.random.default_rng([seed, 0xA73]), store=store)
    steps = []
    regmap = d.map
    sweep = (sorted(int(b) for b in rng.integers(0, len(beats) + 1, size=NOW_SWEEP))
             if gap == 0 and "soft_reset" in allowed else [])
    waits = list(range(len(sweep)))
    hard = np.random.default_rng([seed, 0xA72])         # aresetn with words in flight
    for stop in [*_positions(geometry, len(beats), starts, rng), len(beats)]:
        while sweep and sweep[0] < stop:        # soft resets with 0 … L words in flight
            steps.append({"soft_reset": "now", "soft_reset_wait": waits.pop(0),
                          "stop": sweep.pop(0)})
            drawn["soft_reset_now"] += 1
        step = {}
        if rng.random() < 0.35:
            d.check(step)
            if rng.random() < 0.3 and "clear_counters" in allowed:
                step["clear_counters"] = True
                drawn["clear_counters"] += 1
            if rng.random() < 0.5:
                bits = int(rng.integers(1, 2**32))
                step.setdefault("bus", []).append(["w", regmap["ERROR"].address, bits, 0xF,
                                                   OKAY])
                drawn["w1c_error"] += 1
        if rng.random() < 0.08 and "aresetn" in allowed:
            step["aresetn"] = int(rng.integers(1, 5))    # cycles held low
            d.reset_values()
            drawn["aresetn"] += 1
        if rng.random() < 0.2 and "soft_reset" in allowed:
            if rng.random() < 0.5:
                step["soft_reset"] = True
                drawn["soft_reset"] += 1
            else:                                        # with words still in flight
                step["soft_reset"] = "now"
                step["soft_reset_wait"] = _wait(rng)
                drawn["soft_reset_now"] += 1
        for p, action, what in ((0.4, d.settings, "settings"),
                                (0.3, d.refused_setting, "settings"),
                                (0.2, d.strobed, "settings"), (0.1, d.no_sof, "settings"),
                                (0.15, d.irq_enable, "settings"), (0.3, d.lut_table, "lut"),
                                (0.3, d.lut_entries, "lut")):
            if rng.random() < p and what in allowed:
                action(step)
        for _ in range(int(rng.integers(0, 3)) if "bus" in allowed else 0):
            d.bus(step)
        if rng.random() < 0.2:
            step.setdefault("bus", []).append(["w", regmap["IRQ_STATUS"].address, 3, 0xF,
                                               OKAY])
            drawn["w1c_irq"] += 1
        step["stop"] = stop
        steps.append(step)
        begin = steps[-2]["stop"] if len(steps) > 1 else 0
        if hard.random() < ARESETN_NOW and "aresetn" in allowed and stop > begin + 1:
            # after the step's operations, at a beat drawn in its stretch, 0 … NOW_WAIT
            # idle cycles after the last beat
            step["stop"] = int(hard.integers(begin + 1, stop))
            steps.append({"aresetn": int(hard.integers(1, 5)), "aresetn_wait": _wait(hard),
                          "stop": stop})
            d.reset_values()
            drawn["aresetn_now"] += 1
    last = {"stop": len(beats)}
    d.check(last)                                        # everything, after the last beat
    steps.append(last)
    if any(s.get("clear_counters") for s in steps):      # the counters read 0 right after
        j = max(i for i, s in enumerate(steps) if s.get("clear_counters"))
        follow = {"stop": steps[j - 1]["stop"] if j else 0}
        d.check(follow)
        follow["check"] = {name: 0 for name in ("FRAMES", "SEGMENTS", "LISTS", "SATURATED",
                                               *(f"FAULT_{k.upper()}" for k in FAULTS))}
        steps[j]["stop"], follow["stop"] = follow["stop"], steps[j]["stop"]
        steps.insert(j + 1, follow)
    if cfg.pixels_per_clock > 1:
        beats, steps = _widen(cfg, beats, steps, np.random.default_rng([seed, 0xA74]))
    pulses = fill_checks(cfg, beats, steps, store)
    notes = [f"gaps {gap:.2f}, back-pressure {pause:.2f}", f"{len(steps)} steps",
             *notes, "drawn " + ", ".join(f"{k} {v}" for k, v in drawn.items() if v)]
    return AxiPlan(beats, steps, gap, pause, tuple(notes), dict(drawn), pulses)


def _widen(cfg: DPConfig, beats: Beats, steps: list, rng) -> tuple[Beats, list]:
    """A run drawn in beats of the beat configuration as P pixels per beat: beat i's pixel
    becomes pixel P*i (its lane 0, with its ``tuser[0]``), lanes 1 … P-1 take the same value
    or a random one (half the beats each), ``tlast`` on lane P-1; every step's ``stop``
    (a beat index) times P."""
    p = cfg.pixels_per_clock
    n = len(beats)
    pixel = np.repeat(np.asarray(beats.pixel, dtype=np.int64), p).reshape(n, p)
    fresh = rng.random(n) < 0.5
    pixel[fresh, 1:] = rng.integers(0, cfg.pixel_max + 1, size=(int(fresh.sum()), p - 1))
    first = np.zeros((n, p), dtype=bool)
    last = np.zeros((n, p), dtype=bool)
    first[:, 0] = beats.first
    last[:, -1] = beats.last
    wide = Beats(pixel.ravel(), first.ravel(), last.ravel())
    return wide, [{**step, "stop": step["stop"] * p} for step in steps]


def check_run(case, seed: int, root: str | None = None, coverage: str | None = None):
    """Build (cached), run and check run ``seed`` of the AXI case ``case``: a
    :class:`~dptbd.sim.campaign.RunOutcome` (``words_out``: candidate words and checked
    register responses) with its bins; with ``coverage`` (a file) on the coverage build, its
    coverage data written there; a case that saturates on purpose gives no
    :class:`~dptbd.config.EnergyWidthWarning`."""
    import warnings

    from dptbd.config import EnergyWidthWarning
    from dptbd.sim.campaign import RunOutcome
    from dptbd.sim.coverage.bins import axi_bins
    from dptbd.sim.verilator import build
    from dptbd.sim.verilator.axi import check_axi

    start = time.perf_counter()
    sim = build(case.cfg, "axi", root=root, coverage=coverage is not None,
                family=case.family)
    plan = draw_run(case, seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        result = check_axi(sim, plan.beats, plan.steps, valid_gap=plan.valid_gap,
                           ready_pause=plan.ready_pause, seed=seed, pulses=plan.pulses,
                           coverage=coverage)
        p = case.cfg.pixels_per_clock       # words in flight at a soft reset: beats
        run = result.run if p == 1 else dataclasses.replace(
            result.run, accept_cycles=result.run.accept_cycles[::p])
        bins = axi_bins(case.cfg, plan.beats, plan.steps, passed=result.passed,
                        latency=sim.latency, valid_gap=plan.valid_gap,
                        ready_pause=plan.ready_pause, run=run)
    report = "" if result.passed else f"seed {seed}: {result.report()}"
    return RunOutcome(case.name, seed, result.passed, report, len(plan.beats),
                      len(result.run.out_words) + len(result.run.op_resp), result.run.cycles,
                      result.run.sim_seconds, time.perf_counter() - start, plan.notes, bins)

