"""Paper 000's experiments through its DP variants on the gateware, against float.

``dptbd paper000`` (``docs/detectors.md`` §1.6) runs, on the same seeded scenes,

* §5.1 / §5.2 (:data:`dptbd.evaluation.detectors.paper000.CASES`: eq (15) and eq (24) at
  4.08 dB, eqs (19)–(23) at 6 dB and 3 dB), one scene per seed ``0 … seeds - 1``;
* the SNR-gain curve of §1.5 (:func:`dptbd.evaluation.detectors.paper000.snr_gain`'s
  protocol and seeds: per-cell Pfa thresholds from noise-only scenes, the likelihood DP
  recalibrated at each SNR, detected = a gate cell above the threshold),

each variant twice: **fixed point** (:func:`dptbd.evaluation.paper000.variants.fixed_maps`,
on the golden model or — ``engine="rtl"`` — on the compiled gateware with every state word
of every frame checked bit for bit against :mod:`dptbd.model.family.fast`) and **float**
(:func:`~dptbd.evaluation.paper000.variants.float_maps`, the float runs of §1.4–1.5).
Fixed and float are compared as ``dptbd compare`` compares them: on the same scenes, with
paired intervals (:func:`dptbd.evaluation.compare.report.paired_difference`, clustered by
scene) and paired-bootstrap SNR losses (:func:`dptbd.evaluation.snr_loss.bootstrap_losses`).

The scenes run in chunks as tasks on the execution layer
(:mod:`dptbd.evaluation.execution`); every number depends only on the seeds, never on the
chunking or the workers. :mod:`dptbd.evaluation.paper000.report` writes the tables.
"""

from __future__ import annotations

import dataclasses
import time
from typing import Sequence

import numpy as np

from dptbd.evaluation.detectors import paper000
from dptbd.evaluation.detectors._checks import DetectorError, check_int, check_prob
from dptbd.evaluation.execution import job_execution, map_tasks
from dptbd.evaluation.paper000.variants import (ENGINES, fixed_maps, fixed_variant, float_maps,
                                                quantise_scene)
from dptbd.scenes import synthetic as scenes

__all__ = ["GAIN_DPS", "Paper000Spec", "Paper000Result", "gain_case", "run_paper000"]

#: The DPs of the gain curve (the DP rows of paper000.GAIN_DETECTORS).
GAIN_DPS = ("DP eq (15)", "DP eq (24)", "DP eqs (19)-(23)")
SIZE = 64


@dataclasses.dataclass(frozen=True)
class Paper000Spec:
    """What :func:`run_paper000` runs (checked on construction, messages naming the field).

    ``cases``: labels of :data:`paper000.CASES` (empty: none); ``seeds``: scenes per case;
    ``gain``: DPs of :data:`GAIN_DPS` on the gain curve (empty: no curve) at
    ``gain_snrs_db`` with ``gain_trials`` target and ``noise_trials`` noise-only scenes
    per SNR, per-cell ``pfa``, base seed ``seed`` (§1.5: 5000); ``frames`` per scene.
    """

    engine: str = "rtl"
    cases: tuple[str, ...] = tuple(c.label for c in paper000.CASES)
    seeds: int = 20
    gain: tuple[str, ...] = GAIN_DPS
    gain_snrs_db: tuple[float, ...] = tuple(float(s) for s in range(0, 16))
    gain_trials: int = 100
    noise_trials: int = 100
    pfa: float = 1e-3
    seed: int = 5000
    frames: int = 20
    chunk: int = 25

    def __post_init__(self) -> None:
        if self.engine not in ENGINES:
            raise DetectorError(f"engine must be one of {ENGINES}, got {self.engine!r}")
        labels = tuple(c.label for c in paper000.CASES)
        for name, allowed in (("cases", labels), ("gain", GAIN_DPS)):
            values = tuple(getattr(self, name))
            bad = [v for v in values if v not in allowed]
            if bad:
                raise DetectorError(f"{name} must be among {', '.join(allowed)}, got {bad[0]!r}")
            object.__setattr__(self, name, values)
        if not self.cases and not self.gain:
            raise DetectorError("cases and gain are both empty: nothing to run")
        for name in ("seeds", "gain_trials", "noise_trials", "chunk"):
            object.__setattr__(self, name, check_int(name, getattr(self, name), 1, 100_000))
        object.__setattr__(self, "frames", check_int("frames", self.frames, 2, 64))
        object.__setattr__(self, "seed", check_int("seed", self.seed, 0))
        object.__setattr__(self, "pfa", check_prob("pfa", self.pfa))
        snrs = tuple(float(s) for s in self.gain_snrs_db)
        if self.gain and (not snrs or any(b <= a for a, b in zip(snrs, snrs[1:]))):
            raise DetectorError(f"gain_snrs_db must be a strictly increasing non-empty list, "
                                f"got {list(snrs)}")
        object.__setattr__(self, "gain_snrs_db", snrs)


