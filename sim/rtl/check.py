"""A compiled RTL run scored against the golden model: stimulus in, verdict out.

:func:`check_stream` runs one input stream through a :class:`~dptbd.sim.verilator.VerilatorBuild`
with a :class:`Stimulus` (pauses, resets, LUT writes, the external store's power-up
contents), splits what came out at every reset, asks :mod:`dptbd.sim.stream_model` what the
golden model says for the words accepted since that reset, and compares with the project's
scoreboards, both :class:`~dptbd.sim.checker.InOrderChecker`:
:class:`~dptbd.sim.scoreboard.Scoreboard` (``states``: the first mismatching frame, row,
column and field) and :class:`~dptbd.sim.candidate_scoreboard.CandidateScoreboard`
(``candidates``: segment, record, field).

Without resets, the counts of the ``events`` pulses (``frame_done``, ``segment_done``,
``list_done``, ``saturated``) that the harness reports are compared with the model's too.

The promise checked around a reset (``docs/gateware.md``, "Reset and resynchronisation"):
what comes out before it is a prefix of the model's output for the words accepted before it
(words in flight are dropped), and everything after it equals the model's output for the
words accepted after it, counted from a new segment.
"""

from __future__ import annotations

import dataclasses
from typing import Sequence

import numpy as np

from dptbd.config import DPConfig
from dptbd.sim.scoreboard import Scoreboard
from dptbd.model.segmentation import segment_stream
from dptbd.model.settings import SegmentSettings
from dptbd.sim.candidate_scoreboard import CandidateScoreboard
from dptbd.sim.stimulus import lut_writes
from dptbd.sim.stream_model import (StreamExpectation, expected_stream, saturated_events,
                                   split_words)
from dptbd.sim.verilator import RawRun, VerilatorBuild, beat_values, run

__all__ = ["Stimulus", "CheckResult", "check_stream", "check_frames", "split_beats",
           "beat_state_words"]

NEVER = np.uint64(2**64 - 1)


@dataclasses.dataclass(frozen=True)
class Stimulus:
    """Everything but the input words that a compiled run takes (all seeded).

    Attributes
    ----------
    valid_gap, ready_pause : float
        Probability in [0, 1) of an idle input cycle and of output back-pressure.
    seed : int
        Seeds the pause generators and the external store's garbage.
    resets : tuple of (cycle, hold)
        ``rst`` high for ``hold`` cycles from ``cycle``.
    lut_changes : tuple of (word index, codes)
        The whole (M+1) x M table written just before that input word.
    store_init : str
        ``"zero"`` or ``"random"`` (``design="core"``: DPCore's external store at power-up).
    settings_changes : tuple of (word index, SegmentSettings)
        Run-time settings driven from just before that input word on (sampled by the
        design at its next segment start).
    stray_lut_writes : tuple of (word index, address, code)
        LUT writes to addresses beyond the table (the LUT port is wider than the table),
        just before that input word: the design ignores them (``hw/weight_lut.py``).
    """

    valid_gap: float = 0.0
    ready_pause: float = 0.0
    seed: int = 1
    resets: tuple[tuple[int, int], ...] = ()
    lut_changes: tuple[tuple[int, np.ndarray], ...] = ()
    store_init: str = "zero"
    settings_changes: tuple[tuple[int, SegmentSettings], ...] = ()
    stray_lut_writes: tuple[tuple[int, int, int], ...] = ()


@dataclasses.dataclass(frozen=True)
class CheckResult:
    """The verdict of one compiled run."""

    passed: bool
    report: str
    words_in: int             # input words accepted
    words_out: int            # output words compared with the model
    cycles: int | None        # first accepted word to last output, inclusive
    epochs: int               # 1 + the resets that happened
    raw: RawRun
    #: per epoch compared: (index of its first accepted word, the model's expectation, the
    #: scoreboard) — what :mod:`dptbd.sim.coverage.bins` reads the run's bins from
    scored: tuple = ()

    @property
    def cycles_per_second(self) -> float:
        return self.raw.cycles_per_second


def _checker(cfg: DPConfig, design_output: str, exp: StreamExpectation, *, cut_by_reset: bool):
    if design_output == "states":
        return Scoreboard(cfg, exp.words, positions=exp.positions)
    fields, settings = exp.fields, exp.settings
    if cut_by_reset:
        # Records of the list in progress stream out before its segment ends: a reset can
        # come after some of them. The model finishes a list only at a segment end, so the
        # stream is padded (zero energy) to beyond the next segment end; what came out
        # before the reset must be a prefix of the padded stream's lists.
        pad = _padding(cfg, exp.runs)
        fields = np.concatenate([fields, pad])
        last = settings[-1] if len(settings) else [cfg.segment_frames, cfg.n_candidates,
                                                   cfg.bin_shift]
        settings = np.concatenate([settings, np.tile(last, (len(pad), 1))])
    return CandidateScoreboard(cfg, segment_stream(fields, cfg, settings))


