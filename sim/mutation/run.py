"""Running the mutants: each mutant of a top level through the verification slice, one
verdict per mutant, and the mutation score.

The slice of ``segmenter`` (``dptbd_seg``) is seeded runs of the campaign
(:func:`dptbd.sim.campaign.make_run`: hostile scenes, input gaps, output back-pressure,
resets, misaligned / short / long frames, LUT and settings rewrites) checked by
:func:`dptbd.sim.rtl_check.check_stream` against the golden model; the slice of ``axi``
(``dptbd_axi``) is seeded runs of :func:`dptbd.sim.verilator_axi.check_axi` (every fault
class, settings and LUT writes, refused writes, W1C, soft reset, register reads, gaps and
back-pressure) — the checks the default suite runs, on :data:`CONFIGS` (small frames, narrow
widths: every bit of the datapath is reached).

A mutant's verdict (:class:`MutantOutcome`) is the first of its runs that is not passed:

* ``killed``: a run finished (the harness saw every word in and the output drain) and the
  check failed: a wrong, missing or extra word, a wrong flag, response, register or counter;
* ``timeout``: a run ran out of its cycle budget with every word the model expects
  delivered right (:func:`hang_verdict`: the mutant hangs where no more output is due; one
  that delivered a wrong or extra word, or left out words the model expects, is killed; in
  ``dptbd_seg``'s runs without resets, the model is fed every offered word, so a mutant
  that stops taking input while the model gives lists for the words it refused is killed
  with ``hang: …``) or ran past the wall-clock limit (:data:`WALL_SECONDS`, exit 124 of the
  harness): never counted as killed;
* ``crashed``: the simulation process failed otherwise (e.g. Verilator's model did not
  converge): never counted as killed;
* ``survived``: every run passed.

A mutation Yosys cannot apply is ``no-build`` (:func:`mutant_design`). The runs stop at a
mutant's first failing run. Mutants are independent tasks of the Dask execution layer
(:func:`dptbd.evaluation.execution.map_tasks`); index 0, the original design, is run first
and must pass every run of the slice.
"""

from __future__ import annotations

import contextlib
import dataclasses
import os
import time
import warnings

import numpy as np
from typing import Callable, Sequence

from dptbd.config import DPConfig, EnergyWidthWarning
from dptbd.sim.mutation.netlist import DESIGN_TOPS, Mutation, mutation_list, run_yosys

__all__ = ["CONFIGS", "RANDOM_AXI_RUNS", "RANDOM_AXI_FRAMES", "SLICE_RUNS", "BACKPRESSURE",
           "WALL_SECONDS", "VERDICTS", "MutantOutcome",
           "MutationResult", "config", "slice_runs", "run_slice", "mutant_task",
           "mutant_design", "run_mutants", "axi_scenario", "hang_verdict"]

#: The configuration of each design's mutants: 12 x 10 frames, B_in = 6, B_E = 8 (the
#: fewest bits that never saturate at K_max = 4), F = 4, n = 60 of C = 120 (lists long
#: enough to carry most pixels), 16 bins of width 16 (s = 4).
CONFIGS = {
    "segmenter": dict(width=12, height=10, segment_frames=2, max_segment_frames=4,
                      input_bits=6, energy_bits=8, weight_frac_bits=4, candidate_count=60,
                      candidate_capacity=120, histogram_bits=4, histogram_shift=4),
    "axi": dict(width=12, height=10, segment_frames=2, max_segment_frames=4,
                input_bits=6, energy_bits=8, weight_frac_bits=4, candidate_count=60,
                candidate_capacity=120, histogram_bits=4, histogram_shift=4),
}

#: Random AXI runs of the ``axi`` slice (:func:`dptbd.sim.axi_runs.draw_run` on the slice's
#: configuration, :data:`RANDOM_AXI_FRAMES` frames each): every refused access class,
#: soft resets with words in flight, aresetn, W1C, clear_counters, LUT and settings writes,
#: every register read with its expected value.
RANDOM_AXI_RUNS, RANDOM_AXI_FRAMES = 32, 24

#: Runs of each design's slice: ``(kind, seed)``, run in this order.
SLICE_RUNS = {
    "segmenter": tuple([("clean", s) for s in range(4)] + [("settings-edge", s) for s in range(8)]
                       + [("random-lut", s) for s in range(12)]
                       + [("faults", s) for s in range(32)]
                       + [("backpressure", s) for s in range(4)]),
    "axi": tuple([("faults", s) for s in range(16)]
                 + [("backpressure", s) for s in (1, 4, 7, 14)]
                 + [("random", s) for s in range(RANDOM_AXI_RUNS)]),
}

