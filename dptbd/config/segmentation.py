"""The segmentation in the configuration: the validation of the candidate count, the
record capacity and the histogram, and what is derived from them (``docs/arithmetic.md`` §6).

:class:`SegmentationFields` is a base class of :class:`~dptbd.config.DPConfig` holding no
fields of its own (``candidate_count``, ``candidate_capacity``, ``histogram_bits``,
``histogram_shift`` stay in the one dataclass).
"""

from __future__ import annotations

from dptbd.errors import ConfigError, check_int

__all__ = ["SegmentationFields", "DEFAULT_FALSE_ALARM_RATE"]

#: Paper 001's constant false-alarm rate, 0.2 %: the default candidate count per segment is
#: this fraction of W*H, rounded half up (``docs/arithmetic.md`` §6).
DEFAULT_FALSE_ALARM_RATE = 0.002


def _int(name: str, value, bounds: tuple[int, int], lo_name: str = "") -> int:
    return check_int(name, value, *bounds, error=ConfigError, lo_name=lo_name)


class SegmentationFields:
    """The segmentation part of :class:`~dptbd.config.DPConfig` (see the module docstring)."""

    def _validate_segmentation(self) -> None:
        pixels = self.width * self.height
        if self.candidate_count is not None:
            object.__setattr__(self, "candidate_count", _int(
                "candidate_count", self.candidate_count, (0, pixels), ""))
        n = self.n_candidates
        if self.candidate_capacity is not None:
            object.__setattr__(self, "candidate_capacity", _int(
                "candidate_capacity", self.candidate_capacity, (n, pixels), "candidate_count="))
        object.__setattr__(self, "histogram_bits", _int(
            "histogram_bits", self.histogram_bits, (1, 16)))
        if self.histogram_shift is not None:
            object.__setattr__(self, "histogram_shift", _int(
                "histogram_shift", self.histogram_shift, (0, self.energy_bits - 1)))

    @property
    def n_candidates(self) -> int:
        """n, candidate points per segment: ``candidate_count``, or by default 0.2 % of
        W*H rounded half up, ``(W*H + 250) // 500`` exactly (33 for 128 x 128)."""
        if self.candidate_count is not None:
            return self.candidate_count
        return (self.width * self.height + 250) // 500

    @property
    def record_capacity(self) -> int:
        """C, the most records emitted per segment: ``candidate_capacity`` or ``min(2n, W*H)``."""
        if self.candidate_capacity is not None:
            return self.candidate_capacity
        return min(2 * self.n_candidates, self.width * self.height)

    @property
    def n_bins(self) -> int:
        """Bins of the segmentation histogram, ``2**histogram_bits``."""
        return 1 << self.histogram_bits

    @property
    def bin_shift(self) -> int:
        """s, the right shift from E to its histogram bin.

        ``histogram_shift``, or by default ``max(0, B_reach - b)`` with
        ``B_reach = min(B_E, energy_bits_needed)`` the width of the largest reachable E (at
        K_max), so
        that only E_max-adjacent values could share the clamped top bin.
        """
        if self.histogram_shift is not None:
            return self.histogram_shift
        reach = min(self.energy_bits, self.energy_bits_needed)
        return max(0, reach - self.histogram_bits)

    @property
    def bin_count_bits(self) -> int:
        """Width of a histogram counter, ``bitlen(C + 1)``; counters saturate at
        ``2**bits - 1 >= C + 1 >= n + 1`` for every run-time n in [0, C], which never changes
        the threshold (§6)."""
        return (self.record_capacity + 1).bit_length()

    @property
    def threshold_bits(self) -> int:
        """Width of the threshold bin T in 0 … 2**b (2**b: no candidates): b + 1."""
        return self.histogram_bits + 1
