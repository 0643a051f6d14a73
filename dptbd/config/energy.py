"""The width of the accumulated energy: the warning that B_E saturates, and the smallest B_E
that never does (``docs/arithmetic.md``).
"""

from __future__ import annotations

__all__ = ["EnergyWidthWarning", "non_saturating_energy_bits"]


class EnergyWidthWarning(UserWarning):
    """``energy_bits`` is too narrow to accumulate K full-scale frames without saturating."""


def non_saturating_energy_bits(input_bits: int, segment_frames: int) -> int:
    """The smallest B_E that accumulates K full-scale B_in-bit pixels without saturating:
    ``max(B_in, bitlen(K * (2**B_in - 1)))``."""
    return max(input_bits, (segment_frames * ((1 << input_bits) - 1)).bit_length())
