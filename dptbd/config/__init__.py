"""The one frozen, validated parameter set shared by ``dptbd.model`` and ``dptbd.hw``.

Every width and parameter of the direction-weighted DP of paper 001 (eqs (8)-(11))
lives here. ``docs/arithmetic.md`` defines what each one means bit for bit.

The fields are all in :class:`DPConfig`; what is validated and derived from a group of them
lives beside it in a base class of its own: the weight LUT (:mod:`dptbd.config.lut`), the
segmentation (:mod:`dptbd.config.segmentation`), P pixels per clock
(:mod:`dptbd.config.beats`), paper 000's DP family (:mod:`dptbd.config.family`); the energy
width's warning in :mod:`dptbd.config.energy`, the state store in external memory in
:mod:`dptbd.config.axi_store`.
"""

from __future__ import annotations

import dataclasses
import json
import warnings
from typing import Any, Mapping

from dptbd.config.beats import PIXELS_PER_CLOCK, BeatFields
from dptbd.config.energy import EnergyWidthWarning, non_saturating_energy_bits
from dptbd.config.family import FamilyFields
from dptbd.config.lut import LutFields
from dptbd.config.segmentation import DEFAULT_FALSE_ALARM_RATE, SegmentationFields
from dptbd.errors import ConfigError, check_int

__all__ = [
    "DPConfig",
    "AxiStoreConfig",
    "AXI_DATA_BITS",
    "EnergyWidthWarning",
    "ROUNDING_MODES",
    "DEFAULT_FALSE_ALARM_RATE",
    "PIXELS_PER_CLOCK",
    "non_saturating_energy_bits",
]

#: Rounding modes of the weight multiplier (``docs/arithmetic.md`` §4).
ROUNDING_MODES = ("truncate", "half_up")

_RANGES = {
    "width": (3, 4096),
    "height": (3, 4096),
    "segment_frames": (1, 65535),
    "input_bits": (1, 16),
    "weight_frac_bits": (0, 16),
    "radius": (1, 2),
}


def _check_int(name: str, value: Any, bounds: tuple[int, int] | None = None,
               lo_name: str = "", hi_name: str = "") -> int:
    lo, hi = _RANGES[name] if bounds is None else bounds
    return check_int(name, value, lo, hi, error=ConfigError, lo_name=lo_name, hi_name=hi_name)


