"""Equal false-alarm rate per pixel: a threshold calibrated on noise-only scenes, and the ROC figure.

The second operating point of every detection-map comparison (``docs/detectors.md`` §7),
beside a fixed list length: a detector's maps are thresholded at the level that noise-only
maps exceed on a stated fraction ``pfa`` of their pixels.

* :func:`check_pfa` — a false-alarm probability per pixel in (0, 1);
* :func:`pixel_threshold` — the threshold of a given set of noise-only map values: with
  N pixel values and n = floor(pfa * N), the (n+1)-th largest; a pixel is a false alarm
  when *strictly* above it, so at most n of the N are (fewer when values tie at the
  threshold; the rule of ``docs/arithmetic.md`` §6);
* :func:`calibrate_pixel_threshold` — the same on the maps a detector makes of noise-only
  scenes named by their seeds (seeded, reproducible: the same seeds give the same
  threshold), with the measured exceedance count (:class:`Calibration`);
* :func:`figure_roc` — the ROC figure: Pd against Pfa per pixel, one line per detector.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any, Callable, Iterable

import numpy as np

from dptbd.errors import DptbdError, check_int, check_prob

__all__ = ["PfaError", "check_pfa", "parse_pfas", "allowed_false_alarms", "pixel_threshold",
           "Calibration", "check_noise_seeds", "calibrate_pixel_threshold", "figure_roc"]


class PfaError(DptbdError):
    """A false-alarm probability or its calibration set is invalid; the message names it."""


def check_pfa(value: Any, name: str = "pfa (false-alarm probability per pixel)") -> float:
    """A false-alarm probability per pixel in the open interval (0, 1), as ``float``."""
    return check_prob(name, value, error=PfaError)


def parse_pfas(text: Any) -> tuple[float, ...]:
    """``"1e-3,1e-4"`` (or a sequence of numbers) -> checked Pfa values, in the given order."""
    if isinstance(text, str):
        parts = [p.strip() for p in text.split(",") if p.strip()]
        values = []
        for p in parts:
            try:
                values.append(float(p))
            except ValueError:
                raise PfaError(f"pfa must be comma-separated numbers in (0, 1), got {text!r}") from None
    else:
        values = list(text)
    if not values:
        raise PfaError("pfa must hold at least one false-alarm probability in (0, 1)")
    return tuple(check_pfa(v) for v in values)


def _needed(pfa: float) -> int:
    """Noise-only pixels needed for ``pfa``: at least one allowed exceedance, floor(pfa N) >= 1."""
    return math.ceil(1.0 / pfa - 1e-9)


def pixel_threshold(values: Any, pfa: float) -> float:
    """The threshold that at most ``pfa`` of the noise-only pixel ``values`` exceed.

    With N finite values and n = floor(pfa * N), the (n+1)-th largest value; a pixel is a
    false alarm when strictly above it.

    Raises
    ------
    PfaError
        ``pfa`` outside (0, 1), or fewer than ceil(1 / pfa) values (n would be 0: the rate
        cannot be resolved).
    """
    pfa = check_pfa(pfa)
    v = np.asarray(values, dtype=np.float64).ravel()
    v = v[np.isfinite(v)]
    k = v.size - allowed_false_alarms(pfa, v.size) - 1
    return float(np.partition(v, k)[k])


def allowed_false_alarms(pfa: float, pixels: int) -> int:
    """n = floor(pfa * pixels): the false alarms ``pixels`` noise-only pixels allow at
    ``pfa``; refused when 0 (the rate cannot be resolved)."""
    pfa = check_pfa(pfa)
    n = int(math.floor(pfa * pixels))
    if n < 1:
        raise PfaError(f"pfa={pfa:g} needs at least {_needed(pfa)} noise-only pixels, got {pixels}; "
                       f"add noise-only scenes or raise pfa")
    return n


def _sorted_threshold(values: np.ndarray, pfa: float) -> tuple[float, int]:
    """:func:`pixel_threshold` of ascending ``values`` and how many are strictly above it."""
    pfa = check_pfa(pfa)
    thr = values[values.size - allowed_false_alarms(pfa, values.size) - 1]
    return float(thr), int(values.size - np.searchsorted(values, thr, side="right"))


@dataclasses.dataclass(frozen=True)
class Calibration:
    """One threshold calibrated on noise-only scenes.

    ``threshold``: :func:`pixel_threshold` of every pixel of every map of the scenes
    ``seeds``; ``pixels``: how many; ``above``: how many of them are strictly above it
    (<= floor(pfa * pixels)); ``values``: the sorted noise-only values (further levels:
    :meth:`threshold_for`, :meth:`count_above`).
    """

    pfa: float
    threshold: float
    seeds: tuple[int, ...]
    pixels: int
    above: int
    values: np.ndarray = dataclasses.field(repr=False, compare=False)

    @property
    def measured_pfa(self) -> float:
        """``above / pixels``, the false-alarm rate per pixel on the calibration scenes."""
        return self.above / self.pixels

    def threshold_for(self, pfa: float) -> float:
        """:func:`pixel_threshold` of the same noise-only values at another ``pfa``."""
        return _sorted_threshold(self.values, pfa)[0]

    def count_above(self, threshold: float) -> int:
        """Noise-only pixels strictly above ``threshold``."""
        return int(self.values.size - np.searchsorted(self.values, threshold, side="right"))


def check_noise_seeds(seeds: Iterable[int]) -> tuple[int, ...]:
    """The seeds of noise-only scenes: at least one, distinct integers >= 0."""
    seeds = tuple(seeds)
    if not seeds:
        raise PfaError("seeds must name at least one noise-only scene")
    for s in seeds:
        check_int("seed (noise-only scene)", s, 0, error=PfaError)
    if len(set(seeds)) != len(seeds):
        raise PfaError(f"seeds must be distinct, got {list(seeds)}")
    return seeds


def calibrate_pixel_threshold(noise_maps: Callable[[int], Any], seeds: Iterable[int],
                              pfa: float) -> Calibration:
    """Calibrate a per-pixel threshold on the maps of noise-only scenes named by seed.

    Parameters
    ----------
    noise_maps : callable
        ``noise_maps(seed) -> array`` of the detector's map values (any shape; every entry
        one pixel of one map) on the noise-only scene(s) of that seed. It must be
        deterministic in ``seed``; then so is the threshold.
    seeds : iterable of int
        The noise-only scenes, each a distinct integer >= 0.
    pfa : float
        False-alarm probability per pixel, in (0, 1).
    """
    pfa = check_pfa(pfa)
    seeds = check_noise_seeds(seeds)
    # the maps' own dtype (integer energies stay 4 bytes a pixel), sorted once
    values = np.sort(np.concatenate([np.asarray(noise_maps(s)).ravel() for s in seeds]))
    if values.dtype.kind == "f":
        values = values[np.isfinite(values)]
    thr, above = _sorted_threshold(values, pfa)
    return Calibration(pfa, thr, seeds, int(values.size), above, values)


def figure_roc(curves: dict, path: Any, *, title: str = "") -> Any:
    """ROC figure (PNG): Pd against Pfa per pixel, one line per curve, Pfa on a log axis.

    ``curves``: ``{label: [(pfa, pd, lo, hi), ...]}``, ``lo``/``hi`` the bounds of Pd's
    interval (drawn as bars; NaN Pd: no point, no bar).
    """
    from dptbd.figures import new_figure, save_figure

    fig, ax = new_figure(6.4, 4.2)
    for label, points in curves.items():
        pts = sorted(points)
        x = [p[0] for p in pts]
        pd = np.array([p[1] for p in pts], dtype=np.float64)
        lo = np.array([p[2] for p in pts], dtype=np.float64)
        hi = np.array([p[3] for p in pts], dtype=np.float64)
        below = np.where(np.isnan(pd), 0.0, pd - lo)
        above = np.where(np.isnan(pd), 0.0, hi - pd)
        ax.errorbar(x, pd, yerr=[below, above], marker="o", ms=3, capsize=2, label=label)
    ax.set_xscale("log")
    ax.set_xlabel("Pfa per pixel (noise-only calibration)")
    ax.set_ylabel("Pd")
    ax.set_ylim(-0.02, 1.02)
    ax.grid(alpha=0.3, which="both")
    if title:
        ax.set_title(title, fontsize=10)
    ax.legend(fontsize=8, loc="best")
    fig.tight_layout()
    return save_figure(fig, path)
