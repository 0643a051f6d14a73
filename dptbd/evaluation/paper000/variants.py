"""Paper 000's DP variants as gateware configurations, and their final maps on either engine.

``docs/arithmetic.md`` §8.9 says how each of 000's variants is a :class:`~dptbd.config.DPConfig`;
this module builds them for 000's scenes (:func:`fixed_variant`) and runs them:

* the **fixed-point** variant on 8-bit ADC codes of the scene, ``code = clip(rint(16 z +
  128), 0, 255)`` (z in noise units, one sigma = 16 LSB, the window [-8, 8) sigma), either
  on the golden model (``engine="model"``: :func:`dptbd.model.family.fast.run_family_fast`)
  or on the compiled gateware (``engine="rtl"``:
  :func:`dptbd.sim.rtl.trials.accumulate_trials`, every state word of every frame checked
  against the golden model); its final E is mapped back to the float scale of h with
  :meth:`FixedVariant.to_float`;
* the **float** variant on the float measurements themselves: the existing float runs of
  ``docs/detectors.md`` §1.4–1.5 (:func:`dptbd.evaluation.detectors.unified.run_unified`,
  ``mode="datapath"``: the same (h, d) state and tie-break as the gateware).

The configurations (:data:`ADC_GAIN`, :data:`ADC_OFFSET`, :data:`LIKELIHOOD_SCALE`):

* eq (15) amplitude DP: identity merit (P = code), no penalty, the all-ones weight LUT
  with F = 0, radius 2: paper 001's datapath (§8.8). E = sum of codes = 16 h + T · 128.
* eq (24): identity merit and the penalty LUT ``round(16 · lg(1 + |v_m - v_p|))`` (eq (22)
  read on velocities, α₂₂ = 1, ``docs/detectors.md`` §1.2), subtracted: E ≈ 16 h + T · 128.
* eqs (19)–(23): merit LUT ``round(256 · S(z(code)))`` (signed), penalty ``round(256 ·
  lg(1 + |v_m - v_p|))``: E ≈ 256 h (clamped at 0 from below, §8.5).

One segment of K = T frames (000's DP over the whole scene), B_E = 16 bits: nothing
saturates at the top (E <= 20 · 256 = 5120 for T = 20).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from dptbd.config import DPConfig
from dptbd.weights import plain_weights
from dptbd.evaluation.detectors import unified
from dptbd.evaluation.detectors._checks import DetectorError, check_int
from dptbd.evaluation.detectors.paper000 import RADIUS, Case
from dptbd.scenes import synthetic as scenes

__all__ = ["ADC_BITS", "ADC_GAIN", "ADC_OFFSET", "LIKELIHOOD_SCALE", "ENERGY_BITS", "ENGINES",
           "FixedVariant", "fixed_variant", "quantise_scene", "float_maps", "fixed_maps"]

ADC_BITS = 8
#: ADC codes per noise sigma, and the code of z = 0 (the window is [-8, 8) sigma).
ADC_GAIN = 16.0
#: The code of z = 0 (see :data:`ADC_GAIN`).
ADC_OFFSET = 128.0
#: Codes per unit of h of the likelihood-difference DP (S(z) <= 1: merits 0 … 256).
LIKELIHOOD_SCALE = 256.0
ENERGY_BITS = 16
ENGINES = ("model", "rtl")


@dataclasses.dataclass(frozen=True)
class FixedVariant:
    """One of 000's variants on the gateware: its configuration and how E maps back to h.

    ``h ≈ (E - T · merit_offset) / scale`` after T frames (exact when the scaled merits and
    penalties are integers and nothing clamps).
    """

    name: str
    cfg: DPConfig
    scale: float
    merit_offset: float

    def to_float(self, energy: np.ndarray, n_frames: int) -> np.ndarray:
        """Final E ``(..., H, W)`` after ``n_frames`` frames on the float scale of h."""
        return (np.asarray(energy, dtype=np.float64) - n_frames * self.merit_offset) / self.scale


def _round_half_up(values: np.ndarray) -> np.ndarray:
    return np.floor(np.asarray(values, dtype=np.float64) + 0.5).astype(np.int64)


def fixed_variant(case: Case, *, size: int = 64, frames: int = 20) -> FixedVariant:
    """The gateware configuration of ``case`` (its merit, penalty and SNR) on 000's scene.

    Parameters
    ----------
    case : paper000.Case
        ``merit`` amplitude or likelihood (the likelihood merit depends on the SNR),
        ``penalty`` with or without eq (22).
    size, frames : int
        Scene size (>= 8) and frames T (2 … 64): one segment of K = T frames.
    """
    size = check_int("size", size, 8, 256)
    frames = check_int("frames", frames, 2, 64)
    if case.merit == "amplitude":
        scale, offset, merit = ADC_GAIN, ADC_OFFSET, None
    else:
        scale, offset = LIKELIHOOD_SCALE, 0.0
        z = (np.arange(1 << ADC_BITS, dtype=np.float64) - ADC_OFFSET) / ADC_GAIN
        merit = tuple(int(v) for v in _round_half_up(scale * case.merit_fn()(z)))
    penalty = None
    if case.penalty:
        penalty = _round_half_up(-scale * case.transition(RADIUS)).tolist()
    cfg = DPConfig(width=size, height=size, segment_frames=frames, input_bits=ADC_BITS,
                   energy_bits=ENERGY_BITS, weight_frac_bits=0, radius=RADIUS,
                   weights=plain_weights(RADIUS), merit_codes=merit, penalty_codes=penalty)
    return FixedVariant(case.label, cfg, scale, offset)


def quantise_scene(frames: np.ndarray) -> np.ndarray:
    """000's float measurements (noise sigma 1) as the variants' 8-bit ADC codes."""
    return scenes.quantise(frames, ADC_BITS, gain=ADC_GAIN, offset=ADC_OFFSET)


def float_maps(case: Case, frames: np.ndarray) -> np.ndarray:
    """The float variant's final h ``(N, H, W)`` on float measurements ``(N, T, H, W)``."""
    return unified.run_unified(frames, case.merit_fn(), case.transition(RADIUS),
                               radius=RADIUS, mode="datapath").value


def fixed_maps(variant: FixedVariant, codes: np.ndarray, engine: str, builds=None,
               label: str = "", first_trial: int = 0):
    """The fixed-point variant's final map on the float scale of h, ``(N, H, W)``, and the
    RTL's :class:`~dptbd.sim.rtl.trials.RTLTally` (None on the model).

    ``engine="rtl"`` runs ``builds`` (:func:`dptbd.sim.rtl.trials.prepare_builds` of
    ``variant.cfg``), checking every state word; a mismatch raises
    :class:`~dptbd.sim.rtl.trials.RTLMismatchError` (``label`` and ``first_trial`` locate it).
    """
    if engine not in ENGINES:
        raise DetectorError(f"engine must be one of {ENGINES}, got {engine!r}")
    n_frames = codes.shape[1]
    if engine == "model":
        from dptbd.model.family.fast import run_family_fast

        energy = run_family_fast(codes, variant.cfg).energy[:, -1]
        return variant.to_float(energy, n_frames), None
    from dptbd.sim.rtl.trials import accumulate_trials

    res = accumulate_trials(variant.cfg if builds is None else builds, codes,
                            first_trial=first_trial, label=label)
    return variant.to_float(res.energy[:, -1], n_frames), res.tally
