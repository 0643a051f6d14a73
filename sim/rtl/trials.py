"""Accumulate a batch of Monte Carlo trials on the compiled RTL, checked against the golden model.

``dptbd compare --rtl`` and ``dptbd table1 --rtl`` (``docs/compare.md``, ``docs/table1.md``,
"RTL in the loop") run the fixed-point detectors' trials through the gateware instead of the
golden model. :func:`accumulate_trials` is the one call they make instead of
:func:`dptbd.model.fast.run_fixed_fast`, with the same result layout
(:class:`~dptbd.model.segments.SegmentOutput`-like ``(trials, S, H, W)`` E and d):

1. The first ``S * K`` frames of every trial (its whole segments; with ``segment_stride ==
   K``, the only scheme the gateware implements, the frames after the last whole segment
   belong to no segment) are packed (:func:`dptbd.sim.stimulus.pixel_words`) and streamed
   **back to back in one** :func:`dptbd.sim.verilator.run` of ``DPPipeline``
   (``design="dp"``). A trial is a whole number of segments, so every trial's first frame
   is a segment's first frame for the gateware's counters: no reset between trials.
2. **Every** ``states`` word is compared with the golden model by
   :class:`dptbd.sim.scoreboard.Scoreboard` (the project's one state-word comparer). The
   expected words are the golden model's state after every frame; they are computed
   frame by frame with the family kernel :mod:`dptbd.model.family.fast` (bit-identical with
   the reference :mod:`dptbd.model.family`, and with :mod:`dptbd.model.fixed` for paper
   001's configurations, ``docs/arithmetic.md`` §8.8) and packed with
   :func:`dptbd.hw.layouts.pack_states` (:func:`expected_state_words`). A mismatch raises :class:`RTLMismatchError`
   naming the configuration, the scene, the trial, the segment, the frame, the row, the
   column and the field.
3. E and d of the last frame of every segment are unpacked from the RTL's own words
   (field offsets of :func:`dptbd.hw.layouts.state_layout`): that is what the caller's
   candidate selection and evaluation see.
4. Unless ``segmenter=False``, the whole FPGA stage (``design="segmenter"``, DP + segmenter,
   top ``dptbd_seg``) runs on the same words and every candidate list is compared with the
   model's (:func:`dptbd.model.segmentation.segment_sequence` of the segments' images from
   reset, :class:`dptbd.sim.candidate_scoreboard.CandidateScoreboard`). The segmenter's
   parameters (n, C, histogram) are the configuration's :class:`~dptbd.config.DPConfig`
   defaults; a configuration whose segmenter cannot be built is reported
   (:func:`prepare_builds`), not failed.

Configurations the gateware does not implement are refused up front
(:func:`check_configs`, :func:`dptbd.hw.schedule.check_supported`).
"""

from __future__ import annotations

import dataclasses
import time
import warnings
from typing import Iterable, Sequence

import numpy as np

from dptbd.config import DPConfig, EnergyWidthWarning
from dptbd.errors import ConfigError

__all__ = [
    "RTLMismatchError",
    "RTLTally",
    "RTLBuilds",
    "RTLTrials",
    "check_configs",
    "prepare_builds",
    "expected_state_words",
    "accumulate_trials",
    "summary",
    "summary_line",
]


class RTLMismatchError(RuntimeError):
    """An RTL output word differs from the golden model (or words are missing / extra)."""


@dataclasses.dataclass(frozen=True)
class RTLTally:
    """What went through the RTL and was compared (sums over runs)."""

    pixel_updates: int = 0         # input words accepted by DPPipeline
    state_words: int = 0           # ``states`` words compared bit for bit
    segmenter_pixels: int = 0      # input words accepted by the DP + segmenter top
    lists: int = 0                 # candidate lists compared
    list_words: int = 0            # ``candidates`` words compared (records + trailers)
    records: int = 0               # candidate records among them
    runs: int = 0                  # executable runs
    cycles: int = 0                # cycles simulated (both designs)
    sim_seconds: float = 0.0       # the harness's cycle loops
    wall_seconds: float = 0.0      # accumulate_trials, checks included

    def __add__(self, other: "RTLTally") -> "RTLTally":
        return RTLTally(*(a + b for a, b in zip(dataclasses.astuple(self),
                                                dataclasses.astuple(other))))

    def to_dict(self) -> dict:
        return dataclasses.asdict(self)


@dataclasses.dataclass(frozen=True)
class RTLBuilds:
    """The compiled executables of one configuration (picklable: paths and a manifest)."""

    dp: object                      # dptbd.sim.verilator.VerilatorBuild
    segmenter: object | None        # the DP + segmenter top, or None …
    segmenter_missing: str | None   # … and why it could not be built


