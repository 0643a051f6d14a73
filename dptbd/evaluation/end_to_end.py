"""The detection chain end to end over seeds: confirmed targets, false tracks, frames until output.

One run is one seed of a named scenario through the whole chain of ``dptbd run``
(:func:`dptbd.evaluation.run.job.prepare`, then :func:`dptbd.evaluation.chain.run_pipeline`:
the DP over K = 6 frame segments, the candidate lists, the DSP association with its default
settings), scored against the ground truth by :func:`dptbd.dsp.track_metrics.evaluate_tracks`
(:func:`run_outcome`). :func:`run_chain` runs a list of seeds on the execution layer
(:mod:`dptbd.evaluation.execution`, one task per seed, results in seed order whatever the
workers) and summarises them (:class:`ChainSummary`). The metrics are defined in
``docs/association.md`` ("The chain end to end"):

* a target's **frames until output**: frames from its appearance to the end of the list
  (segment) in which its track was confirmed (``TargetTrackResult.frames_until_output``);
  None when it was never confirmed;
* a **false track**: a confirmed track that belongs to no target;
* a **clean run**: every target confirmed and no false track;
* the summary's **median frames until output**: the median over every confirmed (run,
  target) pair, with its distribution-free 95 % interval
  (:func:`dptbd.evaluation.stats.median_interval`).

Scenarios (:data:`SCENARIOS`): ``paper001-experiment-2`` (``dptbd run``'s built-in scenario),
``manoeuvring`` and ``crossing`` (:mod:`dptbd.scenes.chain`), each with the built-in
scenario's DP, ADC, false-alarm rate and association; ``lists`` is ``"ideal"`` (each
segment's own n largest pixels: the lists of the chain comparison's reference figures in
``docs/tracking.md``) or ``"gateware"`` (the segmenter's lists, ``dptbd run``'s default).
"""

from __future__ import annotations

import dataclasses
import re
import statistics
from typing import Any

from dptbd.dsp.track_metrics import evaluate_tracks
from dptbd.errors import DptbdError
from dptbd.evaluation.chain import LISTS, run_pipeline
from dptbd.evaluation.execution import job_execution, run_tasks
from dptbd.evaluation.run.scenario import Scenario, TargetSpec, default_scenario
from dptbd.evaluation.stats import median_interval, wilson_interval
from dptbd.model.segmentation import count_for_rate
from dptbd.scenes import chain as chain_scenes

__all__ = ["SCENARIOS", "ChainError", "RunOutcome", "ChainSummary", "scenario", "parse_seeds",
           "variant", "run_outcome", "run_chain"]

#: The named scenarios, the built-in one first.
SCENARIOS = ("paper001-experiment-2", "manoeuvring", "crossing")
#: Most seeds one job runs.
MAX_SEEDS = 100_000


class ChainError(DptbdError):
    """A bad scenario name, seed range or lists choice."""


def _spec(target) -> TargetSpec:
    turns = tuple({"frame": t.frame, **({"degrees": t.degrees} if t.degrees is not None
                                        else {"velocity": t.velocity})} for t in target.turns)
    return TargetSpec(target.start, target.velocity, turns=turns)


def scenario(name: str) -> Scenario:
    """The named scenario (:data:`SCENARIOS`), seed 0, the built-in scenario's settings."""
    base = default_scenario()
    if name == SCENARIOS[0]:
        return base
    if name == "manoeuvring":
        targets = chain_scenes.manoeuvring_targets(base.snr)
    elif name == "crossing":
        targets = chain_scenes.crossing_targets(base.snr)
    else:
        raise ChainError(f"unknown scenario {name!r}; allowed: {', '.join(SCENARIOS)}")
    return base.replace(name=name, targets=tuple(_spec(t) for t in targets))


def parse_seeds(text: str) -> range:
    """``"A-B"`` (A <= B, both integers >= 0; or one integer ``"A"``) as ``range(A, B + 1)``."""
    m = re.fullmatch(r"(\d+)(?:-(\d+))?", str(text))
    if m is None:
        raise ChainError(f"seeds must be A-B (integers 0 <= A <= B) or A, got {text!r}")
    first = int(m.group(1))
    last = first if m.group(2) is None else int(m.group(2))
    if last < first:
        raise ChainError(f"seeds A-B need A <= B, got {text!r}")
    if last - first + 1 > MAX_SEEDS:
        raise ChainError(f"seeds A-B may hold at most {MAX_SEEDS} seeds, got {text!r} "
                         f"({last - first + 1})")
    return range(first, last + 1)


@dataclasses.dataclass(frozen=True)
class RunOutcome:
    """One seed through the chain.

    ``frames_until_output[j]``: target j's frames until output (None: never confirmed);
    ``false_tracks``: confirmed tracks that belong to no target; ``lists``: lists the DSP
    received.
    """

    seed: int
    frames_until_output: tuple
    false_tracks: int
    lists: int

    @property
    def all_confirmed(self) -> bool:
        return all(f is not None for f in self.frames_until_output)

    @property
    def clean(self) -> bool:
        """Every target confirmed and no false track."""
        return self.all_confirmed and self.false_tracks == 0


