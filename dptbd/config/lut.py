"""The weight LUT in the configuration: its validation, its codes and its address map
(``docs/arithmetic.md`` §4).

:class:`LutFields` is a base class of :class:`~dptbd.config.DPConfig` holding no fields of its
own: the fields stay in the one dataclass (``weights``, ``weight_frac_bits``, ``radius``),
this module holds what is computed from them.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from dptbd.errors import ConfigError
from dptbd.weights import check_move_table, move_offsets, paper_weights

if TYPE_CHECKING:
    from dptbd.config import DPConfig

__all__ = ["LutFields"]


class LutFields:
    """The weight-LUT part of :class:`~dptbd.config.DPConfig` (see the module docstring)."""

    def _validate_lut(self) -> None:
        """Check and freeze ``weights`` (``None``: paper 001 eq (11)) as nested tuples."""
        lut = paper_weights(self.radius) if self.weights is None else self.weights
        arr = check_move_table("weights", lut, self.radius, 0.0, 1.0)
        # hashable and immutable
        object.__setattr__(self, "weights", tuple(tuple(float(v) for v in row) for row in arr))

    @property
    def lut_entries(self) -> int:
        """Entries of the weight LUT, ``(M + 1) * M``."""
        return (self.n_moves + 1) * self.n_moves

    def lut_address(self, predecessor: int, move: int) -> int:
        """Address of the weight LUT entry ``[predecessor direction p, move m]``: ``p * M + m``.

        The one definition of the LUT's address map (``docs/arithmetic.md`` §4), used by the
        gateware's write port, the testbenches and the register map.
        """
        if not 0 <= predecessor <= self.n_moves or not 0 <= move < self.n_moves:
            raise ConfigError(
                f"LUT entry must have predecessor in [0, {self.n_moves}] and move in "
                f"[0, {self.n_moves - 1}], got ({predecessor}, {move})")
        return predecessor * self.n_moves + move

    @property
    def moves(self) -> np.ndarray:
        """``(M, 2)`` array of ``(dy, dx)`` per move index (:func:`move_offsets`)."""
        return move_offsets(self.radius)

    @property
    def weight_array(self) -> np.ndarray:
        """The weight LUT as a ``float64`` array of shape ``(M + 1, M)``."""
        return np.array(self.weights, dtype=np.float64)

    @property
    def weight_codes(self) -> np.ndarray:
        """The LUT quantised to F fractional bits, round half up: ``uint32`` codes in [0, 2**F].

        ``floor(w * 2**F + 1/2)`` evaluated exactly: scaling by a power of two and taking
        the fraction are exact in float64, adding 0.5 is not.
        """
        scaled = self.weight_array * (1 << self.weight_frac_bits)
        whole = np.floor(scaled)
        return (whole + (scaled - whole >= 0.5)).astype(np.uint32)

    @property
    def weights_exact(self) -> bool:
        """True when every weight is exactly representable with F fractional bits."""
        codes = self.weight_codes.astype(np.float64) / (1 << self.weight_frac_bits)
        return bool(np.array_equal(codes, self.weight_array))

    def with_weight_codes(self, codes: Any) -> "DPConfig":
        """A copy whose quantised LUT (:attr:`weight_codes`) is ``codes``.

        Models a LUT written at run time: each code ``c`` in [0, 2**F] becomes the weight
        ``c / 2**F``, which quantises back to exactly ``c``.
        """
        arr = np.asarray(codes, dtype=np.int64)
        unity = 1 << self.weight_frac_bits
        shape = (self.n_moves + 1, self.n_moves)
        if arr.shape != shape:
            raise ConfigError(f"LUT codes must have shape {shape} for radius={self.radius}, "
                              f"got {arr.shape}")
        if arr.min() < 0 or arr.max() > unity:
            raise ConfigError(f"LUT codes must be in [0, 2**F = {unity}], found "
                              f"{arr[(arr < 0) | (arr > unity)][:3].tolist()}")
        out = self.replace(weights=arr.astype(np.float64) / unity)
        assert np.array_equal(out.weight_codes, arr)
        return out

    @property
    def weights_binary(self) -> bool:
        """True when every weight is 0 or 1 (the paper's LUT): exact at any F, even F = 0."""
        return bool(np.isin(self.weight_array, (0.0, 1.0)).all())