#: Output back-pressure densities of the ``backpressure`` runs (seed % 4): the lists
#: pile up behind the output, every FIFO and credit counter fills.
BACKPRESSURE = (0.9, 0.95, 0.97, 0.99)

#: Wall-clock seconds one run of a mutant may take (the harness exits with status 124).
WALL_SECONDS = 60

#: Verdicts, in the order they are listed.
VERDICTS = ("killed", "survived", "timeout", "crashed", "no-build")

_EVERY = ("reset", "misaligned_first", "short_frame", "long_frame", "lut", "settings")


def config(design: str) -> DPConfig:
    """The :class:`DPConfig` of ``design``'s mutants (:data:`CONFIGS`)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        return DPConfig(**CONFIGS[design])


def slice_runs(design: str, scale: float = 1.0) -> tuple[tuple[str, int], ...]:
    """The runs of ``design``'s slice (:data:`SLICE_RUNS`), each kind's seeds scaled by
    ``scale`` (at least one run per kind)."""
    runs = SLICE_RUNS[design]
    kinds = dict.fromkeys(kind for kind, _ in runs)
    out = []
    for kind in kinds:
        seeds = [s for k, s in runs if k == kind]
        out += [(kind, s) for s in seeds[:max(1, round(len(seeds) * scale))]]
    return tuple(out)


@dataclasses.dataclass(frozen=True)
class MutantOutcome:
    """The verdict of mutant ``index`` (0: the original), the run that decided it and its
    report."""

    index: int
    verdict: str
    run: str
    report: str
    seconds: float


#: What :class:`dptbd.sim.checker.InOrderChecker` reports for a wrong, an extra or a
#: missing output word: a run whose cycle budget ran out with one of these is killed.
_DETECTED = ("first mismatch at", "beyond the", "incomplete: ")


def hang_verdict(status: str, report: str) -> str | None:
    """``"timeout"`` if a run that did not finish (``status`` is not ``"done"``: its cycle
    budget, :func:`dptbd.sim.verilator.cycle_budget`, three times the cycles it needs, ran
    out) has a ``report`` with no wrong, extra or missing output word (the mutant hangs
    where the model expects no more output, e.g. the input stalls after the last list);
    ``None`` otherwise (the run's own check decides: a hang where the model expects more
    words is a failed check, ``incomplete: …``, and killed). A run past the wall-clock
    limit never gets here: it is a timeout (:func:`run_slice`)."""
    if status != "done" and not any(text in report for text in _DETECTED):
        return "timeout"
    return None


def _edge_settings(cfg: DPConfig, n_words: int, seed: int) -> tuple:
    """New n and s (K kept) a few words after most segment starts: inside the window between
    the DP's segment start, where the top latches the ports, and the segmenter's, where it
    takes them (so a latch at the wrong time is seen)."""
    import numpy as np

    from dptbd.model.settings import SegmentSettings

    rng = np.random.default_rng([seed, 0xED6E])
    size = cfg.width * cfg.height * cfg.segment_frames
    out = []
    for start in range(size, n_words, size):
        at = start + int(rng.integers(0, 24))
        if at < n_words:
            out.append((at, SegmentSettings(cfg.segment_frames,
                                            int(rng.integers(0, cfg.record_capacity + 1)),
                                            int(rng.integers(0, cfg.energy_bits)))))
    return tuple(out)


def _missing_of_offered(sim, words, stim, result) -> str:
    """For a run without resets whose cycle budget ran out with offered words not taken:
    the golden model fed every offered word against what the design delivered; the report
    of the missing (or wrong) words, or ``""`` if every word the model gives came out."""
    from dptbd.sim.rtl_check import _checker, expected_stream, split_words

    if stim.resets or result.raw.status == "done":
        return ""
    pixels, first = split_words(sim.cfg, np.asarray(words))
    exp = expected_stream(sim.cfg, pixels, first,
                          {int(i): codes for i, codes in stim.lut_changes},
                          {int(i): entry for i, entry in stim.settings_changes})
    board = _checker(sim.cfg, sim.output, exp, cut_by_reset=False)
    board.receive_array(result.raw.out_words)
    if board.done:
        return ""
    return (f"hang: {result.words_in} of {len(words)} offered words taken in {result.raw.cycles} "
            f"cycles; against the model of every offered word: {board.report()}")


def _segmenter_run(sim, kind: str, seed: int) -> tuple[str, str]:
    from dptbd.sim.campaign import Case, make_run
    from dptbd.sim.rtl_check import check_stream

    frames = {"clean": 12, "random-lut": 16, "faults": 24, "settings-edge": 16,
              "backpressure": 8}[kind]
    case = Case(f"mutant-{kind}", CONFIGS["segmenter"], "segmenter", frames, 1,
                () if kind != "faults" else _EVERY, kind in ("random-lut", "settings-edge"))
    words, stim, _ = make_run(case, seed)
    if kind == "backpressure":                  # the output stalled most of the time
        stim = dataclasses.replace(stim, valid_gap=0.0, ready_pause=BACKPRESSURE[seed % 4])
    if kind == "settings-edge":
        stim = dataclasses.replace(stim, settings_changes=_edge_settings(sim.cfg, len(words),
                                                                         seed))
    result = check_stream(sim, words, stim)
    if hang_verdict(result.raw.status, result.report):
        missing = _missing_of_offered(sim, words, stim, result)
        if missing:
            return "killed", missing
        return "timeout", f"cycle budget ({result.raw.cycles} cycles) ran out: {result.report}"
    return ("survived" if result.passed else "killed"), result.report


def axi_scenario(cfg: DPConfig, seed: int) -> tuple:
    """The beats, steps and stimulus of AXI run ``seed``: two clean segments and every fault
    class (:func:`dptbd.sim.axi_stimulus.with_fault`), K / n / s writes (one refused), the
    LUT rewritten, ERROR W1C, a soft reset, register checks; gaps and back-pressure from the
    seed."""
    import numpy as np

    from dptbd.hw.flow.register_export import constants_namespace
    from dptbd.hw.register_map import FAULTS, register_map
    from dptbd.sim.axi_stimulus import fault_stretches
    from dptbd.sim.scenarios import make_frames

    rng = np.random.default_rng([seed, 0xA71])
    regs = constants_namespace(cfg)
    frames = make_frames("two-targets" if seed % 2 == 0 else "mixed", cfg,
                         4 + 2 * len(FAULTS), seed=seed)
    beats, starts = fault_stretches(cfg, frames)
    frame = cfg.width * cfg.height
    every = sum(getattr(regs, f"ERROR_{k.upper()}_MASK") for k in FAULTS)
    unity = 1 << cfg.weight_frac_bits
    codes = rng.integers(0, unity + 1, size=(cfg.n_moves + 1, cfg.n_moves)).tolist()
    k1, k2 = (int(v) for v in rng.integers(1, cfg.k_max + 1, size=2))
    n1 = int(rng.integers(1, cfg.record_capacity + 1))
    s2 = int(rng.integers(0, cfg.energy_bits))
    at_reset = {r.name: sum(f.reset << f.lsb for f in r.fields)
                for r in register_map(cfg).registers if r.group != "status" or r.name in
                ("ERROR", "IRQ_STATUS", "STATUS")}
    steps = [{"check": at_reset, "writes": [["IRQ_ENABLE", 3]], "stop": 2 * frame},
             {"writes": [["SEGMENT_FRAMES", k1], ["CANDIDATE_COUNT", n1],
                         ["HISTOGRAM_SHIFT", cfg.energy_bits]], "stop": 4 * frame},
             {"check": {"ERROR": regs.ERROR_WRITE_REFUSED_MASK, "SEGMENT_FRAMES": k1,
                        "CANDIDATE_COUNT": n1, "HISTOGRAM_SHIFT": cfg.bin_shift,
                        "IRQ_ENABLE": 3, "IRQ_STATUS": 3},
              "lut_codes": codes,
              "writes": [["SEGMENT_FRAMES", k2], ["ERROR", regs.ERROR_WRITE_REFUSED_MASK]],
              "stop": starts[2]},
             {"soft_reset": True, "writes": [["HISTOGRAM_SHIFT", s2]], "stop": len(beats)},
             {"check": {"ERROR": every, "SEGMENT_FRAMES": k2, "HISTOGRAM_SHIFT": s2,
                        "STATUS": 0, "INPUT_STALLS": None, "OUTPUT_STALLS": None},
              "writes": [["ERROR", every]], "stop": len(beats)}]
    gap, pause = (float(v) for v in rng.uniform(0.0, 0.5, size=2))
    return beats, steps, gap, pause


def _axi_random_run(sim, seed: int) -> tuple[str, str]:
    from dptbd.sim.axi_runs import AXI_FAULTS, draw_run
    from dptbd.sim.campaign import Case
    from dptbd.sim.verilator_axi import check_axi

    case = Case("mutant-axi-random", CONFIGS["axi"], "axi", RANDOM_AXI_FRAMES, 1, AXI_FAULTS)
    plan = draw_run(case, seed)
    result = check_axi(sim, plan.beats, plan.steps, valid_gap=plan.valid_gap,
                       ready_pause=plan.ready_pause, seed=seed, pulses=plan.pulses)
    if hang_verdict(result.run.status, result.report()):
        return "timeout", (f"cycle budget ({result.run.cycles} cycles) ran out: "
                           f"{result.report()}")
    return ("survived" if result.passed else "killed"), result.report()


def _axi_run(sim, kind: str, seed: int) -> tuple[str, str]:
    from dptbd.sim.verilator_axi import check_axi

    if kind == "random":
        return _axi_random_run(sim, seed)
    beats, steps, gap, pause = axi_scenario(sim.cfg, seed)
    if kind == "backpressure":
        gap, pause = 0.0, BACKPRESSURE[seed % 4]
    result = check_axi(sim, beats, steps, valid_gap=gap, ready_pause=pause, seed=seed)
    if hang_verdict(result.run.status, result.report()):
        return "timeout", (f"cycle budget ({result.run.cycles} cycles) ran out: "
                           f"{result.report()}")
    # the stall counters against the harness's own count of the same cycles
    stalls = [f"{name} = {result.reads.get(name)}, the harness counted {result.run.counters[key]}"
              for name, key in (("INPUT_STALLS", "stalled_input_cycles"),
                                ("OUTPUT_STALLS", "paused_output_cycles"))
              if result.reads.get(name) != result.run.counters[key]]
    if result.passed and stalls:
        return "killed", "; ".join(stalls)
    return ("survived" if result.passed else "killed"), result.report()


_RUNNERS = {"segmenter": _segmenter_run, "axi": _axi_run}


@contextlib.contextmanager
def _selected(index: int, wall_seconds: int):
    """``DPTBD_MUTANT`` / ``DPTBD_MUTANT_SECONDS`` for the harness (a worker runs one task
    at a time)."""
    saved = {k: os.environ.get(k) for k in ("DPTBD_MUTANT", "DPTBD_MUTANT_SECONDS")}
    os.environ["DPTBD_MUTANT"] = str(int(index))
    os.environ["DPTBD_MUTANT_SECONDS"] = str(int(wall_seconds))
    try:
        yield
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


def run_slice(sim, index: int, runs: Sequence[tuple[str, int]], *,
              wall_seconds: int = WALL_SECONDS,
              runner: Callable | None = None) -> MutantOutcome:
    """Mutant ``index`` of the mutant build ``sim`` through ``runs``, stopping at the first
    run that is not passed (see the module doc for the verdicts). ``runner(sim, kind,
    seed) -> (verdict, report)`` replaces the design's runner (tests)."""
    runner = runner or _RUNNERS[sim.design]
    start = time.perf_counter()
    with _selected(index, wall_seconds):
        for kind, seed in runs:
            label = f"{kind} seed {seed}"
            try:
                verdict, report = runner(sim, kind, seed)
            except RuntimeError as exc:
                text = str(exc)
                if "(exit 124)" in text:
                    verdict, report = "timeout", f"wall-clock limit of {wall_seconds} s"
                else:
                    verdict, report = "crashed", text.strip().splitlines()[0][:300]
            if verdict != "survived":
                return MutantOutcome(index, verdict, label, report,
                                     time.perf_counter() - start)
    return MutantOutcome(index, "survived", "", "", time.perf_counter() - start)


