"""P pixels per clock in the configuration: the validation of ``pixels_per_clock`` and the
configuration counted in beats of P pixels (``docs/gateware.md``, "P pixels per clock").

:class:`BeatFields` is a base class of :class:`~dptbd.config.DPConfig` holding no fields of
its own (the field ``pixels_per_clock`` stays in the one dataclass).
"""

from __future__ import annotations

import warnings
from typing import TYPE_CHECKING

import numpy as np

from dptbd.config.energy import EnergyWidthWarning
from dptbd.errors import ConfigError

if TYPE_CHECKING:
    from dptbd.config import DPConfig

__all__ = ["BeatFields", "PIXELS_PER_CLOCK"]

#: ``DPConfig.pixels_per_clock``: the gateware's pixels per clock (and per input beat).
PIXELS_PER_CLOCK = (1, 2, 4)


class BeatFields:
    """The pixels-per-clock part of :class:`~dptbd.config.DPConfig` (see the module
    docstring)."""

    def _validate_pixels_per_clock(self) -> None:
        p = self.pixels_per_clock
        if isinstance(p, bool) or not isinstance(p, (int, np.integer)) or p not in PIXELS_PER_CLOCK:
            raise ConfigError(f"pixels_per_clock must be one of {PIXELS_PER_CLOCK}, got {p!r}")
        object.__setattr__(self, "pixels_per_clock", int(p))
        if self.width % p:
            raise ConfigError(f"width={self.width} is not a multiple of pixels_per_clock={p}: "
                              f"a beat of P pixels never straddles two rows")
        if self.width < 3 * p:
            raise ConfigError(f"width={self.width} is less than 3 * pixels_per_clock = {3 * p}: "
                              f"a row needs at least 3 beats of P pixels")

    @property
    def row_beats(self) -> int:
        """Beats (groups of P pixels, one per clock at full rate) per row: ``W / P``."""
        return self.width // self.pixels_per_clock

    @property
    def frame_beats(self) -> int:
        """Beats per frame, ``W * H / P``: the cycles of a frame at full rate."""
        return self.row_beats * self.height

    def beat_config(self) -> "DPConfig":
        """The configuration in units of beats: W / P columns of one "pixel" each, every
        other parameter the same (its default candidate count and capacity, which only the
        segmenter uses). The gateware's frame controller and read-ahead count beats with
        it; ``self`` at P = 1."""
        if self.pixels_per_clock == 1:
            return self
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", EnergyWidthWarning)
            return self.replace(width=self.row_beats, pixels_per_clock=1,
                                candidate_count=None, candidate_capacity=None)
