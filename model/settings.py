"""Run-time settings of the gateware, per segment: K, n and s (``docs/gateware.md``,
"Run-time settings"; ``docs/arithmetic.md`` §5 and §6).

The gateware samples its three run-time inputs once per segment, in the cycle that
segment's first pixel is accepted, and keeps them for the whole segment:

* ``segment_frames`` (K) is the segment's length in frames;
* ``histogram_shift`` (s) bins the segment's scored (last) frame, ``min(E >> s, 2**b - 1)``;
* ``candidate_count`` (n) thresholds the segment's histogram, which makes the *next*
  segment's list (the threshold is one segment stale, §6.1).

A *schedule* is a sequence of :class:`SegmentSettings`, one per segment from reset; the
segments after its end keep its last entry (a register keeps its value). ``None`` means the
build values, :meth:`SegmentSettings.defaults`.
"""

from __future__ import annotations

import dataclasses
from typing import Sequence

from dptbd.config import DPConfig
from dptbd.errors import ConfigError, check_int

__all__ = ["SegmentSettings", "Schedule", "check_schedule", "settings_of_segment",
           "segment_lengths"]


@dataclasses.dataclass(frozen=True)
class SegmentSettings:
    """The run-time settings one segment runs with.

    Attributes
    ----------
    segment_frames : int
        K, frames in the segment, in [1, K_max].
    candidate_count : int
        n, the candidate count its histogram is thresholded for, in [0, C].
    histogram_shift : int
        s, the shift from E to its histogram bin, in [0, B_E - 1].
    """

    segment_frames: int
    candidate_count: int
    histogram_shift: int

    @classmethod
    def defaults(cls, cfg: DPConfig) -> "SegmentSettings":
        """The build values, which the gateware's settings hold after reset."""
        return cls(cfg.segment_frames, cfg.n_candidates, cfg.bin_shift)

    def checked(self, cfg: DPConfig) -> "SegmentSettings":
        """These settings, refused with :class:`~dptbd.errors.ConfigError` when one is out of
        the range the gateware built for ``cfg`` accepts (as the register block refuses it)."""
        return SegmentSettings(
            check_int("segment_frames", self.segment_frames, 1, cfg.k_max, error=ConfigError,
                      hi_name="K_max="),
            check_int("candidate_count", self.candidate_count, 0, cfg.record_capacity,
                      error=ConfigError, hi_name="C="),
            check_int("histogram_shift", self.histogram_shift, 0, cfg.energy_bits - 1,
                      error=ConfigError, hi_name="B_E-1="))


Schedule = Sequence[SegmentSettings]


def check_schedule(cfg: DPConfig, schedule: Schedule | None) -> tuple[SegmentSettings, ...]:
    """``schedule`` checked against ``cfg``; ``None`` is the one-entry schedule of the build
    values. Refused: a schedule with overlapping segments (``segment_stride != K``, which the
    gateware does not implement), an empty schedule, an entry that is not a
    :class:`SegmentSettings`, a setting out of range (:meth:`SegmentSettings.checked`)."""
    if schedule is None:
        return (SegmentSettings.defaults(cfg),)
    if cfg.segment_stride != cfg.segment_frames:
        raise ConfigError(f"a run-time schedule needs non-overlapping segments, but "
                          f"segment_stride={cfg.segment_stride} != segment_frames="
                          f"{cfg.segment_frames}")
    entries = tuple(schedule)
    if not entries:
        raise ConfigError("schedule must hold at least one SegmentSettings, got none")
    for index, entry in enumerate(entries):
        if not isinstance(entry, SegmentSettings):
            raise ConfigError(f"schedule[{index}] must be a SegmentSettings, got "
                              f"{type(entry).__name__}")
    return tuple(entry.checked(cfg) for entry in entries)


def settings_of_segment(schedule: Sequence[SegmentSettings], index: int) -> SegmentSettings:
    """The settings of segment ``index`` (from reset): its entry, or the last one."""
    return schedule[min(index, len(schedule) - 1)]


def segment_lengths(schedule: Sequence[SegmentSettings], n_frames: int) -> list[int]:
    """K of each whole segment in a sequence of ``n_frames`` frames: consecutive segments,
    each as long as its schedule entry says; a trailing partial segment is not counted."""
    out, used = [], 0
    while True:
        k = settings_of_segment(schedule, len(out)).segment_frames
        if used + k > n_frames:
            return out
        out.append(k)
        used += k
