"""The ``dp`` slice (``dptbd_dp``, :class:`~dptbd.hw.dp_pipeline.DPPipeline`): seeded runs
of the campaign (:func:`dptbd.sim.campaign.make_run`: hostile scenes, input gaps, output
back-pressure, resets, one early with the pipeline holding 0 … L words, misaligned / short /
long frames, LUT rewrites, writes beyond the table, run-time K rewrites) checked by
:func:`dptbd.sim.rtl.check.check_stream` bit-exact on every state word (E, d and the end
flags) and, in runs without resets, on the counts of the ``events`` pulses and on the
``segment_begin`` pulses (how many, and the words they came with); K written out of its
range (0, above K_max: clamped, ``docs/gateware.md`` "Run-time settings") and LUT codes
above 2^F (stored as 2^F); LUT tables of corner codes on noise (every code bit of every
entry set in one run, clear in another); at full speed the cycle of every word, exactly L
after its acceptance, one word a cycle."""

from __future__ import annotations

import dataclasses
import warnings

from dptbd.config import DPConfig, EnergyWidthWarning
from dptbd.sim.mutation.slices import BACKPRESSURE, CONFIGS
from dptbd.sim.mutation.verdict import hang_verdict, stream_hang

__all__ = ["RUNS", "FRAMES", "run"]

#: Frames of each kind's runs (before the faults cut or lengthen them).
FRAMES = {"clean": 12, "timing": 16, "k-edge": 16, "k-clamp": 16, "lut-corners": 12,
          "lut-clamp": 12, "random-lut": 12, "faults": 24, "backpressure": 8, "k-begin": 8,
          "lut-reverse": 12}

_EVERY = ("reset", "misaligned_first", "short_frame", "long_frame", "lut", "settings")


def _corners(frac: int) -> tuple[int, ...]:
    """Corner codes of F = ``frac``: 1.0, the largest below it, 0, alternate fraction bits."""
    unity = 1 << frac
    ones = unity - 1
    return (unity, ones, 0, ones & 0x5555, ones & 0xAAAA)


def _noise_words(cfg: DPConfig, n_frames: int, seed: int):
    """Uniform noise frames, each over [0, B_in max >> a], a in {0, 1, 2} at random: every
    direction is taken and every LUT entry read, and the sums saturate only now and then."""
    import numpy as np

    from dptbd.sim.stimulus import pixel_words

    rng = np.random.default_rng([seed, 0x401])
    tops = cfg.pixel_max >> rng.integers(0, 3, size=n_frames)
    frames = np.stack([rng.integers(0, top + 1, size=(cfg.height, cfg.width)) for top in tops])
    return pixel_words(cfg, frames.astype(np.uint16))


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
             + [("k-edge", s) for s in range(8)] + [("k-clamp", s) for s in range(4)]
             + [("lut-corners", s) for s in range(2 * len(_corners(0)))]
             + [("lut-clamp", s) for s in range(4)]
             + [("random-lut", s) for s in range(8)]
             + [("faults", s) for s in range(24)]
             + [("backpressure", s) for s in range(4)]
             + [("k-begin", s) for s in range(2)] + [("lut-reverse", s) for s in range(2)])

#: The K port's raw value of each ``k-begin`` run, held from word 0 (K_BEGIN[seed]): every
#: segment's first pixel samples it, so the clamp's every copy is read with it.
K_BEGIN = (0, 7)


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


def _edge_raw_k(cfg: DPConfig, n_words: int, seed: int) -> tuple:
    """:func:`_edge_k` with port values out of range too: 0 and K_max + 1 … the port's
    largest, as often as values in range."""
    import numpy as np

    rng = np.random.default_rng([seed, 0xC1A])
    top = (1 << (cfg.k_max).bit_length()) - 1             # the port holds 0 … top
    out = []
    for at, entry in _edge_k(cfg, n_words, seed):
        k = entry.segment_frames
        if rng.random() < 0.5:
            k = int(rng.choice([0, *range(cfg.k_max + 1, top + 1)]))
        out.append((at, k))
    return tuple(out)