@dataclasses.dataclass(frozen=True)
class ChainSummary:
    """A scenario over seeds: the runs in seed order and what they add up to."""

    scenario: str
    lists: str
    seeds: range
    runs: tuple[RunOutcome, ...]

    @property
    def clean(self) -> int:
        return sum(r.clean for r in self.runs)

    @property
    def all_confirmed(self) -> int:
        return sum(r.all_confirmed for r in self.runs)

    @property
    def with_false_track(self) -> int:
        return sum(r.false_tracks > 0 for r in self.runs)

    @property
    def false_tracks(self) -> int:
        return sum(r.false_tracks for r in self.runs)

    @property
    def frames_until_output(self) -> list[int]:
        """Every confirmed (run, target) pair's frames until output, runs in seed order."""
        return [f for r in self.runs for f in r.frames_until_output if f is not None]

    @property
    def median(self) -> float:
        """Median frames until output over the confirmed (run, target) pairs (nan: none)."""
        values = self.frames_until_output
        return float(statistics.median(values)) if values else float("nan")

    @property
    def median_interval(self) -> tuple[float, float]:
        return median_interval(self.frames_until_output)

    def lines(self) -> list[str]:
        """The summary as text, one figure a line."""
        n = len(self.runs)
        seeds = f"{self.seeds.start}-{self.seeds.stop - 1}"

        def wil(k: int) -> str:
            lo, hi = wilson_interval(k, n)
            return f"{k}/{n} [{lo:.2f}, {hi:.2f}]"

        lo, hi = self.median_interval
        return [f"scenario {self.scenario}, seeds {seeds}, {self.lists} lists",
                f"clean runs (all targets confirmed, no false track): {wil(self.clean)}",
                f"all targets confirmed: {wil(self.all_confirmed)}",
                f"runs with a false track: {wil(self.with_false_track)}; false tracks "
                f"{self.false_tracks} ({self.false_tracks / n:.2f} per run)",
                f"frames until output: median {self.median:g} [{lo:g}, {hi:g}] over "
                f"{len(self.frames_until_output)} confirmed target(s)"] + [
                f"target {j + 1}: confirmed {wil(len(fs))}, median frames until output "
                + (f"{statistics.median(fs):g}" if fs else "-")
                for j, fs in enumerate(self.per_target())]

    def per_target(self) -> list[list[int]]:
        """Per target, its frames until output in the runs that confirmed it."""
        n = len(self.runs[0].frames_until_output) if self.runs else 0
        return [[r.frames_until_output[j] for r in self.runs
                 if r.frames_until_output[j] is not None] for j in range(n)]


def _check_lists(lists: Any) -> str:
    if lists not in LISTS:
        raise ChainError(f"lists must be one of {', '.join(map(repr, LISTS))}, got {lists!r}")
    return lists


def run_outcome(sc: Scenario | str, seed: int, lists: str = "ideal") -> RunOutcome:
    """One seed of scenario ``sc`` (a name of :data:`SCENARIOS` or a :class:`Scenario`)."""
    from dptbd.evaluation.run.job import prepare

    sc = scenario(sc) if isinstance(sc, str) else sc
    sc = sc.replace(seed=int(seed), lists=_check_lists(lists))
    sc.check()
    inp = prepare(sc)
    result = run_pipeline(inp.frames, inp.cfg, inp.count, inp.assoc, lists=sc.lists)
    n_lists = len(result.segments.end_frames)
    ev = evaluate_tracks(result.tracks, result.positions, inp.truth, result.cfg, n_lists)
    return RunOutcome(int(seed), tuple(t.frames_until_output for t in ev.targets),
                      ev.false_tracks, n_lists)


def variant(sc: Scenario | str, *, dp: dict | None = None, association: dict | None = None,
            false_alarm_rate: float | None = None) -> Scenario:
    """Scenario ``sc`` with ``[dp]`` (DPConfig fields, e.g. ``segment_frames``),
    ``[association]`` (AssociationConfig fields) and ``[segmentation] false_alarm_rate`` (the
    fraction of pixels per list: n, the list length) overridden, checked
    (:class:`~dptbd.evaluation.run.scenario.ScenarioError` names a bad key or value): another
    chain on the same scenes."""
    sc = scenario(sc) if isinstance(sc, str) else sc
    sc = sc.replace(dp={**sc.dp, **(dp or {})},
                    association={**sc.association, **(association or {})})
    if false_alarm_rate is not None:
        sc = sc.replace(false_alarm_rate=false_alarm_rate)
    sc.check()
    pixels = sc.height * sc.width
    if sc.simulated and count_for_rate(sc.false_alarm_rate, pixels) < 1:
        raise ChainError(f"false_alarm_rate {sc.false_alarm_rate:g} keeps no candidate point "
                         f"of {pixels} pixels; allowed: at least {0.5 / pixels:g} (n = 1)")
    return sc


def run_chain(sc: Scenario | str, seeds: range | str, *, lists: str = "ideal",
              workers: int | None = 1, scheduler: str | None = None) -> ChainSummary:
    """Every seed of ``seeds`` (a range or ``"A-B"``) of scenario ``sc`` through the chain.

    ``sc``: a name of :data:`SCENARIOS` (today's default chain) or a :class:`Scenario`
    (e.g. :func:`variant`: another K or association on the same scenes). Refused before any
    run: an unknown scenario name, a bad seed range, a bad ``lists``, a bad worker count.
    The result does not depend on ``workers``.
    """
    sc = scenario(sc) if isinstance(sc, str) else sc
    seeds = parse_seeds(seeds) if isinstance(seeds, str) else seeds
    if not isinstance(seeds, range) or len(seeds) == 0 or seeds.start < 0 or seeds.step != 1:
        raise ChainError(f"seeds must be a non-empty range of integers >= 0 in steps of 1, "
                         f"got {seeds!r}")
    _check_lists(lists)
    sc.replace(seed=seeds.start, lists=lists).check()
    execution = job_execution(workers, scheduler=scheduler, tasks=len(seeds))
    runs, _ = run_tasks(run_outcome, [(sc, s, lists) for s in seeds], execution)
    return ChainSummary(sc.name, lists, seeds, tuple(runs))
