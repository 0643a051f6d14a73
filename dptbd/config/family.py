"""Paper 000's DP family in the configuration: the validation and the derived quantities of
:class:`~dptbd.config.DPConfig`'s §8 fields (``docs/arithmetic.md`` §8: merit LUT, penalty
LUT, forgetting factor, recursion).

:class:`FamilyFields` is a base class of ``DPConfig`` holding no fields of its own: the
fields stay in the one dataclass (``merit_codes``, ``merit_bits``, ``penalty_codes``,
``penalty_bits``, ``forgetting``, ``forgetting_bits``, ``recursive``), this module holds
what is computed from them, so that ``dptbd/config/__init__.py`` stays the one home of every
parameter without growing past one concept.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from dptbd.errors import ConfigError, check_bool, check_int, check_real, shown

__all__ = ["FamilyFields"]


def _family_int(name: str, value: Any, bounds: tuple[int, int], lo_name: str = "",
                hi_name: str = "") -> int:
    lo, hi = bounds
    return check_int(name, value, lo, hi, error=ConfigError, lo_name=lo_name,
                     hi_name=hi_name)


class FamilyFields:
    """The §8 part of :class:`~dptbd.config.DPConfig` (see the module docstring)."""

    def _validate_family(self) -> None:
        """Check and freeze the §8 fields (merit LUT, penalty LUT, forgetting, recursion)."""
        check_bool("recursive", self.recursive, error=ConfigError)
        object.__setattr__(self, "recursive", bool(self.recursive))
        if self.recursive and self.segment_stride != self.segment_frames:
            raise ConfigError(
                f"segment_stride must be segment_frames={self.segment_frames} when "
                f"recursive=True (one state that never resets), got {self.segment_stride}")
        top = self.energy_bits + 1
        if self.merit_codes is None:
            if self.merit_bits is not None:
                object.__setattr__(self, "merit_bits", _family_int(
                    "merit_bits", self.merit_bits, (self.input_bits + 1, top),
                    "input_bits+1=", "energy_bits+1="))
        else:
            entries = 1 << self.input_bits
            arr = _integer_table("merit_codes", self.merit_codes, (entries,))
            bits = self.merit_bits
            if bits is None:
                bits = max(2, _signed_bits(int(arr.min())), _signed_bits(int(arr.max())))
            bits = _family_int("merit_bits", bits, (2, top), hi_name="energy_bits+1=")
            _check_codes("merit_codes", arr, -(1 << (bits - 1)), (1 << (bits - 1)) - 1,
                         f"merit_bits={bits}")
            object.__setattr__(self, "merit_codes", tuple(int(v) for v in arr))
        if self.penalty_codes is None:
            if self.penalty_bits is not None:
                object.__setattr__(self, "penalty_bits", _family_int(
                    "penalty_bits", self.penalty_bits, (1, self.energy_bits), hi_name="energy_bits="))
        else:
            arr = _integer_table("penalty_codes", self.penalty_codes,
                                 (self.n_moves + 1, self.n_moves))
            bits = self.penalty_bits
            if bits is None:
                bits = max(1, int(max(arr.max(), 0)).bit_length())
            bits = _family_int("penalty_bits", bits, (1, self.energy_bits), hi_name="energy_bits=")
            _check_codes("penalty_codes", arr, 0, (1 << bits) - 1, f"penalty_bits={bits}")
            object.__setattr__(self, "penalty_codes", tuple(tuple(int(v) for v in row) for row in arr))
        object.__setattr__(self, "forgetting_bits", _family_int(
            "forgetting_bits", self.forgetting_bits, (0, 16)))
        alpha = check_real("forgetting", self.forgetting, 0.0, 1.0, lo_open=True,
                           error=ConfigError)
        lowest = 2.0 ** -(self.forgetting_bits + 1)
        if alpha < lowest:
            raise ConfigError(
                f"forgetting must be a finite real number in [{lowest:g}, 1] for forgetting_bits="
                f"{self.forgetting_bits} (its code round(forgetting * 2**{self.forgetting_bits}) "
                f"must be >= 1), got {shown(self.forgetting)}")
        object.__setattr__(self, "forgetting", alpha)

    @property
    def merit_width(self) -> int:
        """B_P, width of a signed merit code: ``merit_bits``, or the smallest that holds the
        LUT (B_in + 1 for the identity LUT)."""
        if self.merit_bits is not None:
            return self.merit_bits
        if self.merit_codes is None:
            return self.input_bits + 1
        return max(2, *(_signed_bits(v) for v in (min(self.merit_codes), max(self.merit_codes))))

    @property
    def merit_code_array(self) -> np.ndarray:
        """The merit LUT, ``int64 (2**B_in,)`` indexed by the pixel code (identity by default)."""
        if self.merit_codes is None:
            return np.arange(1 << self.input_bits, dtype=np.int64)
        return np.array(self.merit_codes, dtype=np.int64)

    @property
    def penalty_width(self) -> int:
        """B_Q, width of an unsigned penalty code: ``penalty_bits`` or the smallest (>= 1)."""
        if self.penalty_bits is not None:
            return self.penalty_bits
        return max(1, int(self.penalty_code_array.max()).bit_length())

    @property
    def penalty_code_array(self) -> np.ndarray:
        """The penalty LUT, ``int64 (M + 1, M)`` indexed ``[predecessor direction, move]``."""
        if self.penalty_codes is None:
            return np.zeros((self.n_moves + 1, self.n_moves), dtype=np.int64)
        return np.array(self.penalty_codes, dtype=np.int64)

    @property
    def forgetting_code(self) -> int:
        """a, the forgetting factor's code: ``floor(alpha * 2**G + 1/2)`` in [1, 2**G]."""
        scaled = self.forgetting * (1 << self.forgetting_bits)
        whole = math.floor(scaled)
        return int(whole + (scaled - whole >= 0.5))

    @property
    def candidate_value_bits(self) -> int:
        """Width of a signed penalised candidate ``C - Qc``: ``max(B_E, B_Q) + 1`` (§8.3)."""
        return max(self.energy_bits, self.penalty_width) + 1

    @property
    def accumulator_sum_bits(self) -> int:
        """Width of the signed sum ``round(alpha V) + P`` before the clamp (§8.5)."""
        return max(self.candidate_value_bits, self.merit_width) + 1

    @property
    def family_fields_in_use(self) -> list[str]:
        """The §8 fields that change the arithmetic: a merit LUT other than the identity, a
        non-zero penalty, alpha's code below 2**G, ``recursive``."""
        used = []
        if self.merit_codes is not None and not np.array_equal(
                self.merit_code_array, np.arange(1 << self.input_bits)):
            used.append("merit_codes")
        if self.penalty_codes is not None and np.any(self.penalty_code_array):
            used.append("penalty_codes")
        if self.forgetting_code != 1 << self.forgetting_bits:
            used.append("forgetting")
        if self.recursive:
            used.append("recursive")
        return used

    @property
    def is_paper001_datapath(self) -> bool:
        """True when no §8 field changes the arithmetic: paper 001's DP bit for bit (§8.8)."""
        return not self.family_fields_in_use

    def require_paper001_datapath(self, where: str) -> None:
        """Refuse a §8 configuration in code that implements only §4–§5 (never ignore it).

        Raises
        ------
        ConfigError
            Naming ``where``, the §8 fields set and the model that implements them.
        """
        fields = self.family_fields_in_use
        if fields:
            raise ConfigError(
                f"{where} implements paper 001's datapath only (docs/arithmetic.md §4-§5), but "
                f"this configuration sets paper 000's family field(s) {', '.join(fields)} "
                f"(§8): use dptbd.model.family.run_family_fixed")


def _signed_bits(value: int) -> int:
    """Width of the smallest two's-complement field holding ``value``."""
    return (value if value >= 0 else ~value).bit_length() + 1


def _integer_table(name: str, table: Any, shape: tuple) -> np.ndarray:
    """``table`` as ``int64`` of ``shape``; refused by name unless every entry is an integer."""
    try:
        arr = np.asarray(table)
    except (TypeError, ValueError) as exc:
        raise ConfigError(f"{name} must be a table of integers, got {type(table).__name__}") from exc
    if arr.shape != shape:
        raise ConfigError(f"{name} must have shape {shape}, got {arr.shape}")
    if arr.dtype == bool or not np.issubdtype(arr.dtype, np.integer):
        raise ConfigError(f"{name} must hold integers, got dtype {arr.dtype}")
    return arr.astype(np.int64)


def _check_codes(name: str, arr: np.ndarray, lo: int, hi: int, width: str) -> None:
    bad = (arr < lo) | (arr > hi)
    if np.any(bad):
        raise ConfigError(f"{name} must be integers in [{lo}, {hi}] for {width}, "
                          f"found {arr[bad].ravel()[:3].tolist()}")
