"""The verification campaign: many parameter sets × hostile scenes × random stalls × faults,
every output word of the compiled RTL compared with the golden model.

A campaign is a list of :class:`Case` (a parameter set and a top level) and, per case, a
number of seeded runs. Each run draws, from its own seed only,

* a scene of frames mixing 001's noise with targets on edges and corners, manoeuvring
  targets, all-maximum, all-zero, constant and checkerboard frames (ties) and uniform noise
  (:func:`hostile_frames`);
* input gap and output back-pressure densities, each uniform in [0, 0.7];
* the case's faults (:class:`Case` ``faults``): resets at random cycles, start-of-frame
  markers in the middle of a frame, frames cut short or run long, run-time LUT rewrites
  between and inside frames, an external store powered up with garbage, run-time settings
  (K, n, s) rewritten between and inside frames;

and is checked by :func:`dptbd.sim.rtl_check.check_stream` against the promise of
``docs/gateware.md`` ("Faults and what the output promises"). The 4-state question — an
X-initialised or garbage external store never reaches an output — is asked of Icarus
(:func:`dptbd.sim.x_store.run_x_store_check`): Verilator is 2-state.

:func:`run_campaign` runs the runs on the Dask execution layer
(:mod:`dptbd.evaluation.execution`: in this process, local worker processes or a cluster) and
returns a :class:`CampaignResult` (per case: runs, words compared, words per second, verdict;
the functional coverage bins of every run, :mod:`dptbd.sim.coverage.bins`, added up), the
same for any number of workers. ``dptbd verify`` is the
command; ``tests/sim/test_campaign.py`` runs a slice of it in the default suite.
"""

from __future__ import annotations

import dataclasses
import time
from typing import Callable, Sequence

import numpy as np

from dptbd.config import DPConfig, EnergyWidthWarning

__all__ = ["FAULTS", "Case", "RunOutcome", "CaseResult", "CampaignResult", "default_cases",
           "axi_cases", "hostile_frames", "make_run", "check_run", "check_x_store",
           "x_store_cases", "campaign_task", "campaign_tasks", "run_campaign"]

#: Fault classes a case may draw from (see :func:`make_run`).
FAULTS = ("reset", "misaligned_first", "short_frame", "long_frame", "lut", "store_garbage",
          "settings")

MAX_STALL = 0.7


@dataclasses.dataclass(frozen=True)
class Case:
    """A parameter set, a top level and what its runs may contain.

    Attributes
    ----------
    name : str
    config : dict
        :class:`~dptbd.config.DPConfig` fields (JSON-able, so a case pickles cheaply).
    design : str
        ``"dp"``, ``"core"``, ``"segmenter"`` or ``"axi"`` (:data:`dptbd.sim.verilator.DESIGNS`;
        an ``"axi"`` case draws its runs with :mod:`dptbd.sim.axi_runs`, its own faults).
    frames : int
        Frames per run (before faults cut or lengthen them).
    runs : int
        Seeded runs in a full campaign.
    faults : tuple of str
        Fault classes (:data:`FAULTS`) each run may draw.
    random_lut : bool
        The run starts by writing a random LUT (codes in [0, 2**F]).
    """

    name: str
    config: dict
    design: str
    frames: int
    runs: int
    faults: tuple[str, ...] = ()
    random_lut: bool = False

    @property
    def cfg(self) -> DPConfig:
        import warnings
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", EnergyWidthWarning)
            return DPConfig(**self.config)

    @property
    def words_per_run(self) -> int:
        return self.frames * self.config["width"] * self.config["height"]


