"""The small build the formal proofs run on (:func:`tiny_config`)."""

from __future__ import annotations

from dptbd.config import DPConfig

__all__ = ["tiny_config"]


def tiny_config(**overrides) -> DPConfig:
    """The small build the proofs run on: 5 x 4 frames (the smallest the read-ahead of
    r = 1 allows), 1-bit pixels, 4-bit energy, F = 1 (weight codes c / 2), K = 2, one
    candidate (C = 2), a 2-bin histogram."""
    return DPConfig(**{"width": 5, "height": 4, "segment_frames": 2, "input_bits": 1,
                       "energy_bits": 4, "weight_frac_bits": 1, "histogram_bits": 1,
                       "candidate_count": 1, **overrides})
