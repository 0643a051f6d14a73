"""The slice of ``dp2`` and ``dp4`` (``dptbd_dp`` at P = 2 and 4 pixels per clock,
:class:`DPPipelineWide <dptbd.hw.wide.pipeline.DPPipelineWide>`): the ``dp`` slice's runs
(:mod:`~dptbd.sim.mutation.slices.dp`, the same kinds, seeds and frames) on beats of P
pixels, with every check of it: every state bit-exact against the golden model
(:func:`dptbd.sim.rtl.check.check_stream`, per pixel), the ``events`` counts and the
``segment_begin`` pulses in runs without resets, K and LUT codes out of range, corner-code
LUTs on noise, and at full speed one beat a cycle, each beat's states exactly L cycles after
its acceptance. One kind of its own, ``drain``: at full speed with pauses long enough
for the pipeline to empty, each beat accepted in the cycle after the one before it and the
pause, its states exactly L cycles later (the input credit's count back at 0 and up again).

The harness's input words are beats here: a K, LUT or settings change before pixel i of
the ``dp`` slice's stimulus goes before beat i // P (the changes of these runs fall on frame
edges, a few pixels off, or on frame starts; a frame start is a beat's first pixel), and the
``segment_begin`` check counts the beat each pulse came with. The runs' faults (framing,
resets, LUT and settings rewrites) fall on beat boundaries
(:func:`dptbd.sim.campaign.draw.make_stream_run` at P > 1)."""

from __future__ import annotations

import dataclasses
import warnings

from dptbd.config import EnergyWidthWarning
from dptbd.sim.mutation.slices import BACKPRESSURE, CONFIGS
from dptbd.sim.mutation.slices import dp as one
from dptbd.sim.mutation.verdict import hang_verdict, stream_hang

__all__ = ["DESIGNS", "RUNS", "FRAMES", "run"]

#: The design with mutants of each P (its configuration:
#: :data:`~dptbd.sim.mutation.slices.CONFIGS`).
DESIGNS = {2: "dp2", 4: "dp4"}

#: The ``dp`` slice's runs and frames, then the ``drain`` runs.
RUNS = one.RUNS + tuple(("drain", s) for s in range(2))
FRAMES = {**one.FRAMES, "drain": 8}

#: Frames before which a ``drain`` run pauses its input (LUT writes beyond the table).
DRAIN_FRAMES = (1, 3, 5, 7)


def _drain_writes(cfg, latency: int, seed: int) -> tuple:
    """The ``drain`` run's pauses: before the first beat of each frame of
    :data:`DRAIN_FRAMES`, L + 2 + k writes beyond the table (which the design ignores), k
    = 0 … 3 in turn from ``seed``: at full speed the pipeline drains, then stays empty for
    2 + k cycles (both parities of an idle count, before the input restarts at full speed)."""
    beats = cfg.frame_beats
    address = cfg.lut_entries                   # the first beyond the table
    return tuple((f * beats, address, 0) for j, f in enumerate(DRAIN_FRAMES)
                 for _ in range(latency + 2 + (j + seed) % 4))


def _drain_report(raw, latency: int, writes) -> str:
    """``""`` if, at full speed, each beat was accepted in the cycle after the one before
    it and the LUT writes between them (``writes``: (beat index, …)), and its states came
    out exactly ``latency`` cycles after its acceptance; else the first beat that was not."""
    import numpy as np

    accepted = raw.accept_cycles.astype(np.int64)
    between = np.bincount([int(i) for i, *_ in writes], minlength=len(accepted))
    wrong = np.flatnonzero(np.diff(accepted) != 1 + between[1:len(accepted)])
    if len(wrong):
        i = int(wrong[0]) + 1
        return (f"drain: beat {i} accepted at cycle {accepted[i]}, beat {i - 1} at "
                f"{accepted[i - 1]} with {between[i]} LUT writes between (full speed)")
    late = np.flatnonzero(raw.out_cycles.astype(np.int64) - accepted != latency)
    if len(late):
        i = int(late[0])
        return (f"drain: beat {i} out at cycle {raw.out_cycles[i]}, accepted at "
                f"{accepted[i]}: latency {int(raw.out_cycles[i]) - int(accepted[i])}, "
                f"L = {latency}")
    return ""