def default_cases() -> list[Case]:
    """The campaign's parameter sets (``docs/gateware.md``, "Verification campaign")."""
    every = ("reset", "misaligned_first", "short_frame", "long_frame", "lut", "settings")
    p001 = dict(width=128, height=128, segment_frames=8, input_bits=12, energy_bits=16,
                weight_frac_bits=8)
    return [
        Case("001-128x128-k8-in12-e16", p001, "dp", 48, 32, every),
        Case("37x23-k3-in8-e12-f4", dict(width=37, height=23, segment_frames=3, input_bits=8,
                                        energy_bits=12, weight_frac_bits=4), "dp", 400, 20,
             every),
        Case("narrow-24x16-in8-e9-sat", dict(width=24, height=16, segment_frames=6,
                                            input_bits=8, energy_bits=9), "dp", 600, 16, every),
        Case("f0-64x48-k4", dict(width=64, height=48, segment_frames=4, weight_frac_bits=0),
             "dp", 300, 16, every),
        Case("f8-half-up-64x48-k5", dict(width=64, height=48, segment_frames=5,
                                         weight_frac_bits=8, rounding="half_up"),
             "dp", 300, 16, every),
        Case("r2-40x30-f6-k4", dict(width=40, height=30, segment_frames=4, radius=2,
                                    weight_frac_bits=6), "dp", 600, 16, every),
        Case("random-lut-48x32-f5", dict(width=48, height=32, segment_frames=4,
                                         weight_frac_bits=5), "dp", 500, 16, every, True),
        Case("core-96x64-garbage-store", dict(width=96, height=64, segment_frames=4),
             "core", 200, 16, every + ("store_garbage",)),
        Case("segmenter-128x128-k4", dict(width=128, height=128, segment_frames=4,
                                          input_bits=12, energy_bits=16), "segmenter", 48, 8,
             every),
        Case("segmenter-33x17-k2-n3", dict(width=33, height=17, segment_frames=2,
                                           candidate_count=3, histogram_bits=6),
             "segmenter", 400, 8, every),
        *axi_cases(),
    ]


def axi_cases() -> list[Case]:
    """The AXI top level's cases (:mod:`dptbd.sim.axi_runs`): 001's setting, a small r = 2
    one with a fractional LUT, a small binary-LUT one with B_E = 9 (bright frames saturate);
    K_max above K and small C, so that run-time K, lists at capacity and overflowing lists
    occur."""
    from dptbd.sim.axi_runs import AXI_FAULTS

    p001 = dict(width=128, height=128, segment_frames=8, input_bits=12, energy_bits=16,
                weight_frac_bits=8)
    return [
        Case("axi-001-128x128-k8", p001, "axi", 16, 4, AXI_FAULTS),
        Case("axi-37x23-r2-f4-k3", dict(width=37, height=23, segment_frames=3,
                                        max_segment_frames=5, radius=2, weight_frac_bits=4,
                                        candidate_count=4, candidate_capacity=8,
                                        histogram_bits=6), "axi", 80, 8, AXI_FAULTS),
        Case("axi-24x16-f0-k2", dict(width=24, height=16, segment_frames=2,
                                     max_segment_frames=4, weight_frac_bits=0,
                                     energy_bits=9, candidate_count=3, candidate_capacity=6,
                                     histogram_bits=6, histogram_shift=2),
             "axi", 160, 8, AXI_FAULTS),
    ]


# ---- scenes ---------------------------------------------------------------------------------

def hostile_frames(cfg: DPConfig, n_frames: int, rng: np.random.Generator) -> np.ndarray:
    """``n_frames`` integer frames mixing the cases a datapath gets wrong.

    Blocks of 1–8 frames, each block one of: 001's noise with targets entering and leaving
    through edges and corners; a manoeuvring target (its velocity changes every few frames);
    all-maximum; all-zero; a constant level; a checkerboard of two levels (ties
    everywhere); uniform noise over the whole range.
    """
    from dptbd.scenes import synthetic as scenes
    from dptbd.sim.scenarios import adc_gain, make_frames

    h, w, top = cfg.height, cfg.width, cfg.pixel_max
    out = np.empty((n_frames, h, w), dtype=np.uint16)
    t = 0
    while t < n_frames:
        n = int(min(n_frames - t, rng.integers(1, 9)))
        kind = rng.integers(0, 8)
        seed = int(rng.integers(0, 2**31))
        if kind == 0:
            block = make_frames("edges", cfg, n, seed=seed)
        elif kind == 1:
            block = make_frames("mixed", cfg, n, seed=seed)
        elif kind == 2:                                      # manoeuvring target
            pos = np.array([rng.uniform(0, h - 1), rng.uniform(0, w - 1)])
            block = np.empty((n, h, w), dtype=np.uint16)
            noise = scenes.make_scene((h, w), n, [], mu=scenes.TABLE1_MU,
                                      sigma=scenes.TABLE1_SIGMA, seed=seed)
            frames = noise.quantised(cfg.input_bits, gain=adc_gain(cfg))
            vel = rng.uniform(-2, 2, size=2)
            for k in range(n):
                if k % 3 == 2:
                    vel = rng.uniform(-2, 2, size=2)         # a turn
                pos = np.clip(pos + vel, 0, [h - 1, w - 1])
                frames[k, int(pos[0]), int(pos[1])] = top
            block = frames
        elif kind == 3:
            block = np.full((n, h, w), top, dtype=np.uint16)
        elif kind == 4:
            block = np.zeros((n, h, w), dtype=np.uint16)
        elif kind == 5:
            block = np.full((n, h, w), int(rng.integers(0, top + 1)), dtype=np.uint16)
        elif kind == 6:
            a, b = (int(v) for v in rng.integers(0, top + 1, size=2))
            board = np.where((np.add.outer(np.arange(h), np.arange(w)) % 2) == 0, a, b)
            block = np.broadcast_to(board, (n, h, w)).astype(np.uint16)
        else:
            block = rng.integers(0, top + 1, size=(n, h, w)).astype(np.uint16)
        out[t:t + n] = block
        t += n
    return out


