"""The ``segmenter`` slice (``dptbd_seg``): seeded runs of the campaign
(:func:`dptbd.sim.campaign.make_run`: hostile scenes, input gaps, output back-pressure,
resets, misaligned / short / long frames, LUT and settings rewrites) checked by
:func:`dptbd.sim.rtl.check.check_stream` against the golden model."""

from __future__ import annotations

import dataclasses

import numpy as np

from dptbd.config import DPConfig
from dptbd.sim.mutation.slices import BACKPRESSURE, CONFIGS
from dptbd.sim.mutation.verdict import stream_hang
from dptbd.sim.rtl.check import NEVER

__all__ = ["RUNS", "run"]

#: The runs of the slice: ``(kind, seed)``, in this order.
RUNS = tuple([("clean", s) for s in range(4)] + [("settings-edge", s) for s in range(8)]
             + [("random-lut", s) for s in range(12)]
             + [("faults", s) for s in range(32)]
             + [("backpressure", s) for s in range(4)]
             + [("settings-range", s) for s in range(4)])

_EVERY = ("reset", "misaligned_first", "short_frame", "long_frame", "lut", "settings")


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


def _port_values(cfg: DPConfig) -> tuple[int, int, int]:
    """The largest value each settings port (K, n, s) can carry: its width's maximum."""
    return ((1 << cfg.k_max.bit_length()) - 1, (1 << cfg.record_capacity.bit_length()) - 1,
            (1 << (cfg.energy_bits - 1).bit_length()) - 1)


def range_settings(cfg: DPConfig, n_words: int, seed: int) -> tuple:
    """``(word index, (K, n, s) driven, SegmentSettings in force)``: settings ports driven
    with values outside their ranges as often as inside (K = 0 or above K_max, n above C,
    s above B_E - 1 where the port holds it), a few words after most segment starts and at
    random words; in force is the clamped value (``docs/gateware.md``, "Run-time settings":
    out-of-range values are clamped, never wrapped)."""
    from dptbd.model.settings import SegmentSettings

    rng = np.random.default_rng([seed, 0x0C1A])
    k_top, n_top, s_top = _port_values(cfg)
    size = cfg.width * cfg.height * cfg.segment_frames
    spots = [start + int(rng.integers(0, 24)) for start in range(size, n_words, size)]
    spots += [int(v) for v in rng.integers(1, n_words, size=3)]
    out = []
    for at in sorted(spots):
        if at >= n_words:
            continue
        outside = rng.random() < 0.5
        k = int(rng.choice([0, *range(cfg.k_max + 1, k_top + 1)]) if outside
                else rng.integers(1, cfg.k_max + 1))
        # in range: n near its ends as often as anywhere (n = 0 against 1 selects nothing
        # or the brightest pixel)
        n = int(rng.integers(cfg.record_capacity + 1, n_top + 1) if outside and
                n_top > cfg.record_capacity else
                rng.choice([0, 1, 2, cfg.record_capacity - 1, cfg.record_capacity])
                if rng.random() < 0.5 else rng.integers(0, cfg.record_capacity + 1))
        s = int(rng.integers(0, s_top + 1))
        out.append((at, (k, n, s), SegmentSettings(min(max(k, 1), cfg.k_max),
                                                   min(n, cfg.record_capacity),
                                                   min(s, cfg.energy_bits - 1))))
    return tuple(out)


def _range_run(sim, words, stim, seed: int) -> tuple[str, str]:
    """A run whose settings ports carry out-of-range values (:func:`range_settings`), checked
    word for word against the golden model with the clamped settings."""
    from dptbd.sim.rtl.check import _checker, expected_stream, lut_writes, split_words
    from dptbd.sim.verilator import run as run_words

    cfg = sim.cfg
    changes = range_settings(cfg, len(words), seed)
    writes = [(int(i), a, c) for i, codes in stim.lut_changes for a, c in lut_writes(cfg, codes)]
    raw = run_words(sim, words, valid_gap=stim.valid_gap, ready_pause=stim.ready_pause,
                    seed=stim.seed, lut_writes=writes,
                    settings=[(i, *driven) for i, driven, _ in changes])
    pixels, first = split_words(cfg, np.asarray(words))
    exp = expected_stream(cfg, pixels, first, {int(i): c for i, c in stim.lut_changes},
                          {i: entry for i, _, entry in changes})
    board = _checker(cfg, sim.output, exp, cut_by_reset=False)
    board.receive_array(raw.out_words)
    if board.failed or not board.done:
        taken = int(np.count_nonzero(raw.accept_cycles != NEVER))
        return "killed", (f"{taken} of {len(words)} words taken in {raw.cycles} cycles; "
                          f"{board.report()}")
    if raw.status != "done":
        return "timeout", f"cycle budget ({raw.cycles} cycles) ran out: {board.report()}"
    return "survived", board.report()


def run(sim, kind: str, seed: int) -> tuple[str, str]:
    from dptbd.sim.campaign import Case, make_run
    from dptbd.sim.rtl.check import check_stream

    frames = {"clean": 12, "random-lut": 16, "faults": 24, "settings-edge": 16,
              "backpressure": 8, "settings-range": 16}[kind]
    case = Case(f"mutant-{kind}", CONFIGS["segmenter"], "segmenter", frames, 1,
                () if kind != "faults" else _EVERY,
                kind in ("random-lut", "settings-edge", "settings-range"))
    words, stim, _ = make_run(case, seed)
    if kind == "settings-range":
        return _range_run(sim, words, stim, seed)
    if kind == "backpressure":                  # the output stalled most of the time
        stim = dataclasses.replace(stim, valid_gap=0.0, ready_pause=BACKPRESSURE[seed % 4])
    if kind == "settings-edge":
        stim = dataclasses.replace(stim, settings_changes=_edge_settings(sim.cfg, len(words),
                                                                         seed))
    result = check_stream(sim, words, stim)
    hung = stream_hang(sim, words, stim, result)
    if hung:
        return hung
    return ("survived" if result.passed else "killed"), result.report