@dataclasses.dataclass(frozen=True)
class DPConfig(LutFields, SegmentationFields, BeatFields, FamilyFields):
    """Parameters of the direction-weighted DP, shared by the golden model and the gateware.

    Parameters
    ----------
    width, height : int
        Frame size W x H in pixels, each in [3, 4096].
    segment_frames : int
        K, frames accumulated per segment (paper 001 eq (10)), in [1, 65535]; the gateware's
        reset value of its run-time K (``docs/gateware.md``, "Run-time settings").
    max_segment_frames : int or None
        K_max, the largest run-time K the gateware accepts, in [K, 65535]; ``None`` means K.
        Every width that depends on K (frame counters, the saturation warning,
        :attr:`energy_bits_needed`, the default :attr:`bin_shift`) uses K_max, see
        :attr:`k_max`.
    segment_stride : int or None
        Frames between the starts of consecutive segments, in [1, K]; ``None`` means K
        (non-overlapping segments, the only scheme the gateware implements).
    input_bits : int
        B_in, width of an unsigned input pixel, in [1, 16].
    energy_bits : int
        B_E, width of the unsigned accumulated energy E, in [B_in, 32].
    weight_frac_bits : int
        F, fractional bits of a weight code; a code ``c`` in [0, 2**F] means ``c / 2**F``.
    radius : int
        Search window radius r (1: 3 x 3, paper 001; 2: 5 x 5, paper 000's scenario).
    rounding : str
        How the weighted predecessor ``E * c`` is scaled back by ``2**-F``:
        ``"truncate"`` (floor) or ``"half_up"`` (round half up).
    weights : tuple of tuple of float or None
        The weight LUT, shape ``(M + 1, M)`` with ``M = (2r + 1)**2``, indexed
        ``[predecessor direction, move]``, each in [0, 1]; ``None`` means paper 001
        eq (11) (:func:`~dptbd.weights.paper_weights`).
    candidate_count : int or None
        n, the candidate points wanted per segment (segmentation, ``docs/arithmetic.md``
        §6), in [0, W*H]; ``None`` means 0.2 % of W*H rounded half up (33 for 128 x 128),
        see :attr:`n_candidates`.
    candidate_capacity : int or None
        C, the most candidate records the segmenter emits per segment, in
        [n, W*H]; ``None`` means ``min(2n, W*H)``, see :attr:`record_capacity`.
    histogram_bits : int
        b, the segmentation histogram has 2**b bins, in [1, 16].
    histogram_shift : int or None
        s, a pixel's bin is ``min(E >> s, 2**b - 1)``, in [0, B_E - 1]; ``None`` means the
        smallest shift whose bins cover every reachable E, see :attr:`bin_shift`.
    merit_codes : tuple of int or None
        Paper 000's merit LUT P (``docs/arithmetic.md`` §8.1): ``2**B_in`` signed codes
        indexed by the pixel code; ``None`` is the identity (P = pixel, paper 001).
    merit_bits : int or None
        B_P, width of a two's-complement merit code, in [2, B_E + 1] (identity: [B_in + 1,
        B_E + 1]); ``None`` means the smallest that holds the LUT, see :attr:`merit_width`.
    penalty_codes : tuple of tuple of int or None
        The additive transition penalty Qc (§8.2), ``(M + 1, M)`` unsigned codes indexed
        ``[predecessor direction, move]`` and *subtracted*; ``None`` is all zeros.
    penalty_bits : int or None
        B_Q, width of a penalty code, in [1, B_E]; ``None``: the smallest (>= 1).
    forgetting : float
        The forgetting factor alpha in (0, 1] (§8.4): ``E = P + alpha * max(...)``.
    forgetting_bits : int
        G, fractional bits of alpha's code ``round(alpha * 2**G)`` in [1, 2**G], G in [0, 16].
    recursive : bool
        True: one DP that never resets, a detection map every frame (§8.6); False: K-frame
        segments (§5).
    pixels_per_clock : int
        P, pixels the gateware takes per clock (one input beat), one of
        :data:`PIXELS_PER_CLOCK`; W must be a multiple of P with at least 3 groups of P
        pixels per row (``docs/gateware.md``, "P pixels per clock"). A build parameter: the
        golden model ignores it, every bit is the same at every P.
    """

    width: int = 128
    height: int = 128
    segment_frames: int = 4
    segment_stride: int | None = None
    input_bits: int = 8
    energy_bits: int = 16
    weight_frac_bits: int = 8
    radius: int = 1
    rounding: str = "truncate"
    weights: tuple | None = None
    candidate_count: int | None = None
    candidate_capacity: int | None = None
    histogram_bits: int = 10
    histogram_shift: int | None = None
    # ---- paper 000's DP family (docs/arithmetic.md §8) ---------------------------------
    merit_codes: tuple | None = None
    merit_bits: int | None = None
    penalty_codes: tuple | None = None
    penalty_bits: int | None = None
    forgetting: float = 1.0
    forgetting_bits: int = 8
    recursive: bool = False

    max_segment_frames: int | None = None
    pixels_per_clock: int = 1

    def __post_init__(self) -> None:
        for name in _RANGES:
            object.__setattr__(self, name, _check_int(name, getattr(self, name)))
        object.__setattr__(self, "energy_bits", _check_int(
            "energy_bits", self.energy_bits, (self.input_bits, 32), "input_bits="))
        k = self.segment_frames
        stride = k if self.segment_stride is None else self.segment_stride
        object.__setattr__(self, "segment_stride", _check_int(
            "segment_stride", stride, (1, k), hi_name="segment_frames="))
        if self.max_segment_frames is not None:
            object.__setattr__(self, "max_segment_frames", _check_int(
                "max_segment_frames", self.max_segment_frames, (k, _RANGES["segment_frames"][1]),
                "segment_frames="))
        if self.rounding not in ROUNDING_MODES:
            raise ConfigError(f"rounding must be one of {ROUNDING_MODES}, got {self.rounding!r}")
        self._validate_lut()
        self._validate_segmentation()
        self._validate_family()
        self._validate_pixels_per_clock()
        full_scale = self.k_max * ((1 << self.input_bits) - 1)
        if full_scale > self.e_max:
            k_name = "K" if self.max_segment_frames is None else "K_max"
            warnings.warn(
                f"energy_bits={self.energy_bits} saturates: {k_name}={self.k_max} full-scale "
                f"{self.input_bits}-bit pixels sum to {full_scale} > {self.e_max}; "
                f"energy_bits >= {self.energy_bits_needed} never saturates",
                EnergyWidthWarning, stacklevel=3)

    # ---- derived quantities -------------------------------------------------------
    @property
    def k_max(self) -> int:
        """K_max, the largest run-time segment length: ``max_segment_frames`` or K."""
        return self.segment_frames if self.max_segment_frames is None else self.max_segment_frames

    @property
    def n_moves(self) -> int:
        """M, the number of moves in the search window, ``(2r + 1)**2``."""
        return (2 * self.radius + 1) ** 2

    @property
    def start_code(self) -> int:
        """Direction code of a pixel in its segment's first frame (no arrival move): ``M``."""
        return self.n_moves

    @property
    def direction_bits(self) -> int:
        """Width of the direction field d: enough for codes 0..M."""
        return int(self.n_moves).bit_length()

    @property
    def weight_bits(self) -> int:
        """Width of a weight code: F + 1 bits, so that 1.0 (``2**F``) is representable."""
        return self.weight_frac_bits + 1

    @property
    def e_max(self) -> int:
        """Largest E, ``2**B_E - 1``; the accumulator saturates here."""
        return (1 << self.energy_bits) - 1

    @property
    def pixel_max(self) -> int:
        """Largest input pixel, ``2**B_in - 1``."""
        return (1 << self.input_bits) - 1

    @property
    def energy_bits_needed(self) -> int:
        """The smallest B_E that accumulates K_max full-scale pixels without saturating."""
        return non_saturating_energy_bits(self.input_bits, self.k_max)

    @property
    def energy_reach_bits(self) -> int:
        """B_reach = ``min(B_E, energy_bits_needed)``: the width of the largest E any input
        reaches (K_max full-scale pixels, weights at most 1, clipped at E_max). A build with
        ``B_E > B_reach`` has headroom: E's bits B_reach … B_E - 1 (and those of every value
        bounded by E) never leave 0 when the stored states are the core's own, and
        :meth:`build_config` builds the gateware with ``B_E = B_reach`` (same bits; kept
        above an explicit ``histogram_shift``)."""
        return min(self.energy_bits, self.energy_bits_needed)

    @property
    def state_bits(self) -> int:
        """Width of one stored state (E, d): ``B_E + B_d`` bits per pixel."""
        return self.energy_bits + self.direction_bits

    @property
    def state_slot_bits(self) -> int:
        """Bits one state (E, d) occupies in external memory: the smallest power of two
        >= :attr:`state_bits` and >= 8 (a byte-addressable slot; ``docs/integration.md``,
        "State store in external memory")."""
        return max(8, 1 << (self.state_bits - 1).bit_length())

    def axi_store(self, **fields: Any) -> "AxiStoreConfig":
        """The validated layout of this configuration's state in external memory behind an
        AXI4 manager port (:class:`AxiStoreConfig`; ``fields`` are its parameters)."""
        return AxiStoreConfig(frame=self, **fields)


    def n_segments(self, n_frames: int) -> int:
        """Number of whole segments in a sequence of ``n_frames`` frames."""
        if n_frames < self.segment_frames:
            return 0
        return (n_frames - self.segment_frames) // self.segment_stride + 1

    def describe(self) -> str:
        """The one-line summary every command prints:
        ``"128x128, K=4, B_in=8, B_E=16, F=8, r=1, truncate"`` (``", P=2"`` appended at
        P > 1)."""
        return (f"{self.width}x{self.height}, K={self.segment_frames}, B_in={self.input_bits}, "
                f"B_E={self.energy_bits}, F={self.weight_frac_bits}, r={self.radius}, "
                f"{self.rounding}"
                + (f", P={self.pixels_per_clock}" if self.pixels_per_clock > 1 else ""))

    def replace(self, **changes: Any) -> "DPConfig":
        """A copy with some parameters changed (validated again).

        A stride that was left at its default (= K) follows a new ``segment_frames``.
        """
        if ("segment_frames" in changes and "segment_stride" not in changes
                and self.segment_stride == self.segment_frames):
            changes["segment_stride"] = None
        return dataclasses.replace(self, **changes)


    # ---- gateware build defaults (docs/synthesis.md, "Build defaults") -----------------
    def build_config(self, *, fractional_lut: bool = False) -> "DPConfig":
        """The configuration the gateware is built with by default; it computes the same bits.

        B_E becomes ``min(B_E, energy_bits_needed)`` (no E can exceed K full-scale pixels,
        weights being at most 1), kept above an explicit ``histogram_shift``; F becomes 0
        when the LUT is binary (:attr:`weights_binary`) unless ``fractional_lut`` asks for a
        LUT that can be written with fractional weights at run time. Every state, direction
        and candidate list equals the one ``self`` computes (``docs/synthesis.md``).
        """
        energy = max(self.energy_reach_bits,
                     min(self.energy_bits, (self.histogram_shift or 0) + 1))
        frac = 0 if self.weights_binary and not fractional_lut else self.weight_frac_bits
        if (energy, frac) == (self.energy_bits, self.weight_frac_bits):
            return self
        with warnings.catch_warnings():
            # the built B_E saturates only where self's does, and self has warned of that
            warnings.simplefilter("ignore", EnergyWidthWarning)
            return self.replace(energy_bits=energy, weight_frac_bits=frac)

    def to_mapping(self) -> dict[str, Any]:
        """Every field as plain JSON/TOML values (the weights as nested lists of floats).

        The inverse of :meth:`from_mapping`: ``DPConfig.from_mapping(cfg.to_mapping()) ==
        cfg``. Defaults left as ``None`` stay ``None``, except ``max_segment_frames``, which is
        omitted when ``None`` (so mappings written before run-time K existed stay the same).
        """
        out = {f.name: getattr(self, f.name) for f in dataclasses.fields(self)
               if f.name not in _FAMILY_DEFAULTS or getattr(self, f.name) != _FAMILY_DEFAULTS[f.name]}
        out["weights"] = [list(row) for row in self.weights]
        for name in ("merit_codes", "penalty_codes"):
            if name in out:
                out[name] = json.loads(json.dumps(out[name]))  # nested tuples -> lists
        if self.max_segment_frames is None:     # absent, as before run-time K existed
            del out["max_segment_frames"]
        if self.pixels_per_clock == 1:          # absent, as before P pixels per clock existed
            del out["pixels_per_clock"]
        return out

    @classmethod
    def from_mapping(cls, values: Mapping[str, Any]) -> "DPConfig":
        """Build from a mapping (e.g. a TOML table); unknown keys are refused by name."""
        known = {f.name for f in dataclasses.fields(cls)}
        unknown = sorted(set(values) - known)
        if unknown:
            raise ConfigError(f"unknown parameter(s) {unknown}; allowed: {sorted(known)}")
        return cls(**dict(values))


#: §8 fields and their defaults; :meth:`DPConfig.to_mapping` leaves out a field at its
#: default so that a paper-001 configuration maps (and hashes) exactly as one without the §8 fields.
_FAMILY_DEFAULTS = dict(merit_codes=None, merit_bits=None, penalty_codes=None,
                        penalty_bits=None, forgetting=1.0, forgetting_bits=8, recursive=False)


# the AXI4 state store's parameters use DPConfig (hence imported after it)
from dptbd.config.axi_store import AXI_DATA_BITS, AxiStoreConfig  # noqa: E402