@dataclasses.dataclass(frozen=True)
class RTLTrials:
    """:func:`accumulate_trials`' result: the RTL's accumulated images and what was checked."""

    energy: np.ndarray      # (trials, S, H, W) uint32, from the RTL's words
    direction: np.ndarray   # (trials, S, H, W) uint8
    end_frames: np.ndarray  # (S,) last frame of each segment
    tally: RTLTally


def check_configs(named: Iterable[tuple[str, DPConfig]]) -> None:
    """Refuse, before any work, a configuration the gateware does not implement.

    Raises
    ------
    dptbd.errors.ConfigError
        ``RTL in the loop: configuration '<name>' cannot run on the gateware: <why>``
        (:func:`dptbd.hw.schedule.check_supported`: ``segment_stride != segment_frames``,
        frames too small for the read-ahead).
    """
    from dptbd.hw.schedule import check_supported

    for name, cfg in named:
        try:
            check_supported(cfg)
        except ConfigError as exc:
            raise ConfigError(f"RTL in the loop: configuration {name!r} cannot run on the "
                              f"gateware: {exc}") from None


def prepare_builds(cfg: DPConfig, *, segmenter: bool = True) -> RTLBuilds:
    """Build (or take from the cache) ``cfg``'s DPPipeline and DP + segmenter executables.

    A segmenter that cannot be generated or compiled for ``cfg`` is recorded in
    ``segmenter_missing`` (the DP-only check still runs); the DP must build.
    """
    from dptbd.sim import verilator

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        dp = verilator.build(cfg, "dp")
        seg, missing = None, None
        if not segmenter:
            missing = "not requested"
        else:
            try:
                seg = verilator.build(cfg, "segmenter")
            except (ConfigError, ValueError, RuntimeError) as exc:
                missing = f"{type(exc).__name__}: {str(exc).strip().splitlines()[0][:300]}"
    return RTLBuilds(dp, seg, missing)


def _segments_view(cfg: DPConfig, frames: np.ndarray) -> tuple[np.ndarray, int]:
    """``(trials * S, K, H, W)`` whole segments of ``frames`` ``(trials, T, H, W)``, and S."""
    n_trials, n_frames = frames.shape[:2]
    k = cfg.segment_frames
    n_seg = cfg.n_segments(n_frames)
    used = np.ascontiguousarray(frames[:, :n_seg * k])
    return used.reshape(n_trials * n_seg, k, cfg.height, cfg.width), n_seg


def expected_state_words(cfg: DPConfig, segments: np.ndarray) -> np.ndarray:
    """The golden model's ``states`` words for whole segments ``(N, K, H, W)`` streamed back
    to back from reset: ``(N * K * H * W,)`` uint64 in stream order.

    State after frame j of a segment: the family kernel
    :func:`~dptbd.model.family.fast.fast_family_start` on the segment's first frame, then
    :func:`~dptbd.model.family.fast.fast_family_step` frame by frame (bit-identical with the
    reference :mod:`dptbd.model.family`, ``tests/model/family/test_fast.py``, which with the
    §8 fields at their defaults is :mod:`dptbd.model.fixed` bit for bit, ``docs/arithmetic.md``
    §8.8; ``tests/sim/rtl/test_trials.py`` checks it against
    :func:`dptbd.sim.scoreboard.model_frames`). Paper 001's configurations and paper 000's
    family (§8) go through the same code; flags by
    :func:`dptbd.sim.scoreboard.pack_frame_states`.
    """
    from dptbd.model.family.fast import fast_family_start, fast_family_step
    from dptbd.sim.scoreboard import pack_frame_states

    n, k, h, w = segments.shape
    energy = np.empty((n, k, h, w), np.int64)
    direction = np.empty((n, k, h, w), np.int64)
    e, d = fast_family_start(segments[:, 0], cfg)
    energy[:, 0], direction[:, 0] = e, d
    for j in range(1, k):
        e, d = fast_family_step(e, d, segments[:, j], cfg)
        energy[:, j], direction[:, j] = e, d
    return pack_frame_states(cfg, energy.reshape(n * k, h, w),
                             direction.reshape(n * k, h, w)).reshape(-1)


def _where(label: str, first_trial: int, n_seg: int, k: int, frame: int) -> str:
    trial, rest = divmod(frame, n_seg * k)
    segment, f = divmod(rest, k)
    return (f"{label}trial {first_trial + trial}, segment {segment}, frame {f} of the segment "
            f"(frame {segment * k + f} of the trial)")


