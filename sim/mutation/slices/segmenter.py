"""The ``segmenter`` slice (``dptbd_seg``): seeded runs of the campaign
(:func:`dptbd.sim.campaign.make_run`: hostile scenes, input gaps, output back-pressure,
resets, misaligned / short / long frames, LUT and settings rewrites) checked by
:func:`dptbd.sim.rtl.check.check_stream` against the golden model; settings ports driven out
of range (``settings-range``); noise scenes at K = K_max and n = C under tables of corner
codes (``lut-corners``) and of codes above 2^F (``lut-wide``), where every LUT entry's bits
reach a listed weighted sum; lists of every length from C - 20 to C records
(``list-lengths``, K = 1 and 2); full-scale frames under tables that make one move the winner
(``full-scale``); and clean runs under back-pressure whose every input and output cycle
must be the original design's (``cycles``). The runs without resets check the counts of the
``events`` pulses too."""

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
             + [("settings-range", s) for s in range(4)]
             + [("lut-corners", s) for s in range(10)] + [("lut-wide", s) for s in range(4)]
             + [("settings-resync", s) for s in range(6)]
             + [("resync-last", s) for s in range(3)]
             + [("list-lengths", s) for s in range(4)] + [("full-scale", s) for s in range(9)]
             + [("cycles", s) for s in range(4)])

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


def _raw_run(sim, words, stim, changes=(), luts=None) -> tuple[str, str]:
    """A run without resets whose settings ports carry ``changes`` (``(word index, (K, n, s)
    driven, SegmentSettings in force)``) and whose LUT port writes ``luts`` (``(word index,
    codes)``, codes up to the port's maximum; default the stimulus' tables), checked word for
    word against the golden model with the values in force (codes clamped to 2^F), and the
    counts of the ``events`` pulses (frames, segments, lists, saturations) the model's."""
    from dptbd.sim.rtl.check import (_checker, _event_report, expected_stream, lut_writes,
                                     split_words)
    from dptbd.sim.verilator import run as run_words

    cfg = sim.cfg
    luts = tuple(stim.lut_changes) if luts is None else tuple(luts)
    writes = [(int(i), a, c) for i, codes in luts for a, c in lut_writes(cfg, codes)]
    raw = run_words(sim, words, valid_gap=stim.valid_gap, ready_pause=stim.ready_pause,
                    seed=stim.seed, lut_writes=writes,
                    settings=[(i, *driven) for i, driven, _ in changes])
    pixels, first = split_words(cfg, np.asarray(words))
    exp = expected_stream(cfg, pixels, first,
                          {int(i): np.minimum(c, 1 << cfg.weight_frac_bits) for i, c in luts},
                          {i: entry for i, _, entry in changes})
    board = _checker(cfg, sim.output, exp, cut_by_reset=False)
    board.receive_array(raw.out_words)
    if board.failed or not board.done:
        taken = int(np.count_nonzero(raw.accept_cycles != NEVER))
        return "killed", (f"{taken} of {len(words)} words taken in {raw.cycles} cycles; "
                          f"{board.report()}")
    if raw.status != "done":
        return "timeout", f"cycle budget ({raw.cycles} cycles) ran out: {board.report()}"
    events = _event_report(sim.output, exp, board, raw, cfg)
    if events:
        return "killed", f"{board.report()}; {events}"
    return "survived", board.report()


def _range_run(sim, words, stim, seed: int) -> tuple[str, str]:
    """A run whose settings ports carry out-of-range values (:func:`range_settings`), checked
    word for word against the golden model with the clamped settings."""
    return _raw_run(sim, words, stim, range_settings(sim.cfg, len(words), seed))


def _all_listed(cfg: DPConfig) -> tuple:
    """From word 0: K = K_max (the weight LUT's rows of every direction are read: with K = 2
    only the START row is, a segment's first frame having d = START) and n = C, every pixel
    of the scored frame in its list (s the build's)."""
    from dptbd.model.settings import SegmentSettings

    entry = SegmentSettings(cfg.k_max, cfg.record_capacity, cfg.bin_shift)
    return ((0, (entry.segment_frames, entry.candidate_count, entry.histogram_shift), entry),)