# ---- one run --------------------------------------------------------------------------------

def _faulty_stream(cfg: DPConfig, words: np.ndarray, faults: Sequence[str],
                   rng: np.random.Generator) -> tuple[np.ndarray, list[str], list]:
    """Cut, lengthen or mark frames of a clean word stream; what was done, for the report,
    and (fault, index of the first word it touches) for the coverage bins."""
    from dptbd.hw.layouts import field_offsets, pixel_layout

    size = cfg.width * cfg.height
    first_bit = np.uint64(1) << np.uint64(field_offsets(pixel_layout(cfg))["first"]["offset"])
    n_frames = len(words) // size
    frames = [words[i * size:(i + 1) * size].copy() for i in range(n_frames)]
    notes, touched = [], []
    for fault in ("misaligned_first", "short_frame", "long_frame"):
        if fault not in faults or n_frames < 4:
            continue
        f = int(rng.integers(1, n_frames - 1))
        if fault == "misaligned_first":
            p = int(rng.integers(1, size))
            frames[f][p] |= first_bit                        # a start marker mid-frame
            notes.append(f"start-of-frame marker at pixel {p} of frame {f}")
            touched.append((fault, f, p))
        elif fault == "short_frame":
            keep = int(rng.integers(1, size))
            frames[f] = frames[f][:keep]
            notes.append(f"frame {f} cut to {keep} of {size} pixels")
            touched.append((fault, f + 1, 0))
        else:
            extra = int(rng.integers(1, size))
            tail = frames[f][:extra].copy()
            tail &= ~first_bit
            frames[f] = np.concatenate([frames[f], tail])
            notes.append(f"frame {f} runs {extra} pixels long")
            touched.append((fault, f, size))
    starts = np.cumsum([0] + [len(frame) for frame in frames])
    events = [(fault, int(starts[f] + p)) for fault, f, p in touched if p < len(frames[f])]
    return np.concatenate(frames), notes, events