#: Words of expected stream materialised at once (the check walks the run in slices of
#: whole segments, so a 128 x 128 chunk does not hold every frame's model state at once).
SLICE_WORDS = 1 << 21


def _check_states(cfg, segments, raw, label, first_trial, n_seg) -> int:
    """Every output word of ``raw`` against the model, slice by slice; the count compared."""
    from dptbd.sim.scoreboard import Scoreboard

    k = cfg.segment_frames
    n_words = segments.size
    n_in = int(np.count_nonzero(raw.accept_cycles != np.uint64(2**64 - 1)))
    if raw.status != "done" or n_in != n_words:
        raise RTLMismatchError(
            f"{label}RTL run incomplete: status {raw.status}, {n_in} of {n_words} input "
            f"words accepted, {len(raw.out_words)} output words")
    seg_words = segments[0].size
    step = max(1, SLICE_WORDS // seg_words)
    compared = 0
    for s0 in range(0, len(segments), step):
        part = segments[s0:s0 + step]
        board = Scoreboard(cfg, expected_state_words(cfg, part))
        board.receive_array(raw.out_words[s0 * seg_words:s0 * seg_words + part.size])
        if board.mismatch is not None:
            m = board.mismatch
            field = m.fields[0]
            raise RTLMismatchError(
                f"RTL states differ from the golden model: "
                f"{_where(label, first_trial, n_seg, k, s0 * k + m.frame)}, row {m.row}, "
                f"col {m.col}, field {field}: expected {m.expected[field]}, got "
                f"{m.got[field]} (output word {s0 * seg_words + m.index} of the run; "
                f"differing fields {list(m.fields)})")
        if not board.done:
            raise RTLMismatchError(
                f"{label}RTL states: {compared + board.count} of {n_words} words came out "
                f"(all bit-exact), the run ended before "
                f"{_where('', first_trial, n_seg, k, s0 * k + board.count // (cfg.width * cfg.height))}")
        compared += board.count
    if len(raw.out_words) > n_words:
        raise RTLMismatchError(f"{label}RTL states: {len(raw.out_words) - n_words} output "
                               f"word(s) beyond the {n_words} expected")
    return compared


def _unpack_ends(cfg: DPConfig, out_words: np.ndarray, n_trials: int, n_seg: int):
    """E and d of the last frame of every segment, from the RTL's words."""
    from dptbd.model.fixed import DIRECTION_DTYPE, ENERGY_DTYPE
    from dptbd.hw.layouts import state_layout, unpack_array

    k, h, w = cfg.segment_frames, cfg.height, cfg.width
    last = unpack_array(state_layout(cfg), out_words.reshape(n_trials, n_seg, k, h, w)[:, :, -1])
    return last["energy"].astype(ENERGY_DTYPE), last["direction"].astype(DIRECTION_DTYPE)


def _check_lists(cfg, seg_build, words, energy, direction, label, first_trial, n_seg, tally):
    from dptbd.model.segmentation import segment_sequence
    from dptbd.sim import verilator
    from dptbd.sim.candidate_scoreboard import CandidateScoreboard

    lists = segment_sequence(energy.reshape(-1, cfg.height, cfg.width).astype(np.int64),
                             direction.reshape(-1, cfg.height, cfg.width).astype(np.int64), cfg)
    board = CandidateScoreboard(cfg, lists)
    raw = verilator.run(seg_build, words)
    n_in = int(np.count_nonzero(raw.accept_cycles != np.uint64(2**64 - 1)))
    board.receive_array(raw.out_words)
    if board.mismatch is not None:
        m = board.mismatch
        trial, segment = divmod(m.segment, n_seg)
        where = (f"record {m.position}" if m.expected_kind == "record"
                 else f"trailer (after {m.position} records)")
        what = ("kind" if m.fields == ("kind",) else m.fields[0])
        detail = (f"expected a {m.expected_kind}, got a {m.got_kind}" if what == "kind"
                  else f"expected {m.expected[what]}, got {m.got[what]}")
        raise RTLMismatchError(
            f"RTL candidate list differs from the golden model: {label}trial "
            f"{first_trial + trial}, segment {segment}, {where}, field {what}: {detail} "
            f"(output word {m.index} of the run)")
    if raw.status != "done" or n_in != len(words) or not board.done:
        raise RTLMismatchError(f"{label}RTL candidate lists: status {raw.status}, {n_in} of "
                               f"{len(words)} input words accepted; {board.report()}")
    return tally + RTLTally(segmenter_pixels=n_in, lists=len(lists), list_words=board.count,
                            records=board.records_expected, runs=1, cycles=raw.cycles,
                            sim_seconds=raw.sim_seconds)


def accumulate_trials(builds: RTLBuilds | DPConfig, frames: np.ndarray, *,
                      first_trial: int = 0, label: str = "") -> RTLTrials:
    """Accumulate ``frames`` ``(trials, T, H, W)`` (integer ADC codes) on the compiled RTL.

    Parameters
    ----------
    builds : RTLBuilds or DPConfig
        :func:`prepare_builds`' executables (a :class:`~dptbd.config.DPConfig` builds them,
        from the cache when it can).
    frames : numpy.ndarray
        ``(trials, T, H, W)`` pixels in ``[0, 2**B_in)``, ``T >= K``.
    first_trial : int
        Index of the first trial, for the error messages.
    label : str
        Prefix of the error messages (e.g. ``"configuration '8/16/8', SNR 2.1: "``).

    Returns
    -------
    RTLTrials
        E and d after every segment's last frame, from the RTL; what was compared.

    Raises
    ------
    RTLMismatchError
        The first state word (or candidate word) that differs from the golden model, by
        trial, segment, frame, row, column and field.
    """
    from dptbd.sim import verilator
    from dptbd.sim.stimulus import pixel_words

    start = time.perf_counter()
    if isinstance(builds, DPConfig):
        check_configs([("(given)", builds)])
        builds = prepare_builds(builds)
    cfg: DPConfig = builds.dp.cfg
    frames = np.asarray(frames)
    if frames.ndim != 4 or frames.shape[2:] != (cfg.height, cfg.width):
        raise ValueError(f"frames must have shape (trials, T, {cfg.height}, {cfg.width}), "
                         f"got {frames.shape}")
    if frames.shape[1] < cfg.segment_frames:
        raise ValueError(f"a trial of {frames.shape[1]} frames is shorter than one segment "
                         f"(segment_frames={cfg.segment_frames})")
    if frames.size and (frames.dtype.kind not in "iu" or int(frames.min()) < 0
                        or int(frames.max()) > cfg.pixel_max):
        raise ValueError(f"pixels must be integers in [0, {cfg.pixel_max}] "
                         f"(input_bits={cfg.input_bits})")
    n_trials = frames.shape[0]
    segments, n_seg = _segments_view(cfg, frames)
    words = pixel_words(cfg, segments.reshape(-1, cfg.height, cfg.width))
    raw = verilator.run(builds.dp, words)
    compared = _check_states(cfg, segments, raw, label, first_trial, n_seg)
    energy, direction = _unpack_ends(cfg, raw.out_words, n_trials, n_seg)
    tally = RTLTally(pixel_updates=len(words), state_words=compared, runs=1, cycles=raw.cycles,
                     sim_seconds=raw.sim_seconds)
    if builds.segmenter is not None:
        tally = _check_lists(cfg, builds.segmenter, words, energy, direction, label,
                             first_trial, n_seg, tally)
    ends = np.arange(n_seg, dtype=np.int64) * cfg.segment_frames + cfg.segment_frames - 1
    tally = dataclasses.replace(tally, wall_seconds=time.perf_counter() - start)
    return RTLTrials(energy, direction, ends, tally)


def summary(tally: RTLTally, segmenters: Sequence[tuple[str, str | None]]) -> dict:
    """The RTL part of a run's summary: counts and the verdict (every check passed, since
    a mismatch raises). ``segmenters``: (configuration, reason its segmenter did not run
    or None)."""
    checked = [n for n, why in segmenters if why is None]
    skipped = {n: why for n, why in segmenters if why is not None}
    verdict = (f"every state word ({tally.state_words} compared) equals the golden model's"
               + (f"; every candidate list ({tally.lists} lists, {tally.list_words} words) "
                  f"equals the model's" if checked else "; no candidate list checked"))
    return dict(tally.to_dict(), segmenter_checked=checked, segmenter_skipped=skipped,
                verdict=verdict)


def summary_line(info: dict) -> str:
    """One printed paragraph of :func:`summary`."""
    line = (f"RTL in the loop: {info['pixel_updates']:,} pixel updates through DPPipeline "
            f"({info['runs']} runs, {info['cycles']:,} cycles, {info['sim_seconds']:.1f} s "
            f"simulated); {info['verdict']}")
    if info["segmenter_checked"]:
        line += f" (DP + segmenter: {info['segmenter_pixels']:,} pixel updates)"
    for name, why in info["segmenter_skipped"].items():
        line += f"; segmenter not run for {name!r}: {why}"
    return line + "."