#: The lists of the ``list-lengths`` runs hold C - k records for each of these k (one frame
#: each, shuffled), then C.
LIST_SHORTFALLS = range(1, 21)


def list_length_frames(cfg: DPConfig, lengths, rng) -> np.ndarray:
    """Frames (flat, one per row) of m bright pixels each for m = C - 1, ``lengths`` in
    order, then C: the bright pixels at least 2^s (bin 1 and up), the frame's last pixel
    among them, the others 0 (the ``list-lengths`` runs of this slice and of ``axi``'s)."""
    size, capacity = cfg.width * cfg.height, cfg.record_capacity
    frames = np.zeros((len(lengths) + 2, size), dtype=np.uint16)
    for f, m in enumerate([capacity - 1, *lengths, capacity]):
        bright = np.zeros(size, dtype=bool)
        bright[size - 1] = True
        bright[rng.choice(size - 1, m - 1, replace=False)] = True
        frames[f] = np.where(bright, rng.integers(1 << cfg.bin_shift, cfg.pixel_max + 1,
                                                  size=size), 0)
    return frames


def list_lengths(cfg: DPConfig, seed: int) -> tuple[np.ndarray, tuple]:
    """The ``list-lengths`` run of ``seed``: ``(words, settings changes)``. K = 1 (seeds 0, 1)
    or K = 2 (seeds 2, 3: each bright frame after a frame of zeros, so the n a list is cut
    at is the one the segmenter held through the segment's unscored frame) and n = C - 1
    from word 0; frame 0 has C - 1 bright pixels, then one frame for each length m = C - k,
    k in :data:`LIST_SHORTFALLS` (shuffled), then one of C: m bright pixels (at least 2^s,
    so in bin 1 or above; its last pixel among them), the others 0. K = 1 makes E the pixel; each frame's
    histogram has at most C - 1 pixels in bins 1 and up and at least one in bin 0, so the next
    list's T is 1 and every list from the second on holds exactly its frame's bright pixels:
    every list length from C - 20 to C, each ending with a selected pixel (a compare of the
    emitter's count with a constant near C is seen; the noise runs list only C). The
    configuration's C is W * H."""
    from dptbd.model.settings import SegmentSettings
    from dptbd.sim.stimulus import pixel_words

    rng = np.random.default_rng([seed, 0x115])
    size = cfg.width * cfg.height
    capacity = cfg.record_capacity
    lengths = [capacity - k for k in LIST_SHORTFALLS]
    rng.shuffle(lengths)
    frames = list_length_frames(cfg, lengths, rng)
    k = 1 if seed % 4 < 2 else 2
    if k == 2:                                   # a frame of zeros before each: E = pixel
        frames = np.stack([np.zeros_like(frames), frames], axis=1).reshape(-1, size)
    entry = SegmentSettings(k, capacity - 1, cfg.bin_shift)
    changes = ((0, (k, capacity - 1, cfg.bin_shift), entry),)
    return pixel_words(cfg, frames.reshape(-1, cfg.height, cfg.width)), changes


def full_scale_lut(cfg: DPConfig, move: int) -> np.ndarray:
    """The table of the ``full-scale`` run of ``move``: every row's code 2^F - 1 for ``move``
    and 2^F - 2 for the others, so that ``move`` wins wherever its predecessor is inside."""
    top = (1 << cfg.weight_frac_bits) - 1
    codes = np.full((cfg.n_moves + 1, cfg.n_moves), top - 1)
    codes[:, move] = top
    return codes


#: Frames of the ``full-scale`` runs: three segments of K_max (the first list is empty).
FULL_SCALE_FRAMES = 3 * CONFIGS["segmenter"]["max_segment_frames"]


def _full_scale_run(sim, seed: int) -> tuple[str, str]:
    """Every pixel of every frame at full scale, K = K_max and n = C (every pixel listed),
    under :func:`full_scale_lut` of move ``seed``: E reaches its largest values without
    saturating (B_in = 6, F = 4: 63, 122, 177, 228 < 2^8), so every bit of the weighted
    sums' partial sums is set somewhere, and the move of the run is the one whose weighted
    sum is E, so a weighted sum made smaller (or larger) by a mutation changes E."""
    from dptbd.sim.rtl.check import Stimulus
    from dptbd.sim.stimulus import pixel_words

    cfg = sim.cfg
    frames = np.full((FULL_SCALE_FRAMES, cfg.height, cfg.width), cfg.pixel_max, dtype=np.uint16)
    luts = ((0, full_scale_lut(cfg, seed % cfg.n_moves)),)
    return _raw_run(sim, pixel_words(cfg, frames), Stimulus(seed=seed), _all_listed(cfg), luts)


