"""The ``dp`` slice (``dptbd_dp``, :class:`~dptbd.hw.dp_pipeline.DPPipeline`): seeded runs
of the campaign (:func:`dptbd.sim.campaign.make_run`: hostile scenes, input gaps, output
back-pressure, resets, one early with the pipeline holding 0 … L words, misaligned / short /
long frames, LUT rewrites, writes beyond the table, run-time K rewrites) checked by
:func:`dptbd.sim.rtl_check.check_stream` bit-exact on every state word (E, d and the end
flags) and, in runs without resets, on the counts of the ``events`` pulses; LUT tables of
corner codes (every code bit of every entry set in one run, clear in another); at full speed
the cycle of every word, exactly L after its acceptance, one word a cycle."""

from __future__ import annotations

import dataclasses
import warnings

from dptbd.config import DPConfig, EnergyWidthWarning
from dptbd.sim.mutation.slices import BACKPRESSURE, CONFIGS
from dptbd.sim.mutation.verdict import hang_verdict

__all__ = ["RUNS", "FRAMES", "run"]

#: Frames of each kind's runs (before the faults cut or lengthen them).
FRAMES = {"clean": 12, "timing": 16, "k-edge": 16, "lut-corners": 12, "random-lut": 12,
          "faults": 24, "backpressure": 8}

_EVERY = ("reset", "misaligned_first", "short_frame", "long_frame", "lut", "settings")


def _corners(frac: int) -> tuple[int, ...]:
    """Corner codes of F = ``frac``: 1.0, the largest below it, 0, alternate fraction bits."""
    unity = 1 << frac
    ones = unity - 1
    return (unity, ones, 0, ones & 0x5555, ones & 0xAAAA)


def _corner_luts(cfg: DPConfig, n_words: int, seed: int) -> tuple:
    """Run ``seed``'s tables: every entry the corner code ``seed`` from word 0 on, the next
    corner code from the middle frame on (:func:`_corners`)."""
    import numpy as np

    corners = _corners(cfg.weight_frac_bits)
    size = cfg.width * cfg.height
    shape = (cfg.n_moves + 1, cfg.n_moves)
    return ((0, np.full(shape, corners[seed % len(corners)])),
            ((n_words // size // 2) * size, np.full(shape, corners[(seed + 1) % len(corners)])))


#: The runs of the slice: ``(kind, seed)``, in this order (the cheap runs first: most
#: mutants fall to the first).
RUNS = tuple([("clean", s) for s in range(4)] + [("timing", s) for s in range(2)]
             + [("k-edge", s) for s in range(8)]
             + [("lut-corners", s) for s in range(len(_corners(0)))]
             + [("random-lut", s) for s in range(8)]
             + [("faults", s) for s in range(24)]
             + [("backpressure", s) for s in range(4)])


def _edge_k(cfg: DPConfig, n_words: int, seed: int) -> tuple:
    """A new run-time K (1 … K_max) a few words before or after most frame starts: the
    DP samples K when a segment's first pixel is accepted, so a K latched a word early or
    late, or at a frame that does not begin a segment, moves the ``segment_done`` flags."""
    import numpy as np

    from dptbd.model.settings import SegmentSettings

    rng = np.random.default_rng([seed, 0xD9E])
    size = cfg.width * cfg.height
    out = []
    for start in range(size, n_words, size):
        if rng.random() < 0.6:
            at = start + int(rng.integers(-3, 4))
            out.append((min(max(at, 1), n_words), SegmentSettings(
                int(rng.integers(1, cfg.k_max + 1)), cfg.n_candidates, cfg.bin_shift)))
    return tuple(out)


def run(sim, kind: str, seed: int) -> tuple[str, str]:
    from dptbd.sim.campaign import Case, _make_run
    from dptbd.sim.mutation.slices.segmenter import _missing_of_offered
    from dptbd.sim.rtl_check import check_stream

    case = Case(f"mutant-{kind}", CONFIGS["dp"], "dp", FRAMES[kind], 1,
                _EVERY if kind == "faults" else (), kind == "random-lut")
    with warnings.catch_warnings():             # B_E saturates on purpose (CONFIGS)
        warnings.simplefilter("ignore", EnergyWidthWarning)
        words, stim, _, _ = _make_run(case, seed, int(sim.latency))
    if kind == "backpressure":                  # the output stalled most of the time
        stim = dataclasses.replace(stim, valid_gap=0.0, ready_pause=BACKPRESSURE[seed % 4])
    if kind in ("k-edge", "timing"):
        stim = dataclasses.replace(stim, settings_changes=_edge_k(sim.cfg, len(words), seed))
    if kind == "timing":                        # full speed: no gap, no pause
        stim = dataclasses.replace(stim, valid_gap=0.0, ready_pause=0.0)
    if kind == "lut-corners":
        stim = dataclasses.replace(stim, lut_changes=_corner_luts(sim.cfg, len(words), seed))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        result = check_stream(sim, words, stim)
    if hang_verdict(result.raw.status, result.report):
        missing = _missing_of_offered(sim, words, stim, result)
        if missing:
            return "killed", missing
        return "timeout", f"cycle budget ({result.raw.cycles} cycles) ran out: {result.report}"
    if result.passed and kind == "timing":
        late = _timing_report(result.raw, int(sim.latency))
        if late:
            return "killed", late
    return ("survived" if result.passed else "killed"), result.report


def _timing_report(raw, latency: int) -> str:
    """``""`` if the words were accepted one a cycle and each came out exactly ``latency``
    cycles after its acceptance (a run at full speed), else the first word that was not."""
    import numpy as np

    accepted = raw.accept_cycles.astype(np.int64)
    gaps = np.flatnonzero(np.diff(accepted) != 1)
    if len(gaps):
        i = int(gaps[0]) + 1
        return (f"timing: word {i} accepted at cycle {accepted[i]}, word {i - 1} at "
                f"{accepted[i - 1]} (one a cycle at full speed)")
    late = np.flatnonzero(raw.out_cycles.astype(np.int64) - accepted != latency)
    if len(late):
        i = int(late[0])
        return (f"timing: word {i} out at cycle {raw.out_cycles[i]}, accepted at {accepted[i]}: "
                f"latency {int(raw.out_cycles[i]) - int(accepted[i])}, L = {latency}")
    return ""