@dataclasses.dataclass
class Paper000Result:
    """Per-scene measurements, fixed and float, and what the RTL checked.

    ``cases[label]``: ``{"fixed": stats, "float": stats}`` with ``stats`` name -> ``(seeds,)``
    arrays (:func:`paper000.map_statistics`'s fields, V_T-keyed ones as ``false_tracks@V_T``,
    plus ``target_is_max``); ``gain[dp]``: ``{"fixed": (S, N) bool, "float": (S, N) bool,
    "thresholds": {...}}`` detections per SNR and scene; ``rtl[variant]``: the
    :class:`~dptbd.sim.rtl.trials.RTLTally` summed over the variant's runs.
    """

    spec: Paper000Spec
    cases: dict
    gain: dict
    rtl: dict
    seconds: float
    workers: int


def gain_case(dp: str, snr_db: float) -> paper000.Case:
    """The :class:`paper000.Case` of one gain-curve DP at one SNR (ε = 0.85, σ = 1, eq (22)
    with α₂₂ = 1, as :func:`paper000.snr_gain`)."""
    merit = "likelihood" if dp == "DP eqs (19)-(23)" else "amplitude"
    return paper000.Case(dp, "§1.5", snr_db, merit, dp != "DP eq (15)", (0.0,))


# ---- tasks (pure functions of their arguments) --------------------------------------------

def _case_task(case, variant, builds, engine, seeds: Sequence[int], frames: int) -> dict:
    """One chunk of seeds of a §5.1/§5.2 case: per-seed statistics, fixed and float."""
    scs = [scenes.paper000_scenario(case.snr_db, seed=s, frames=frames) for s in seeds]
    cell = scs[0].truth[0].pixel[-1]
    floats = np.stack([sc.frames for sc in scs])
    fixed, tally = fixed_maps(variant, quantise_scene(floats), engine, builds,
                              label=f"variant {variant.name!r} (trial = seed): ",
                              first_trial=seeds[0])
    out = {"rtl": tally}
    for kind, maps in (("fixed", fixed), ("float", float_maps(case, floats))):
        rows = [paper000.map_statistics(m, cell, case.thresholds) for m in maps]
        stats = {k: np.array([r[k] for r in rows]) for k in
                 ("target", "noise_max", "target_rank", "two_track_level")}
        stats["target_is_max"] = (stats["target"] > stats["noise_max"]).astype(np.int64)
        for v in case.thresholds:
            stats[f"false_tracks@{v:g}"] = np.array([r["false_tracks"][v] for r in rows])
            stats[f"false_cells@{v:g}"] = np.array([r["false_cells"][v] for r in rows])
        out[kind] = stats
    return out


def _gain_frames(snr_db: float | None, seed: int, first: int, stop: int, frames: int):
    """§1.5's scenes: noise-only (base ``seed + 1``) or with the target (base ``seed``)."""
    if snr_db is None:
        return scenes.make_noise((SIZE, SIZE), frames, seed=seed + 1, trials=stop - first,
                                 first_trial=first)
    return scenes.paper000_scenario(snr_db, seed=seed, trials=stop - first, first_trial=first,
                                    frames=frames).frames


def _gain_task(case, variant, builds, engine, snr_db, seed, first, stop, frames) -> dict:
    """One chunk of gain-curve scenes: noise-only (``snr_db`` None: every cell of the final
    maps) or with the target (the largest value in the target's gate, per scene)."""
    floats = _gain_frames(snr_db, seed, first, stop, frames)
    scene = "noise only" if snr_db is None else f"SNR {snr_db:g} dB"
    fixed, tally = fixed_maps(variant, quantise_scene(floats), engine, builds,
                              label=f"variant {variant.name!r} ({scene}): ", first_trial=first)
    out = {"rtl": tally}
    cell = scenes.paper000_scenario(0.0, noise=False, frames=frames).truth[0].pixel[-1]
    gate = paper000.gate_mask((SIZE, SIZE), cell)
    for kind, maps in (("fixed", fixed), ("float", float_maps(case, floats))):
        out[kind] = maps if snr_db is None else maps[:, gate].max(axis=1)
    return out


# ---- the job ---------------------------------------------------------------------------------

def _bounds(n: int, chunk: int):
    return [(a, min(a + chunk, n)) for a in range(0, n, chunk)]