def _settings_changes(cfg: DPConfig, n_words: int, rng: np.random.Generator):
    """Two or three run-time settings writes, about half of them between frames, with
    random K in [1, K_max], n in [0, C], s in [0, B_E - 1] (sampled at the next segment
    start, ``docs/gateware.md`` "Run-time settings")."""
    from dptbd.model.settings import SegmentSettings

    size = cfg.width * cfg.height
    out = []
    for _ in range(int(rng.integers(2, 4))):
        at = int(rng.integers(1, max(2, n_words)))
        if rng.random() < 0.5:
            at = (at // size) * size or size
        out.append((min(at, n_words), SegmentSettings(
            int(rng.integers(1, cfg.k_max + 1)), int(rng.integers(0, cfg.record_capacity + 1)),
            int(rng.integers(0, cfg.energy_bits)))))
    return tuple(sorted(out, key=lambda change: change[0]))


def make_run(case: Case, seed: int, latency: int | None = None):
    """The input words and :class:`~dptbd.sim.rtl_check.Stimulus` of run ``seed`` of ``case``,
    and a description of its faults; for ``design="axi"`` the
    :class:`~dptbd.sim.axi_runs.AxiPlan` (:func:`dptbd.sim.axi_runs.draw_run`). ``latency``:
    the build's DP pipeline L (then about half the runs with resets get one more early on,
    soon after the first word, when the pipeline holds 0 … L words)."""
    if case.design == "axi":
        from dptbd.sim.axi_runs import draw_run
        return draw_run(case, seed)
    return _make_run(case, seed, latency)[:3]


def _make_run(case: Case, seed: int, latency: int | None = None):
    """:func:`make_run` of a stream design and the framing faults' (fault, first word
    touched)."""
    from dptbd.sim.rtl_check import Stimulus
    from dptbd.sim.stimulus import pixel_words
    from dptbd.sim.verilator import cycle_budget

    cfg = case.cfg
    rng = np.random.default_rng([seed, 0x7E57])
    frames = hostile_frames(cfg, case.frames, rng)
    words, notes, events = _faulty_stream(cfg, pixel_words(cfg, frames), case.faults, rng)
    gap, pause = (float(v) for v in rng.uniform(0.0, MAX_STALL, size=2))
    speed = rng.random()
    if speed < 0.25:
        gap, pause = 0.0, 0.0                           # some runs at full speed
    elif speed < 0.35:
        gap = 0.0                                       # back-pressure only
    elif speed < 0.45:
        pause = 0.0                                     # input gaps only
    size = cfg.width * cfg.height
    unity = 1 << cfg.weight_frac_bits
    luts = []
    if case.random_lut:
        luts.append((0, rng.integers(0, unity + 1, size=(cfg.n_moves + 1, cfg.n_moves))))
    if "lut" in case.faults:
        for _ in range(2):
            at = int(rng.integers(1, len(words)))
            stage = rng.random()
            frame, col = (at // size) * size, max(1, at % cfg.width)
            if stage < 0.5:
                at = frame or size                      # between frames
            elif stage < 0.625:
                at = frame + col                        # in the first row
            elif stage < 0.75:
                at = frame + (cfg.height - 1) * cfg.width + col - 1     # in the last row
            luts.append((min(at, len(words)), rng.integers(0, unity + 1,
                                                           size=(cfg.n_moves + 1, cfg.n_moves))))
        notes.append(f"LUT rewritten before words {[i for i, _ in luts if i]}")
    resets = []
    if "reset" in case.faults and rng.random() < 0.7:
        budget = int(len(words) / ((1 - gap) * (1 - pause)))
        for c in sorted(rng.integers(1000, max(1001, budget), size=int(rng.integers(1, 3)))):
            if not resets or c > resets[-1][0] + 10:
                resets.append((int(c), int(rng.integers(1, 6))))
        notes.append(f"resets at cycles {[c for c, _ in resets]}")
    if latency is not None and "reset" in case.faults and rng.random() < 0.5:
        # a reset when the pipeline holds 0 … L words: the first word comes after the LUT
        # writes before word 0, then one per cycle at full speed
        early = 2 + sum(cfg.lut_entries for i, _ in luts if i == 0) \
            + int(rng.integers(0, latency + 2))
        resets.insert(0, (early, int(rng.integers(1, 6))))
        notes.append(f"early reset at cycle {early}")
    store = "random" if "store_garbage" in case.faults else "zero"
    settings = _settings_changes(cfg, len(words), rng) if "settings" in case.faults else ()
    if settings:
        notes.append(f"settings (K, n, s) rewritten before words {[i for i, _ in settings]}")
    stray = ()
    span = 1 << (cfg.lut_entries - 1).bit_length()
    if "lut" in case.faults and span > cfg.lut_entries:
        # a write beyond the table (ignored by the design), from a generator of its own so
        # the other draws stay as they were
        extra = np.random.default_rng([seed, 0x5742])
        stray = ((int(extra.integers(0, len(words) + 1)),
                  int(extra.integers(cfg.lut_entries, span)), int(extra.integers(0, unity + 1))),)
        notes.append(f"LUT write beyond the table (address {stray[0][1]}) before word "
                     f"{stray[0][0]}")
    stim = Stimulus(valid_gap=gap, ready_pause=pause, seed=int(seed), resets=tuple(resets),
                    lut_changes=tuple(luts), store_init=store, settings_changes=settings,
                    stray_lut_writes=stray)
    notes.insert(0, f"gaps {gap:.2f}, back-pressure {pause:.2f}")
    assert all(c < cycle_budget(len(words), gap, pause, 0) for c, _ in resets)
    return words, stim, notes, tuple(events)


@dataclasses.dataclass(frozen=True)
class RunOutcome:
    case: str
    seed: int
    passed: bool
    report: str
    words_in: int
    words_out: int
    cycles: int
    sim_seconds: float
    wall_seconds: float
    notes: tuple[str, ...]
    #: functional coverage, {bin: hits} (:mod:`dptbd.sim.coverage.bins`)
    bins: dict = dataclasses.field(default_factory=dict, compare=False)


def check_run(case: Case, seed: int, root: str | None = None,
              coverage: str | None = None) -> RunOutcome:
    """Build (cached), run and check run ``seed`` of ``case``, and count its bins; with
    ``coverage`` (a file) on the coverage build, its coverage data written there
    (:mod:`dptbd.sim.coverage`). A case that saturates on purpose gives no
    :class:`~dptbd.config.EnergyWidthWarning` (as :attr:`Case.cfg`), so the workers print
    none."""
    import warnings

    from dptbd.sim.coverage.bins import stream_bins
    from dptbd.sim.rtl_check import check_stream
    from dptbd.sim.verilator import build

    if case.design == "axi":
        from dptbd.sim import axi_runs
        return axi_runs.check_run(case, seed, root, coverage)

    start = time.perf_counter()
    sim = build(case.cfg, case.design, root=root, coverage=coverage is not None)
    latency = int(sim.manifest.get("dp_latency", sim.latency))
    words, stim, notes, events = _make_run(case, seed, latency)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        result = check_stream(sim, words, stim, coverage=coverage)
    bins = stream_bins(case, stim, result, events, latency)
    return RunOutcome(case.name, seed, result.passed, result.report, result.words_in,
                      result.words_out, result.raw.cycles, result.raw.sim_seconds,
                      time.perf_counter() - start, tuple(notes), bins)


# ---- the 4-state cases ----------------------------------------------------------------------

def x_store_cases() -> list[tuple[str, dict, str]]:
    """(name, config, store init) of the Icarus X-freedom checks of DPCore's external store."""
    small = dict(width=16, height=12, segment_frames=3)
    r2 = dict(width=14, height=11, segment_frames=2, radius=2, weight_frac_bits=6)
    return [("x-store-16x12", small, "x"), ("garbage-store-16x12", small, "random"),
            ("x-store-r2-14x11", r2, "x"), ("garbage-store-r2-14x11", r2, "random")]


def check_x_store(name: str, config: dict, init: str, seed: int = 1) -> RunOutcome:
    """One 4-state run: no output bit X or Z, every word equal to the model."""
    from dptbd.sim.x_store import run_x_store_check

    start = time.perf_counter()
    cfg = DPConfig(**config)
    rng = np.random.default_rng([seed, 0x5EED])
    frames = hostile_frames(cfg, 3 * cfg.segment_frames, rng)
    ok, report, words = run_x_store_check(cfg, frames, init=init, seed=seed)
    return RunOutcome(name, seed, bool(ok), report.splitlines()[0] if report else "",
                      int(words), int(words), 0, 0.0, time.perf_counter() - start,
                      (f"Icarus, store {init}",))


# ---- the campaign ---------------------------------------------------------------------------

@dataclasses.dataclass(frozen=True)
class CaseResult:
    name: str
    design: str
    runs: int
    passed: bool
    words_in: int
    words_out: int
    cycles: int
    sim_seconds: float
    first_failure: RunOutcome | None

    @property
    def words_per_second(self) -> float:
        return self.words_out / self.sim_seconds if self.sim_seconds > 0 else float("nan")


@dataclasses.dataclass(frozen=True)
class CampaignResult:
    cases: tuple[CaseResult, ...]
    outcomes: tuple[RunOutcome, ...]
    wall_seconds: float
    workers: int

    @property
    def passed(self) -> bool:
        return all(c.passed for c in self.cases)

    @property
    def words_out(self) -> int:
        return sum(c.words_out for c in self.cases)

    @property
    def words_in(self) -> int:
        return sum(c.words_in for c in self.cases)

    @property
    def mismatches(self) -> int:
        return sum(not o.passed for o in self.outcomes)

    @property
    def bins(self) -> dict[str, int]:
        """Functional coverage: every bin the runs declared, hits added."""
        from dptbd.sim.coverage.bins import merge
        return merge(*(o.bins for o in self.outcomes))

    @property
    def empty_bins(self) -> list[str]:
        """The declared bins no run hit: the campaign fails on them."""
        from dptbd.sim.coverage.bins import empty_bins
        return empty_bins(self.bins)

    @property
    def covered(self) -> bool:
        """Every declared bin hit (the coverage verdict, beside :attr:`passed`)."""
        return not self.empty_bins


def _summarise(name: str, design: str, outcomes: list[RunOutcome]) -> CaseResult:
    failed = [o for o in outcomes if not o.passed]
    return CaseResult(name, design, len(outcomes), not failed,
                      sum(o.words_in for o in outcomes), sum(o.words_out for o in outcomes),
                      sum(o.cycles for o in outcomes), sum(o.sim_seconds for o in outcomes),
                      failed[0] if failed else None)


def campaign_task(kind: str, *args) -> RunOutcome:
    """One task of :func:`run_campaign`: ``("run", case, seed, root)`` is
    :func:`check_run`, ``("x_store", name, config, init)`` :func:`check_x_store`."""
    if kind == "run":
        return check_run(*args)
    if kind == "x_store":
        return check_x_store(*args)
    raise ValueError(f"campaign task kind must be 'run' or 'x_store', got {kind!r}")


def campaign_tasks(cases: Sequence[Case], *, runs_scale: float = 1.0, base_seed: int = 0,
                   x_store: bool = True, root: str | None = None) -> list[tuple]:
    """The arguments of every :func:`campaign_task` of a campaign, in task order: each case's
    runs (``round(case.runs * runs_scale)``, at least 1; seed ``base_seed * 1_000_003 +
    7919 * case index + run``), then the 4-state store checks."""
    tasks: list[tuple] = [("run", case, base_seed * 1_000_003 + 7919 * i + r, root)
                          for i, case in enumerate(cases)
                          for r in range(max(1, round(case.runs * runs_scale)))]
    if x_store:
        tasks += [("x_store", n, cfg, init) for n, cfg, init in x_store_cases()]
    return tasks


def run_campaign(cases: Sequence[Case] | None = None, *, runs_scale: float = 1.0,
                 base_seed: int = 0, workers: int | None = None, x_store: bool = True,
                 root: str | None = None,
                 on_outcome: Callable[[RunOutcome], None] | None = None,
                 scheduler: str | None = None, dashboard: bool = False) -> CampaignResult:
    """Run every case's runs and the 4-state store checks (:func:`campaign_tasks`) on the
    execution layer (:mod:`dptbd.evaluation.execution`, ``docs/distributed.md``).

    ``workers``: local worker processes (default: the machine's cores, at most one per
    task; 1 runs in this process); with ``scheduler`` (``tcp://HOST:PORT``, or the
    ``DPTBD_SCHEDULER`` environment variable) the workers that cluster must have (default:
    any). Refusals are the layer's (:class:`~dptbd.evaluation.execution.ExecutionError`),
    before any build. Every Verilator executable is built (or found in the cache) once, here,
    before the tasks; each task calls :func:`~dptbd.sim.verilator.build` again, which on a
    worker that sees the same build root (this machine, or a shared file system) finds it
    and on any other builds it once into the worker's own cache (``root=None``: the worker's
    :func:`~dptbd.sim.verilator.default_build_root`; the build is locked, so the workers of
    one machine build it once). ``on_outcome`` is called with each outcome as its task
    finishes; the result lists them in task order, the same for any workers or cluster.
    """
    from dptbd.evaluation.execution import job_execution, run_tasks
    from dptbd.sim.verilator import build

    cases = list(default_cases() if cases is None else cases)
    tasks = campaign_tasks(cases, runs_scale=runs_scale, base_seed=base_seed,
                           x_store=x_store, root=root)
    execution = job_execution(workers, scheduler=scheduler, dashboard=dashboard,
                              tasks=len(tasks))

    def build_all() -> None:                  # once, up front (then cached)
        for case in cases:
            build(case.cfg, case.design, root=root)

    start = time.perf_counter()
    outcomes, used = run_tasks(
        campaign_task, tasks, execution, prepare=build_all,
        on_result=None if on_outcome is None else lambda _, outcome: on_outcome(outcome))
    by_case: dict[str, list[RunOutcome]] = {c.name: [] for c in cases}
    design = {c.name: c.design for c in cases}
    if x_store:
        for n, _, _ in x_store_cases():
            by_case[n] = []
            design[n] = "core (Icarus, 4-state)"
    for outcome in outcomes:
        by_case[outcome.case].append(outcome)
    results = tuple(_summarise(n, design[n], o) for n, o in by_case.items())
    return CampaignResult(results, tuple(o for lst in by_case.values() for o in lst),
                          time.perf_counter() - start, used)