def _beats(changes, p: int) -> tuple:
    """``(pixel index, x, …)`` changes as ``(beat index, x, …)``: before pixel i's beat."""
    return tuple((int(i) // p, *rest) for i, *rest in changes)


def _segment_begin_report(exp, counters: dict, p: int) -> str:
    """:func:`dp._segment_begin_report <dptbd.sim.mutation.slices.dp._segment_begin_report>`
    counted in beats, the harness's input words at P > 1 (a segment begins on a beat's first
    pixel)."""
    runs = tuple(dataclasses.replace(r, start=r.start // p) for r in exp.runs)
    return one._segment_begin_report(dataclasses.replace(exp, runs=runs), counters)


def _check_raw(sim, words, stim, k_changes=(), luts=(), reverse=False) -> tuple[str, str]:
    """:func:`dp._check_raw <dptbd.sim.mutation.slices.dp._check_raw>` on beats: ``words``
    (beats) with the K port driven to raw values (``k_changes``: (beat index, K)) and raw
    tables written through the LUT port (``luts``: (beat index, codes), ``reverse``: each
    table from its last address to its first); the model runs them as the design must take
    them, K clamped to [1, K_max], codes to [0, 2^F]; checked per pixel, then the ``events``
    counts and the ``segment_begin`` pulses."""
    import numpy as np

    from dptbd.model.settings import SegmentSettings
    from dptbd.sim.rtl.check import _checker, _event_report, beat_state_words, split_beats
    from dptbd.sim.stimulus import lut_writes
    from dptbd.sim.stream_model import expected_stream
    from dptbd.sim.verilator import run as run_words

    cfg = sim.cfg
    p = cfg.pixels_per_clock
    raw = run_words(sim, words, valid_gap=stim.valid_gap, ready_pause=stim.ready_pause,
                    seed=stim.seed,
                    settings=[(i, k, cfg.n_candidates, cfg.bin_shift) for i, k in k_changes],
                    lut_writes=[(i, a, c) for i, codes in luts
                                for a, c in (lut_writes(cfg, codes)[::-1] if reverse
                                             else lut_writes(cfg, codes))])
    pixels, first = split_beats(cfg, words)
    clamped = {i * p: SegmentSettings(min(max(k, 1), cfg.k_max), cfg.n_candidates,
                                      cfg.bin_shift) for i, k in k_changes}
    tables = {i * p: np.minimum(codes, 1 << cfg.weight_frac_bits) for i, codes in luts}
    exp = expected_stream(cfg, pixels, first, tables, clamped)
    board = _checker(cfg, "states", exp, cut_by_reset=False)
    board.receive_array(beat_state_words(cfg, raw.out_words))
    report = (f"K port {[k for _, k in k_changes]}: " if k_changes else "") + board.report()
    if raw.status != "done":
        return hang_verdict(raw.status, board.report()) or "killed", report
    if board.failed or not board.done:
        return "killed", report
    wrong = (_event_report("states", exp, board, raw, cfg)
             or _segment_begin_report(exp, raw.counters, p))
    return ("killed", wrong) if wrong else ("survived", report)


def run(sim, kind: str, seed: int) -> tuple[str, str]:
    """Run ``(kind, seed)`` of the slice on ``sim`` (``DPTBD_MUTANT`` selects the mutant):
    ``(verdict, report)``, the verdict ``killed``, ``timeout`` or ``survived``."""
    with warnings.catch_warnings():             # B_E saturates on purpose (CONFIGS)
        warnings.simplefilter("ignore", EnergyWidthWarning)
        return _run(sim, kind, seed)


def _run(sim, kind: str, seed: int) -> tuple[str, str]:
    from dptbd.sim.campaign import Case
    from dptbd.sim.campaign.draw import _pixel_beats, make_stream_run
    from dptbd.sim.rtl.check import check_stream

    cfg = sim.cfg
    p = cfg.pixels_per_clock
    case = Case(f"mutant-{kind}", CONFIGS[DESIGNS[p]], "dp", FRAMES[kind], 1,
                one._EVERY if kind == "faults" else (), kind == "random-lut")
    words, stim, _, _ = make_stream_run(case, seed, int(sim.latency))
    pixels = len(words) * p
    if kind == "backpressure":                  # the output stalled most of the time
        stim = dataclasses.replace(stim, valid_gap=0.0, ready_pause=BACKPRESSURE[seed % 4])
    if kind in ("k-edge", "timing"):
        stim = dataclasses.replace(stim, settings_changes=_beats(
            one._edge_k(cfg, pixels, seed), p))
    if kind in ("timing", "drain"):             # full speed: no gap, no pause
        stim = dataclasses.replace(stim, valid_gap=0.0, ready_pause=0.0)
    if kind == "drain":                         # paused until the pipeline is empty
        stim = dataclasses.replace(stim, stray_lut_writes=_drain_writes(
            cfg, int(sim.latency), seed))
    if kind == "k-clamp":
        return _check_raw(sim, words, stim,
                          k_changes=_beats(one._edge_raw_k(cfg, pixels, seed), p))
    if kind == "k-begin":                       # K = 0 or 7 at every segment's first pixel
        return _check_raw(sim, words, stim, k_changes=((0, one.K_BEGIN[seed]),))
    if kind in ("lut-clamp", "lut-reverse", "lut-corners"):     # noise: every entry is read
        noise = one._noise_words(cfg, FRAMES[kind], seed + (8 if kind == "lut-reverse" else 0))
        words = _pixel_beats(cfg, noise)
        if kind == "lut-clamp":
            return _check_raw(sim, words, stim, luts=_beats(one._wide_luts(cfg, len(noise),
                                                                           seed), p))
        if kind == "lut-reverse":               # random tables, written backwards
            return _check_raw(sim, words, stim, luts=_beats(
                one._random_luts(cfg, len(noise), seed), p), reverse=True)
        stim = dataclasses.replace(stim, lut_changes=_beats(
            one._corner_luts(cfg, len(noise), seed), p))
    result = check_stream(sim, words, stim)
    hung = stream_hang(sim, words, stim, result)
    if hung:
        return hung
    if result.passed and kind == "timing":      # beats: one a cycle, each L after
        late = one._timing_report(result.raw, int(sim.latency))
        if late:
            return "killed", late
    if result.passed and kind == "drain":
        late = _drain_report(result.raw, int(sim.latency), stim.stray_lut_writes)
        if late:
            return "killed", late
    if result.passed and not stim.resets:
        begins = _segment_begin_report(result.scored[-1][1], result.raw.counters, p)
        if begins:
            return "killed", begins
    return ("survived" if result.passed else "killed"), result.report