def _plan(spec: Paper000Spec) -> list[tuple]:
    """Every task as ``(kind, key, case, variant, arguments)``: kind "case", "noise", "target"."""
    by_label = {c.label: c for c in paper000.CASES}
    plan = []
    for label in spec.cases:
        case = by_label[label]
        variant = fixed_variant(case, frames=spec.frames)
        for a, b in _bounds(spec.seeds, spec.chunk):
            plan.append(("case", label, case, variant, (list(range(a, b)),)))
    for dp in spec.gain:
        for j, snr in enumerate(spec.gain_snrs_db):
            case = gain_case(dp, snr)
            variant = fixed_variant(case, frames=spec.frames)
            if j == 0 or case.merit == "likelihood":  # the amplitude DPs' noise maps do not depend on the SNR
                for a, b in _bounds(spec.noise_trials, spec.chunk):
                    plan.append(("noise", (dp, snr), case, variant, (None, a, b)))
            for a, b in _bounds(spec.gain_trials, spec.chunk):
                plan.append(("target", (dp, snr), case, variant, (snr, a, b)))
    return plan


def _builds(spec: Paper000Spec, plan: list[tuple]) -> dict:
    """The compiled gateware of every configuration (by its mapping), refused up front."""
    if spec.engine != "rtl":
        return {}
    from dptbd.sim.rtl.trials import check_configs, prepare_builds

    configs = {}
    for _, key, case, variant, _ in plan:
        name = variant.name if isinstance(key, str) else f"{key[0]} at {key[1]:g} dB"
        configs.setdefault(_config_key(variant.cfg), (name, variant.cfg))
    check_configs(configs.values())
    return {k: prepare_builds(cfg, segmenter=False) for k, (_, cfg) in configs.items()}


def _config_key(cfg) -> str:
    import json

    return json.dumps(cfg.to_mapping(), sort_keys=True, default=str)


def _run_task(kind, case, variant, builds, spec: Paper000Spec, args) -> dict:
    if kind == "case":
        return _case_task(case, variant, builds, spec.engine, args[0], spec.frames)
    return _gain_task(case, variant, builds, spec.engine, args[0], spec.seed, args[1], args[2],
                      spec.frames)


def run_paper000(spec: Paper000Spec, *, workers: int | None = None, scheduler: str | None = None,
                 dashboard: bool = False, progress: bool = False) -> Paper000Result:
    """Run ``spec``'s scenes on its engine and on float, in tasks on the execution layer.

    Raises
    ------
    dptbd.errors.ConfigError
        ``engine="rtl"`` and a variant the gateware cannot build, before any run
        (:func:`dptbd.sim.rtl.trials.check_configs`).
    dptbd.sim.rtl.trials.RTLMismatchError
        An RTL state word differs from the golden model: variant, scene, frame, row, column
        and field.
    """
    plan = _plan(spec)
    execution = job_execution(workers, scheduler=scheduler, dashboard=dashboard,
                              tasks=len(plan))
    builds = _builds(spec, plan)
    tasks = [(kind, case, variant, builds.get(_config_key(variant.cfg)), spec, args)
             for kind, _, case, variant, args in plan]
    bar = None
    if progress:
        from tqdm import tqdm
        bar = tqdm(total=len(tasks), unit="task", desc="paper000", smoothing=0.1)
    try:
        with execution.client() as client:
            start = time.perf_counter()
            parts = map_tasks(_run_task, tasks, client, bar=bar)
            seconds = time.perf_counter() - start
    finally:
        if bar is not None:
            bar.close()
    return _collect(spec, plan, parts, seconds, execution.workers)


def _collect(spec, plan, parts, seconds, workers) -> Paper000Result:
    cases: dict = {}
    noise: dict = {}
    target: dict = {}
    rtl: dict = {}
    for (kind, key, _, variant, _), part in zip(plan, parts):
        if part["rtl"] is not None:
            name = variant.name
            rtl[name] = part["rtl"] if name not in rtl else rtl[name] + part["rtl"]
        if kind == "case":
            got = cases.setdefault(key, {"fixed": [], "float": []})
        else:
            got = (noise if kind == "noise" else target).setdefault(key, {"fixed": [], "float": []})
        got["fixed"].append(part["fixed"])
        got["float"].append(part["float"])
    out_cases = {label: {kind: {k: np.concatenate([p[k] for p in parts_]) for k in parts_[0]}
                         for kind, parts_ in got.items()} for label, got in cases.items()}
    gain: dict = {}
    for dp in spec.gain:
        det = {"fixed": [], "float": []}
        thresholds = {"fixed": [], "float": []}
        level = None
        for snr in spec.gain_snrs_db:
            if (dp, snr) in noise:
                level = {k: paper000.quantile_threshold(np.concatenate(v), spec.pfa)
                         for k, v in noise[(dp, snr)].items()}
            for kind in ("fixed", "float"):
                thresholds[kind].append(level[kind])
                det[kind].append(np.concatenate(target[(dp, snr)][kind]) > level[kind])
        gain[dp] = {k: np.array(v) for k, v in det.items()}
        gain[dp]["thresholds"] = {k: np.array(v) for k, v in thresholds.items()}
    return Paper000Result(spec, out_cases, gain, rtl, seconds, workers)