def _event_report(design_output: str, exp: StreamExpectation, board, raw: RawRun,
                  cfg: DPConfig) -> str:
    """'' when the harness's event counts equal the model's, else what differs."""
    want = {"frame_done": int(exp.fields[:, 3].sum()), "segment_done": int(exp.fields[:, 4].sum()),
            "list_done": len(board.lists) if design_output == "candidates" else 0,
            "saturated": saturated_events(cfg, exp.saturated)}
    bad = [f"{name} counted {raw.counters.get('events_' + name)}, model {value}"
           for name, value in want.items() if raw.counters.get("events_" + name) != value]
    return "events: " + "; ".join(bad) if bad else ""


def _padding(cfg: DPConfig, runs) -> np.ndarray:
    """``states`` rows (E = 0, d = START) completing the last frame of ``runs`` and K more
    frames, with the counters' end flags."""
    size = cfg.width * cfg.height
    last = runs[-1] if runs else None
    k = last.segment_frames if last is not None else cfg.segment_frames
    done = 0 if last is None or last.complete else last.stop - last.start
    frame = 0 if last is None else (last.frame if not last.complete else last.frame + 1)
    rows = []
    for extra in range(k + 1):
        p = np.arange(done if extra == 0 else 0, size)
        block = np.zeros((len(p), 5), dtype=np.int64)
        block[:, 1] = cfg.start_code
        block[:, 2] = (p % cfg.width) == cfg.width - 1
        if len(p):
            block[-1, 3] = 1
            block[-1, 4] = int((frame + extra) % k == k - 1)
        rows.append(block)
    return np.concatenate(rows)


def check_stream(sim: VerilatorBuild, words: np.ndarray, stimulus: Stimulus = Stimulus(),
                 *, trace=None, coverage=None) -> CheckResult:
    """Run ``words`` through ``sim`` with ``stimulus`` and compare every output word.

    Parameters
    ----------
    sim : VerilatorBuild
    words : numpy.ndarray
        Packed ``pixels`` payloads (:func:`dptbd.sim.stimulus.pixel_words`), any framing:
        short, long or misaligned frames are modelled by the counter rule. At P > 1 pixels
        per clock: beats as :func:`dptbd.sim.verilator.run` takes them (one row of uint64
        words per beat of :func:`~dptbd.hw.wide.pack_beat`); the word indices of the
        stimulus's LUT and settings changes then count beats, and the verdict's words (in,
        out, compared) count pixels and states.
    stimulus : Stimulus
    trace : path, optional
        FST waveform (a build with ``waves=True``).
    coverage : path, optional
        The run's coverage data (a build with ``coverage=True``).
    """
    cfg = sim.cfg
    writes = [(int(i), a, c) for i, codes in stimulus.lut_changes
              for a, c in lut_writes(cfg, codes)]
    for i, a, c in stimulus.stray_lut_writes:
        if not cfg.lut_entries <= int(a) < 1 << (cfg.lut_entries - 1).bit_length():
            raise ValueError(f"a stray LUT write goes beyond the table: address "
                             f"{cfg.lut_entries} … {(1 << (cfg.lut_entries - 1).bit_length()) - 1}"
                             f", got {a}")
        writes.append((int(i), int(a), int(c)))
    settings = [(int(i), *dataclasses.astuple(entry.checked(cfg)))
                for i, entry in stimulus.settings_changes]
    raw = run(sim, words, valid_gap=stimulus.valid_gap, ready_pause=stimulus.ready_pause,
              seed=stimulus.seed, resets=stimulus.resets, lut_writes=writes,
              settings=settings, store_init=stimulus.store_init, trace=trace,
              coverage=coverage)
    # per pixel from here on: at P > 1 a beat's P pixels (and its P states) share its cycle
    p = cfg.pixels_per_clock
    all_pixels, all_first = split_words(cfg, words) if p == 1 else split_beats(cfg, words)
    accept_cycles, out_cycles, out_words = np.repeat(raw.accept_cycles, p), raw.out_cycles, \
        raw.out_words
    if p > 1 and sim.output == "states":
        out_cycles, out_words = np.repeat(out_cycles, p), beat_state_words(cfg, out_words)
    accepted = accept_cycles != NEVER
    n_in = int(np.count_nonzero(accepted))
    pixels, first = all_pixels[:n_in], all_first[:n_in]
    resets = sorted(c for c, _ in stimulus.resets)
    # epoch boundaries: words accepted and outputs transferred before each reset cycle
    in_cuts = [0] + [int(np.searchsorted(accept_cycles[:n_in], c)) for c in resets] + [n_in]
    out_cuts = [0] + [int(np.searchsorted(out_cycles, c)) for c in resets] + \
        [len(out_words)]
    report, passed, compared = "", True, 0
    scored = []
    for e in range(len(in_cuts) - 1):
        a, b = in_cuts[e], in_cuts[e + 1]
        changes = {int(i) * p - a: codes for i, codes in stimulus.lut_changes}
        # the harness keeps driving the settings ports through a reset: a change before
        # this epoch is in force at its start
        written = {int(i) * p - a: entry for i, entry in stimulus.settings_changes}
        exp = expected_stream(cfg, pixels[a:b], first[a:b], changes, written)
        last = e == len(in_cuts) - 2
        board = _checker(cfg, sim.output, exp, cut_by_reset=not last)
        got = out_words[out_cuts[e]:out_cuts[e + 1]]
        board.receive_array(got)
        compared += board.count
        scored.append((a, exp, board))
        label = f"after reset {e} (cycle {resets[e - 1]}): " if e else ""
        if board.failed or (last and not board.done):
            passed = False
            report = label + board.report()
            break
        if not last:
            report += f"{label}{board.count} of {board.total} words before reset {e + 1}; "
    if passed:
        if raw.status != "done":
            passed = False
            report += (f"timeout after {raw.cycles} cycles: {n_in} of {len(all_pixels)} "
                       f"words in")
        elif n_in != len(all_pixels):
            passed = False
            report += f"only {n_in} of {len(all_pixels)} words accepted"
        else:
            report += board.report()
            events = _event_report(sim.output, exp, board, raw, cfg) if not resets else ""
            if events:
                passed = False
                report += "; " + events
    cycles = None
    if n_in and len(out_words):
        cycles = int(raw.out_cycles[-1]) - int(raw.accept_cycles[0]) + 1
    return CheckResult(passed, report, n_in, compared, cycles, len(in_cuts) - 1, raw,
                       tuple(scored))