def mutant_task(design: str, commands: tuple[str, ...], index: int,
                runs: tuple[tuple[str, int], ...], wall_seconds: int,
                root: str | None = None) -> MutantOutcome:
    """One task of :func:`run_mutants` (picklable arguments; the build is cached on disk)."""
    from dptbd.sim.verilator_build import build

    sim = build(config(design), design, root=root, mutations=commands)
    return run_slice(sim, index, runs, wall_seconds=wall_seconds)


def mutant_design(cfg: DPConfig, design: str, mutations: Sequence[Mutation]
                  ) -> tuple[tuple[str, ...], list[int]]:
    """The commands of the mutations Yosys can apply and write as Verilog (a mutation it
    refuses is replaced by ``""``, which applies nothing, so every mutant keeps its index)
    and the 1-based indices of the refused ones (``no-build``). All are tried at once; only
    if that fails, each half in turn, down to the single mutations Yosys refuses."""
    from dptbd.sim.mutation.netlist import MUTSEL_WIDTH, _prepared, top_rtlil

    commands = [m.command for m in mutations]
    text, _ = top_rtlil(cfg, design)
    base = _prepared(text, design)

    def applies(lines: list[str]) -> bool:
        try:
            run_yosys("\n".join([base, *lines, "write_verilog mutant.v"]))
        except RuntimeError:
            return False
        return True

    def refused_of(lines: list[tuple[int, str]]) -> list[int]:
        """The indices of the refused mutations among ``lines``, by halves."""
        if applies([line for _, line in lines]):
            return []
        if len(lines) == 1:
            return [lines[0][0]]
        half = len(lines) // 2
        return refused_of(lines[:half]) + refused_of(lines[half:])

    refused = refused_of([(i, f"{c} -ctrl mutsel {MUTSEL_WIDTH} {i}")
                          for i, c in enumerate(commands, 1)])
    return tuple("" if i in refused else c for i, c in enumerate(commands, 1)), refused