def _wide_luts(cfg: DPConfig, n_words: int, seed: int) -> tuple:
    """Two tables of codes over the whole ``lut_data`` port, 0 … 2^(F+1) - 1, about half of
    them above 2^F (stored as 2^F, ``docs/gateware.md`` "Weight LUT"): from word 0 and from
    the middle frame."""
    import numpy as np

    rng = np.random.default_rng([seed, 0x3C0D])
    shape = (cfg.n_moves + 1, cfg.n_moves)
    size = cfg.width * cfg.height
    top = 1 << (cfg.weight_frac_bits + 1)
    return tuple((at, rng.integers(0, top, size=shape))
                 for at in (0, (n_words // size // 2) * size))


def _random_luts(cfg: DPConfig, n_words: int, seed: int) -> tuple:
    """Two random tables of codes 0 … 2^F: from word 0 and from the middle frame."""
    import numpy as np

    rng = np.random.default_rng([seed, 0x2EF])
    shape = (cfg.n_moves + 1, cfg.n_moves)
    size = cfg.width * cfg.height
    return tuple((at, rng.integers(0, (1 << cfg.weight_frac_bits) + 1, size=shape))
                 for at in (0, (n_words // size // 2) * size))


def _check_raw(sim, words, stim, k_changes=(), luts=(), reverse=False) -> tuple[str, str]:
    """``words`` with the K port driven to raw values (``k_changes``: (word index, K)) and
    raw tables written through the LUT port (``luts``: (word index, codes); ``reverse``:
    each table's entries from the last address to the first, so that a write that also
    reaches a later entry is not undone by that entry's own write); the model runs them as
    the design must take them: K clamped to [1, K_max], codes to [0, 2^F]. No resets or
    other settings changes."""
    import numpy as np

    from dptbd.model.settings import SegmentSettings
    from dptbd.sim.rtl.check import _checker
    from dptbd.sim.stimulus import lut_writes
    from dptbd.sim.stream_model import expected_stream, split_words
    from dptbd.sim.verilator import run as run_words

    cfg = sim.cfg
    raw = run_words(sim, words, valid_gap=stim.valid_gap, ready_pause=stim.ready_pause,
                    seed=stim.seed,
                    settings=[(i, k, cfg.n_candidates, cfg.bin_shift) for i, k in k_changes],
                    lut_writes=[(i, a, c) for i, codes in luts
                                for a, c in (lut_writes(cfg, codes)[::-1] if reverse
                                             else lut_writes(cfg, codes))])
    pixels, first = split_words(cfg, words)
    clamped = {i: SegmentSettings(min(max(k, 1), cfg.k_max), cfg.n_candidates, cfg.bin_shift)
               for i, k in k_changes}
    tables = {i: np.minimum(codes, 1 << cfg.weight_frac_bits) for i, codes in luts}
    exp = expected_stream(cfg, pixels, first, tables, clamped)
    board = _checker(cfg, "states", exp, cut_by_reset=False)
    board.receive_array(raw.out_words)
    report = (f"K port {[k for _, k in k_changes]}: " if k_changes else "") + board.report()
    if raw.status != "done":
        return hang_verdict(raw.status, board.report()) or "killed", report
    if board.failed or not board.done:
        return "killed", report
    begins = _segment_begin_report(exp, raw.counters)
    return ("killed", begins) if begins else ("survived", report)


def _segment_begin_report(exp, counters: dict) -> str:
    """``""`` if a run without resets (the model's expectation ``exp``, the harness's
    ``counters``) saw one ``segment_begin`` pulse with every word that begins a segment in
    the model (a frame 0: the stream's first word, every K-th frame, a resynchronisation)
    and no other, else what differs."""
    starts = [r.start for r in exp.runs if r.frame == 0]
    want = (len(starts), sum(s + 1 for s in starts))
    got = (counters.get("segment_begins"), counters.get("segment_begin_words"))
    if got == want:
        return ""
    return (f"segment_begin: {got[0]} pulses with words summing (index + 1) to {got[1]}, "
            f"model {want[0]} at words {starts[:8]}{' …' if len(starts) > 8 else ''} "
            f"(sum {want[1]})")


def run(sim, kind: str, seed: int) -> tuple[str, str]:
    """Run ``(kind, seed)`` of the slice on ``sim`` (``DPTBD_MUTANT`` selects the mutant):
    ``(verdict, report)``, the verdict ``killed``, ``timeout`` or ``survived``."""
    with warnings.catch_warnings():             # B_E saturates on purpose (CONFIGS)
        warnings.simplefilter("ignore", EnergyWidthWarning)
        return _run(sim, kind, seed)


def _run(sim, kind: str, seed: int) -> tuple[str, str]:
    from dptbd.sim.campaign import Case, _make_run
    from dptbd.sim.rtl.check import check_stream

    case = Case(f"mutant-{kind}", CONFIGS["dp"], "dp", FRAMES[kind], 1,
                _EVERY if kind == "faults" else (), kind == "random-lut")
    words, stim, _, _ = _make_run(case, seed, int(sim.latency))
    if kind == "backpressure":                  # the output stalled most of the time
        stim = dataclasses.replace(stim, valid_gap=0.0, ready_pause=BACKPRESSURE[seed % 4])
    if kind in ("k-edge", "timing"):
        stim = dataclasses.replace(stim, settings_changes=_edge_k(sim.cfg, len(words), seed))
    if kind == "timing":                        # full speed: no gap, no pause
        stim = dataclasses.replace(stim, valid_gap=0.0, ready_pause=0.0)
    if kind == "k-clamp":
        return _check_raw(sim, words, stim, k_changes=_edge_raw_k(sim.cfg, len(words), seed))
    if kind == "lut-clamp":
        words = _noise_words(sim.cfg, FRAMES[kind], seed)
        return _check_raw(sim, words, stim, luts=_wide_luts(sim.cfg, len(words), seed))
    if kind == "k-begin":                       # K = 0 or 7 at every segment's first pixel
        return _check_raw(sim, words, stim, k_changes=((0, K_BEGIN[seed]),))
    if kind == "lut-reverse":                   # random tables, written backwards, on noise
        words = _noise_words(sim.cfg, FRAMES[kind], seed + 8)
        return _check_raw(sim, words, stim, luts=_random_luts(sim.cfg, len(words), seed),
                          reverse=True)
    if kind == "lut-corners":                   # noise scenes: every LUT entry is read
        words = _noise_words(sim.cfg, FRAMES[kind], seed)
        stim = dataclasses.replace(stim, lut_changes=_corner_luts(sim.cfg, len(words), seed))
    result = check_stream(sim, words, stim)
    hung = stream_hang(sim, words, stim, result)
    if hung:
        return hung
    if result.passed and kind == "timing":
        late = _timing_report(result.raw, int(sim.latency))
        if late:
            return "killed", late
    if result.passed and not stim.resets:
        begins = _segment_begin_report(result.scored[-1][1], result.raw.counters)
        if begins:
            return "killed", begins
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