def run(sim, kind: str, seed: int) -> tuple[str, str]:
    from dptbd.sim.campaign import Case, make_run
    from dptbd.sim.rtl.check import Stimulus, check_stream

    if kind in NOISE_FRAMES:
        return _noise_run(sim, kind, seed)
    if kind == "cycles":
        return _cycles_run(sim, seed)
    if kind == "full-scale":
        return _full_scale_run(sim, seed)
    if kind == "list-lengths":
        words, changes = list_lengths(sim.cfg, seed)
        return _raw_run(sim, words, Stimulus(seed=seed), changes)
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


#: Frames of the runs on noise scenes (:func:`!_noise_run`).
NOISE_FRAMES = {"lut-corners": 20, "lut-wide": 20, "settings-resync": 12, "resync-last": 12}


def resync_settings(cfg: DPConfig, seed: int) -> tuple[int, tuple, int]:
    """The ``settings-resync`` run of ``seed``: ``(word index, (K, n, s), resync word)``.
    One word after the start of segment 1, 2 or 3 (the build's K, every start aligned so
    far) the ports change, K to another value, and 1 … 3 words later a ``first`` restarts
    the DP's counters: the DP began that segment (the top latched its settings) but the
    segmenter has not taken them yet (the pipeline holds more words than that), so a latch
    at the resync would hand the segmenter the new values instead (``docs/gateware.md``,
    "Resynchronisation and settings": a resync's segment start is never latched)."""
    rng = np.random.default_rng([seed, 0x2E5C])
    start = (1 + seed % 3) * cfg.segment_frames * cfg.width * cfg.height
    k = int(rng.choice([k for k in range(1, cfg.k_max + 1) if k != cfg.segment_frames]))
    settings = (k, int(rng.integers(0, cfg.record_capacity + 1)),
                int(rng.integers(0, cfg.energy_bits)))
    return start + 1, settings, start + 2 + seed % 3


def _noise_run(sim, kind: str, seed: int) -> tuple[str, str]:
    """Uniform noise frames (every direction taken, every LUT entry read, ``dp`` slice's
    :func:`~dptbd.sim.mutation.slices.dp._noise_words`), without gaps or pauses:

    * ``lut-corners``: tables of one corner code each (2^F, 2^F - 1, 0, alternate bits: every
      code bit of every entry set in one run and clear in another), n = C (every pixel of
      the scored frame listed, so every weighted sum that wins shows);
    * ``lut-wide``: random tables over the whole ``lut_data`` port, about half of the codes
      above 2^F (stored as 2^F), n = C;
    * ``settings-resync``: new settings one word into a segment and a resync a few words
      later (:func:`resync_settings`);
    * ``resync-last``: K = 1, n = C, and a ``first`` on a frame's last pixel (frame 1, 2
      or 3): the pixel the controller takes as the segment's last is a new segment's first,
      so a segment end that ignores the resync shows.

    K = K_max (:func:`_all_listed`; ``resync-last``: K = 1); the first table from word 0,
    the second from the third segment on."""
    from dptbd.sim.mutation.slices.dp import _corners, _noise_words, _wide_luts
    from dptbd.sim.rtl.check import Stimulus

    cfg = sim.cfg
    words = _noise_words(cfg, NOISE_FRAMES[kind], seed)
    stim = Stimulus(seed=seed)
    if kind == "settings-resync":
        from dptbd.model.settings import SegmentSettings
        from dptbd.sim.stimulus import pixel_words

        at, settings, resync = resync_settings(cfg, seed)
        first = pixel_words(cfg, np.zeros((1, cfg.height, cfg.width), dtype=np.uint16))[0]
        words = words.copy()
        words[resync] |= first                     # the first word's only bit: `first`
        return _raw_run(sim, words, stim, ((at, settings, SegmentSettings(*settings)),))
    if kind == "resync-last":
        from dptbd.model.settings import SegmentSettings
        from dptbd.sim.stimulus import pixel_words

        first = pixel_words(cfg, np.zeros((1, cfg.height, cfg.width), dtype=np.uint16))[0]
        words = words.copy()
        words[(1 + seed % 3) * cfg.width * cfg.height - 1] |= first
        one = SegmentSettings(1, cfg.record_capacity, cfg.bin_shift)
        return _raw_run(sim, words, stim,
                        ((0, (1, one.candidate_count, one.histogram_shift), one),))
    # two tables: from word 0 (the first list, after reset, is empty: T selects nothing) and
    # from the third segment's first word on, each in force for at least one whole segment
    second = 2 * cfg.k_max * cfg.width * cfg.height
    shape = (cfg.n_moves + 1, cfg.n_moves)
    if kind == "lut-corners":
        corners = _corners(cfg.weight_frac_bits)
        luts = ((0, np.full(shape, corners[seed % len(corners)])),
                (second, np.full(shape, corners[(seed + 1) % len(corners)])))
    else:
        luts = tuple((at, codes) for (_, codes), at in
                     zip(_wide_luts(cfg, len(words), seed), (0, second)))
    return _raw_run(sim, words, stim, _all_listed(cfg), luts)