def check_frames(sim: VerilatorBuild, frames: np.ndarray, stimulus: Stimulus = Stimulus(),
                 *, trace=None) -> CheckResult:
    """:func:`check_stream` on whole frames ``(T, H, W)`` (refused like ``dptbd sim``: wrong
    frame size, pixels wider than B_in); at P > 1 as beats of P pixels, ``first`` on each
    frame's first beat."""
    from dptbd.sim.icarus import check_scene
    from dptbd.sim.stimulus import pixel_words

    cfg = sim.cfg
    frames = check_scene(cfg, frames)
    if cfg.pixels_per_clock == 1:
        return check_stream(sim, pixel_words(cfg, frames), stimulus, trace=trace)
    from dptbd.hw.wide import pack_beat
    from dptbd.sim.verilator import beat_words, payload_words

    p = cfg.pixels_per_clock
    flat = np.asarray(frames).reshape(len(frames), -1)
    values = [pack_beat(cfg, frame[i:i + p], i == 0) for frame in flat
              for i in range(0, frame.size, p)]
    return check_stream(sim, beat_words(values, payload_words(sim, "pixels")), stimulus,
                        trace=trace)


def lut_change_words(changes: Sequence[tuple[int, np.ndarray]], words_per_frame: int):
    """``(word index, codes)`` for LUT changes given per frame ``(frame, codes)``."""
    return tuple((int(f) * words_per_frame, np.asarray(c)) for f, c in changes)


def split_beats(cfg: DPConfig, words: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(pixel, first)`` per pixel of ``pixels`` beats at P > 1 pixels per clock (rows of
    uint64 words, :func:`dptbd.sim.verilator.beat_words`): a beat's ``first`` on its pixel 0."""
    from dptbd.hw.wide import wide_pixel_layout
    from dptbd.hw.layouts import unpack

    p = cfg.pixels_per_clock
    pixels, first = [], []
    for value in beat_values(words):
        fields = unpack(wide_pixel_layout(cfg), value)
        pixels += [fields[f"pixel_{k}"] for k in range(p)]
        first += [bool(fields["first"])] + [False] * (p - 1)
    return np.array(pixels, dtype=np.int64), np.array(first, dtype=bool)


def beat_state_words(cfg: DPConfig, words: np.ndarray) -> np.ndarray:
    """The ``states`` payloads of one pixel each (:func:`~dptbd.hw.layouts.state_layout`, as
    a P = 1 design gives them) of ``states`` beats at P > 1 (rows of uint64 words)."""
    from dptbd.hw.wide import unpack_beat_states
    from dptbd.hw.layouts import pack_states

    states = [s for value in beat_values(words) for s in unpack_beat_states(cfg, value)]
    names = ("energy", "direction", "end_of_line", "end_of_frame", "end_of_segment")
    return pack_states(cfg, **{n: np.array([s[n] for s in states], dtype=np.int64)
                               for n in names})
