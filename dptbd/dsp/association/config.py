"""Parameters of the DSP track association (:class:`AssociationConfig`) and its error class.

The parameters are given in pixels and ratios and checked here; the tracker
(:class:`dptbd.dsp.association.Tracker`) quantises them once to integer codes.
``docs/association.md`` lists and motivates them. Both names are importable from
:mod:`dptbd.dsp.association` too.
"""

from __future__ import annotations

import dataclasses
from typing import Any, Mapping

from dptbd.dsp.errors import AssociationError
from dptbd.errors import check_bool, check_int, check_real

__all__ = ["AssociationConfig", "AssociationError"]


@dataclasses.dataclass(frozen=True)
class AssociationConfig:
    """Parameters of the association, in pixels and ratios; quantised once to codes.

    Capacities
        ``capacity`` track records; ``max_candidates`` input records per segment: the
        DSP's receive buffer, which must hold the gateware segmenter's whole list (at most
        its capacity C; the job checks C <= this) before
        :func:`~dptbd.dsp.records.trim_to_count` cuts it to n; ``max_points`` history points
        per record (a ring: a longer track keeps its newest points); ``output_capacity``
        finished confirmed tracks kept for the output.
    Gates (pixels)
        ``seed_gate`` for tentative tracks; ``gate_base``, ``gate_growth`` per segment of
        length x detection ratio (up to ``gate_growth_segments`` segments) for tracks in
        the prediction space; ``gate_miss`` added per consecutive miss; ``gate_max``
        (``None``: ``max_speed * segment_stride + 1``, one segment's largest move).
    Motion
        ``max_speed`` (pixels/frame, 001: 1); ``manoeuvre``: two step velocities differing
        by more than this (pixels per segment, Chebyshev) mean a manoeuvre.
        ``link_gate``: a track in the prediction space detected in the previous segment
        also accepts a candidate outside its gate whose backtracked DP path starts within
        this distance (pixels) of the track's newest point — the DP followed the target
        through a turn the linear prediction could not foresee (0: off; back-to-back
        segments only).
    Score
        ``heading_weight``: cost of a fully reversed heading relative to a candidate at the
        gate's edge; ``reject_reversed``: never match a candidate whose heading points
        backwards (001 §2: "目标的运动是不后退的"); ``heading_min``: headings and velocities
        shorter than this (pixels per segment) have no direction and cost nothing.
    Thresholds (001 §3 (3): output > predict > delete)
        Output (confirm): ``counted >= confirm_hits`` and ``ratio >= confirm_ratio``.
        ``confirm_disjoint``: count toward ``confirm_hits`` only a hit whose list shares no
        frame with the list of the previous counted hit (overlapping segments,
        ``segment_stride < segment_frames``: one noise peak lies in consecutive lists and
        would count twice); false: every hit counts (``counted == hits``).
        Predict (prediction space): ``hits >= predict_hits`` and ``ratio >= predict_ratio``.
        Delete: ``ratio < delete_ratio`` or ``misses > max_misses``.
        ``ratio = hits / length``.
    Clusters and duplicates
        ``merge_radius``: Chebyshev radius of cluster suppression (0: off).
        ``duplicate_radius``: two tracks that both matched in a segment, with newest
        points within this Chebyshev distance and velocities within ``manoeuvre`` of each
        other, follow the same object: the weaker one is deleted (0: off).
    Wake
        ``wake_radius``: a candidate left over after matching within this Chebyshev
        distance (pixels) of a live track's recent path — the newest ``wake_points`` points
        of its history and, where backtracked, their paths' starts — starts no track (0:
        off). The recursive DP's energy stays on the pixels a target has just left
        (``docs/detection_results.md`` §6.2); K-frame segments hardly need it.
    """

    capacity: int = 64
    max_candidates: int = 128
    max_points: int = 64
    output_capacity: int = 64
    max_speed: float = 1.0
    merge_radius: int = 1
    duplicate_radius: int = 2
    wake_radius: int = 0
    wake_points: int = 2
    seed_gate: float = 3.0
    gate_base: float = 2.5
    gate_growth: float = 0.25
    gate_growth_segments: int = 8
    gate_miss: float = 1.0
    gate_max: float | None = None
    manoeuvre: float = 3.0
    link_gate: float = 0.0
    heading_weight: float = 1.0
    reject_reversed: bool = False
    heading_min: float = 1.0
    confirm_hits: int = 4
    confirm_ratio: float = 0.6
    confirm_disjoint: bool = False
    predict_hits: int = 2
    predict_ratio: float = 0.5
    delete_ratio: float = 0.4
    max_misses: int = 3

    def __post_init__(self) -> None:
        ints = {"capacity": (1, 65535), "max_candidates": (1, 65535), "max_points": (1, 65535),
                "output_capacity": (0, 65535), "merge_radius": (0, 16),
                "duplicate_radius": (0, 1000), "wake_radius": (0, 16),
                "wake_points": (1, 65535),
                "gate_growth_segments": (0, 1000), "confirm_hits": (1, 65535),
                "predict_hits": (1, 65535), "max_misses": (0, 255)}
        for name, (lo, hi) in ints.items():
            object.__setattr__(self, name, check_int(f"association {name}", getattr(self, name),
                                                     lo, hi, error=AssociationError))
        reals = {"max_speed": (0.0, 64.0), "seed_gate": (0.0, 1000.0),
                 "gate_base": (0.0, 1000.0), "gate_growth": (0.0, 100.0),
                 "gate_miss": (0.0, 1000.0), "manoeuvre": (0.0, 1000.0),
                 "heading_weight": (0.0, 100.0), "link_gate": (0.0, 1000.0), "heading_min": (0.0, 1000.0),
                 "confirm_ratio": (0.0, 1.0), "predict_ratio": (0.0, 1.0),
                 "delete_ratio": (0.0, 1.0), "gate_max": (0.0, 1000.0)}
        for name, (lo, hi) in reals.items():
            v = getattr(self, name)
            if name == "gate_max" and v is None:
                continue
            object.__setattr__(self, name, check_real(f"association {name}", v, lo, hi,
                                                      error=AssociationError))
        for name in ("reject_reversed", "confirm_disjoint"):
            object.__setattr__(self, name, check_bool(f"association {name}", getattr(self, name),
                                                      error=AssociationError))
        if not self.confirm_ratio >= self.predict_ratio >= self.delete_ratio:
            raise AssociationError(
                "association thresholds must be ordered as 001 §3 says (output > predict > "
                f"delete): confirm_ratio={self.confirm_ratio} >= predict_ratio="
                f"{self.predict_ratio} >= delete_ratio={self.delete_ratio}")
        if not self.confirm_hits >= self.predict_hits:
            raise AssociationError(
                f"association confirm_hits={self.confirm_hits} must be >= predict_hits="
                f"{self.predict_hits} (output threshold above predict threshold)")

    @classmethod
    def from_mapping(cls, values: Mapping[str, Any]) -> "AssociationConfig":
        """Build from a mapping (a TOML table); unknown keys are refused by name."""
        known = [f.name for f in dataclasses.fields(cls)]
        unknown = sorted(set(values) - set(known))
        if unknown:
            raise AssociationError(f"unknown association parameter(s) {unknown}; allowed: {known}")
        return cls(**dict(values))

    def replace(self, **changes: Any) -> "AssociationConfig":
        return dataclasses.replace(self, **changes)
