"""What each run of the verification campaign draws from its seed only
(:mod:`dptbd.sim.campaign`): hostile scenes (:func:`hostile_frames`), stall densities, the
case's faults (framing faults, resets, LUT and settings rewrites, a garbage store), as the
input words and :class:`~dptbd.sim.rtl.check.Stimulus` of a compiled run (:func:`make_run`)."""

from __future__ import annotations

from typing import Sequence

import numpy as np

from dptbd.config import DPConfig
from dptbd.sim.campaign.cases import Case

__all__ = ["MAX_STALL", "hostile_frames", "make_run", "make_stream_run"]

#: The highest input gap and output back-pressure density a run draws.
MAX_STALL = 0.7


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
                   rng: np.random.Generator, align: int = 1
                   ) -> tuple[np.ndarray, list[str], list]:
    """Cut, lengthen or mark frames of a clean word stream; what was done, for the report,
    and (fault, index of the first word it touches) for the coverage bins. ``align`` = P
    at P pixels per clock: every fault at a multiple of P pixels (a beat boundary)."""
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
            p = align * int(rng.integers(1, size // align))
            frames[f][p] |= first_bit                        # a start marker mid-frame
            notes.append(f"start-of-frame marker at pixel {p} of frame {f}")
            touched.append((fault, f, p))
        elif fault == "short_frame":
            keep = align * int(rng.integers(1, size // align))
            frames[f] = frames[f][:keep]
            notes.append(f"frame {f} cut to {keep} of {size} pixels")
            touched.append((fault, f + 1, 0))
        else:
            extra = align * int(rng.integers(1, size // align))
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
    """The input words and :class:`~dptbd.sim.rtl.check.Stimulus` of run ``seed`` of ``case``,
    and a description of its faults; for ``design="axi"`` the
    :class:`~dptbd.sim.axi.runs.AxiPlan` (:func:`dptbd.sim.axi.runs.draw_run`), for
    ``"dp_axi"`` the :class:`~dptbd.sim.campaign.store.dp_axi.StorePlan`. ``latency``:
    the build's DP pipeline L (then about half the runs with resets get one more early on,
    soon after the first word, when the pipeline holds 0 … L words)."""
    if case.design == "axi":
        from dptbd.sim.axi.runs import draw_run
        return draw_run(case, seed)
    if case.design == "dp_axi":
        from dptbd.sim.campaign.store.dp_axi import draw_store_run
        return draw_store_run(case, seed)
    return make_stream_run(case, seed, latency)[:3]


def make_stream_run(case: Case, seed: int, latency: int | None = None):
    """:func:`make_run` of a stream design and the framing faults' (fault, first word
    touched)."""
    from dptbd.sim.rtl.check import Stimulus
    from dptbd.sim.stimulus import pixel_words
    from dptbd.sim.verilator import cycle_budget

    cfg = case.cfg
    p = cfg.pixels_per_clock
    rng = np.random.default_rng([seed, 0x7E57])
    frames = hostile_frames(cfg, case.frames, rng)
    words, notes, events = _faulty_stream(cfg, pixel_words(cfg, frames), case.faults, rng, p)
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
        budget = int(len(words) // p / ((1 - gap) * (1 - pause)))     # cycles of the run
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
    if p > 1:       # beats of P pixels; the changes before a pixel go before its beat
        words = _pixel_beats(cfg, words)
        luts = [(i // p, codes) for i, codes in luts]
        settings = tuple((i // p, entry) for i, entry in settings)
        stray = tuple((i // p, a, c) for i, a, c in stray)
    stim = Stimulus(valid_gap=gap, ready_pause=pause, seed=int(seed), resets=tuple(resets),
                    lut_changes=tuple(luts), store_init=store, settings_changes=settings,
                    stray_lut_writes=stray)
    notes.insert(0, f"gaps {gap:.2f}, back-pressure {pause:.2f}")
    assert all(c < cycle_budget(len(words), gap, pause, 0) for c, _ in resets)
    return words, stim, notes, tuple(events)


def _pixel_beats(cfg: DPConfig, words: np.ndarray) -> np.ndarray:
    """``pixels`` words of one pixel each (a multiple of P, ``first`` only on a beat's
    first pixel) as the beats of P pixels the harness takes at P > 1
    (:func:`dptbd.sim.verilator.beat_words`)."""
    from amaranth.lib import data

    from dptbd.hw.layouts import field_offsets, pixel_layout
    from dptbd.hw.wide import pack_beat, wide_pixel_layout
    from dptbd.sim.verilator import beat_words

    p = cfg.pixels_per_clock
    first = int(field_offsets(pixel_layout(cfg))["first"]["offset"])
    values = np.asarray(words, dtype=np.uint64).reshape(-1, p)
    beats = [pack_beat(cfg, [int(v) & ((1 << first) - 1) for v in row], bool(int(row[0]) >> first))
             for row in values]
    per_beat = -(-data.Layout.cast(wide_pixel_layout(cfg)).size // 64)
    return beat_words(beats, per_beat)