#: Output back-pressure of the ``cycles`` runs (seed % 4): the FIFO fills to its ``space``
#: limit and drains, so the cycle each word goes in and out depends on every flow-control bit.
CYCLES_PAUSE = (0.5, 0.7, 0.8, 0.9)

#: The original design's runs of the ``cycles`` kind, per build and seed (one per process).
_ORIGINAL_RUNS: dict = {}


def _cycles_run(sim, seed: int) -> tuple[str, str]:
    """A clean run (12 frames, K = 2) under output back-pressure (:data:`CYCLES_PAUSE`),
    checked word for word against the model and then cycle for cycle against the original
    design (``mutsel = 0``, MCY's reference): the cycle of every input word's acceptance and
    of every output transfer must be the original's. The harness' back-pressure is a seeded
    function of the cycle and the run, so the same stimulus gives the same cycles; a mutant
    that changes only when words move (a flow-control limit, a stall) changes an output
    (``ready``, ``valid``) and is killed here."""
    import os

    from dptbd.sim.campaign import Case, make_run
    from dptbd.sim.rtl.check import check_stream

    case = Case("mutant-cycles", CONFIGS["segmenter"], "segmenter", 12, 1, (), False)
    words, stim, _ = make_run(case, seed)
    stim = dataclasses.replace(stim, valid_gap=0.0, ready_pause=CYCLES_PAUSE[seed % 4])
    key = (str(sim.executable), seed)
    if key not in _ORIGINAL_RUNS:
        mutant = os.environ.get("DPTBD_MUTANT")
        os.environ["DPTBD_MUTANT"] = "0"
        try:
            _ORIGINAL_RUNS[key] = check_stream(sim, words, stim)
        finally:
            if mutant is None:
                os.environ.pop("DPTBD_MUTANT", None)
            else:
                os.environ["DPTBD_MUTANT"] = mutant
    original = _ORIGINAL_RUNS[key]
    if not original.passed:
        raise RuntimeError(f"the original fails the cycles run of seed {seed}: "
                           f"{original.report}")
    result = check_stream(sim, words, stim)
    hung = stream_hang(sim, words, stim, result)
    if hung:
        return hung
    if not result.passed:
        return "killed", result.report
    for what, got, want in (("input word", result.raw.accept_cycles,
                             original.raw.accept_cycles),
                            ("output word", result.raw.out_cycles, original.raw.out_cycles)):
        if len(got) != len(want) or (got != want).any():
            i = int(np.argmax(got != want)) if len(got) == len(want) else min(len(got),
                                                                               len(want))
            return "killed", (f"{what} {i} moved at cycle {int(got[i]) if i < len(got) else '-'}"
                              f", the original's at {int(want[i]) if i < len(want) else '-'}; "
                              f"{result.report}")
    return "survived", result.report