@dataclasses.dataclass(frozen=True)
class MutationResult:
    """Every mutant's outcome (index 1 … N), the mutations, the original's outcome."""

    design: str
    seed: int
    mutations: tuple[Mutation, ...]
    original: MutantOutcome
    outcomes: tuple[MutantOutcome, ...]
    runs: tuple[tuple[str, int], ...]
    wall_seconds: float
    workers: int

    def count(self, verdict: str) -> int:
        return sum(o.verdict == verdict for o in self.outcomes)

    @property
    def killed(self) -> int:
        return self.count("killed")

    @property
    def total(self) -> int:
        return len(self.outcomes)

    @property
    def score(self) -> float:
        """Killed / total: survivors, timeouts, crashes and no-builds all count against."""
        return self.killed / self.total if self.total else float("nan")

    def of(self, verdict: str) -> list[tuple[MutantOutcome, Mutation]]:
        return [(o, self.mutations[o.index - 1]) for o in self.outcomes if o.verdict == verdict]


def run_mutants(design: str, count: int, seed: int = 1, *, workers: int | None = 1,
                scheduler: str | None = None, scale: float = 1.0,
                wall_seconds: int = WALL_SECONDS, root: str | None = None,
                bar=None) -> MutationResult:
    """Sample ``count`` mutations of ``design`` (``mutate -list count -seed seed``), build
    the mutant design once, check the original passes the slice, then run every mutant
    through it (``workers`` / ``scheduler``: :func:`~dptbd.evaluation.execution.job_execution`).

    Raises
    ------
    RuntimeError
        The original design fails the slice (a broken slice scores nothing).
    """
    from dptbd.evaluation.execution import job_execution, map_tasks
    from dptbd.sim.verilator_build import build

    if design not in DESIGN_TOPS:
        raise ValueError(f"design must be one of {', '.join(DESIGN_TOPS)}, got {design!r}")
    start = time.perf_counter()
    cfg = config(design)
    mutations = tuple(mutation_list(cfg, design, count, seed))
    commands, refused = mutant_design(cfg, design, mutations)
    sim = build(cfg, design, root=root, mutations=commands)
    runs = slice_runs(design, scale)
    original = run_slice(sim, 0, runs, wall_seconds=wall_seconds)
    if original.verdict != "survived":
        raise RuntimeError(f"the original {DESIGN_TOPS[design]} fails the mutation slice "
                           f"({original.run}: {original.verdict}): {original.report}")
    todo = [i for i in range(1, len(mutations) + 1) if i not in refused]
    execution = job_execution(workers, scheduler=scheduler, tasks=len(todo))
    tasks = [(design, commands, i, runs, wall_seconds, root) for i in todo]
    with execution.client() as client:
        done = map_tasks(mutant_task, tasks, client, bar=bar)
    by_index = {o.index: o for o in done}
    by_index.update({i: MutantOutcome(i, "no-build", "", "Yosys refused the mutation", 0.0)
                     for i in refused})
    outcomes = tuple(by_index[i] for i in range(1, len(mutations) + 1))
    return MutationResult(design, seed, mutations, original, outcomes, runs,
                          time.perf_counter() - start, execution.workers or 1)
