"""The candidate rules of ``dptbd compare`` (run-level key ``tie_rule``, ``--tie-rule``): which
pixels of an accumulated image are its candidates, n = the run's candidate count.

``random`` (the default)
    Exactly n candidates: every pixel with E above the image's n-th largest value, and of
    the pixels AT that value the ones with the smallest pseudo-random priority per (seed,
    trial, segment, pixel) (:func:`!_select`, written plainly in :func:`candidate_indices`).
``gateware``
    The gateware segmenter's selection (``docs/arithmetic.md`` §6) with the image's own
    histogram and one bin per E value (s = 0): the pixels with E strictly above the image's
    (n+1)-th largest value, a tie at the boundary dropped whole, so at most n
    (:func:`!_select_above`; the model's rule is
    :func:`dptbd.model.segmentation.candidate_mask`).
``gateware-bins``
    The same on the histogram bins ``min(E >> s, 2**b - 1)`` of the configuration the
    detector runs with (:func:`dptbd.model.segmentation.histogram_bins`, s =
    ``DPConfig.bin_shift``): what the segmenter selects when it thresholds an image with its
    own histogram. Float models have no bins; they select on E as under ``gateware``.

Neither gateware rule models the segmenter's stale threshold (the previous segment's
histogram) or the empty first list after reset. One function per rule (:data:`RULES`),
called through :func:`!_candidates`.
"""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING

import numpy as np
from numba import njit

from dptbd.config import DPConfig
from dptbd.model.segmentation import histogram_bins, threshold_level

if TYPE_CHECKING:
    from dptbd.evaluation.compare.plan import Plan

__all__ = ["image_keys", "nth_largest", "candidate_indices", "RULES"]

# ---- the random rule: exactly n per image, ties at the n-th largest broken at random ------
#
# Every pixel with E above the image's n-th largest value is a candidate; the pixels AT that
# value fill the list up to n in the order of a pseudo-random priority per pixel,
# splitmix64 of (seed, trial, segment, pixel). The priority depends on the scene, never on
# the detector, so every detector breaks its ties with the same priorities on the same scene
# (paired), and it is uniform over the frame, so a tied target is kept with the same chance
# wherever it is (a raster-order tie-break keeps tied pixels near the top of the frame:
# docs/compare_results.md measures the bias). Reproducible: no generator state, only the indices.

_GOLDEN = np.uint64(0x9E3779B97F4A7C15)
_M1 = np.uint64(0xBF58476D1CE4E5B9)
_M2 = np.uint64(0x94D049BB133111EB)


@njit(cache=True)
def _mix(z):
    """splitmix64's finaliser (uint64 -> uint64, a bijection)."""
    z = (z ^ (z >> np.uint64(30))) * _M1
    z = (z ^ (z >> np.uint64(27))) * _M2
    return z ^ (z >> np.uint64(31))


def _mix_np(z):
    """:func:`_mix` in numpy (uint64 scalars or arrays; wraps like the kernel)."""
    z = np.asarray(z, dtype=np.uint64)
    with np.errstate(over="ignore"):
        z = (z ^ (z >> np.uint64(30))) * _M1
        z = (z ^ (z >> np.uint64(27))) * _M2
        return z ^ (z >> np.uint64(31))


def image_keys(seed: int, first_trial: int, n_trials: int, n_seg: int) -> np.ndarray:
    """``(n_trials * n_seg,)`` uint64 tie-break keys of the images of trials
    ``first_trial ..`` (image ``i``: trial ``first_trial + i // n_seg``, segment
    ``i % n_seg``), the same for every detector and every SNR of a trial."""
    trial = np.repeat(np.arange(first_trial, first_trial + n_trials, dtype=np.uint64), n_seg)
    seg = np.tile(np.arange(n_seg, dtype=np.uint64), n_trials)
    with np.errstate(over="ignore"):
        base = _mix_np(np.uint64(seed) + _GOLDEN)
        return _mix_np(_mix_np(base ^ _mix_np(trial + _GOLDEN)) ^ seg)


@njit(cache=True)
def _select(energy, level, keys, near, n_seg, count, idx, n_cand, hit, near_count):
    """Exactly ``min(count, H*W)`` candidates of each image (raster order) and how many lie
    in the detection gate.

    ``energy``: ``(images, H*W)``; image ``i`` is segment ``i % n_seg``; ``level[i]`` its
    ``count``-th largest value (``-inf`` when ``count >= H*W``); ``keys[i]`` its tie-break
    key (:func:`image_keys`). Every pixel with E > level is a candidate; of the pixels with
    E == level, the ``count - #(E > level)`` with the smallest priority
    ``_mix(keys[i] ^ (p * golden))`` (then the lowest index) are too
    (:func:`candidate_indices` is the same rule in numpy).
    """
    n_pix = energy.shape[1]
    prio = np.empty(n_pix, np.uint64)
    for i in range(energy.shape[0]):
        s = i % n_seg
        lv = level[i]
        above = 0
        tied = 0
        for p in range(n_pix):
            e = energy[i, p]
            if e > lv:
                above += 1
            elif e == lv:
                prio[tied] = _mix(keys[i] ^ (np.uint64(p) * _GOLDEN))
                tied += 1
        slots = count - above  # tied pixels to take
        if slots > tied:
            slots = tied
        cut = np.uint64(0)
        if 0 < slots < tied:
            cut = np.sort(prio[:tied])[slots - 1]  # the slots-th smallest priority
        k = 0
        inside = 0
        j = 0  # tied pixels seen: prio[j] is this one's priority (same order as above)
        for p in range(n_pix):
            e = energy[i, p]
            take = e > lv
            if not take and e == lv and slots > 0:
                if slots == tied - j:
                    take = True
                else:
                    take = prio[j] <= cut
                if take:
                    slots -= 1
                j += 1
            if take:
                idx[i, k] = p
                k += 1
                if near[s, p]:
                    inside += 1
        n_cand[i] = k
        near_count[i] = inside
        hit[i] = inside > 0


def nth_largest(flat: np.ndarray, count: int) -> np.ndarray:
    """The ``count``-th largest value of each row of ``flat`` ``(images, pixels)``, with
    multiplicity, as float64 (``-inf`` when ``count >= pixels``, ``+inf`` when 0)."""
    n_pix = flat.shape[-1]
    if count >= n_pix:
        return np.full(flat.shape[:-1], -np.inf)
    if count <= 0:
        return np.full(flat.shape[:-1], np.inf)
    kth = n_pix - count  # ascending position of the count-th largest
    return np.partition(flat, kth, axis=-1)[..., kth].astype(np.float64)


def candidate_indices(image: np.ndarray, count: int, key: int) -> np.ndarray:
    """The compare rule, written plainly: the raster indices (ascending) of exactly
    ``min(count, H*W)`` candidates of ONE image — the first ``count`` pixels sorted by
    descending E, then ascending tie-break priority ``_mix(key ^ (p * golden))``, then
    index. ``key``: the image's entry of :func:`image_keys`. The reference of the numba
    kernel :func:`!_select` (``docs/compare.md``)."""
    flat = np.asarray(image).reshape(-1)
    pix = np.arange(flat.size, dtype=np.uint64)
    with np.errstate(over="ignore"):
        prio = _mix_np(np.uint64(key) ^ (pix * _GOLDEN))
    order = np.lexsort((np.arange(flat.size), prio, -flat.astype(np.float64)))
    return np.sort(order[:max(0, min(count, flat.size))])


@njit(cache=True)
def _same_points(idx_a, n_a, dir_a, idx_b, n_b, dir_b, out):
    """Per image: candidates at the same pixel with the same direction in both lists."""
    for i in range(idx_a.shape[0]):
        ja = 0
        jb = 0
        same = 0
        while ja < n_a[i] and jb < n_b[i]:
            pa = idx_a[i, ja]
            pb = idx_b[i, jb]
            if pa == pb:
                if dir_a[i, pa] == dir_b[i, pb]:
                    same += 1
                ja += 1
                jb += 1
            elif pa < pb:
                ja += 1
            else:
                jb += 1
        out[i] = same


@dataclasses.dataclass
class _Candidates:
    """The candidate lists of one detector on one batch, flattened to (images, …)."""

    idx: np.ndarray        # (images, count) raster index, first n_cand valid
    n_cand: np.ndarray     # (images,)
    hit: np.ndarray        # (images,) a candidate in the gate
    near_count: np.ndarray  # (images,) candidates in the gate
    direction: np.ndarray  # (images, H*W)


# ---- one function per rule: (values (images, H*W), plan, keys, cfg) -> _Candidates fields ----

def _empty_lists(images: int, count: int) -> tuple:
    """``idx``, ``n_cand``, ``hit``, ``near_count`` for ``images`` images, zeroed."""
    return (np.zeros((images, max(count, 1)), np.int64), np.zeros(images, np.int64),
            np.zeros(images, np.bool_), np.zeros(images, np.int64))


def random_rule(flat: np.ndarray, plan: "Plan", keys: np.ndarray,
                cfg: DPConfig | None) -> tuple:
    """``random``: exactly n per image, ties at the n-th largest E broken by the
    priorities of ``keys`` (:func:`image_keys`; :func:`!_select`)."""
    count = plan.spec.candidate_count
    out = _empty_lists(flat.shape[0], count)
    _select(flat, nth_largest(flat, count), keys, plan.near_flat, len(plan.ends), count, *out)
    return out


@njit(cache=True)
def _select_above(values, level, idx, n_cand):
    """Every pixel with ``values[i, p] > level[i]``, in raster order, into ``idx[i]``; their
    number into ``n_cand[i]``. ``idx`` must be wide enough (``level`` the (n+1)-th largest
    value: at most n pixels)."""
    for i in range(values.shape[0]):
        lv = level[i]
        k = 0
        for p in range(values.shape[1]):
            if values[i, p] > lv:
                idx[i, k] = p
                k += 1
        n_cand[i] = k


def _above_next_largest(values: np.ndarray, plan: "Plan") -> tuple:
    """The pixels strictly above each row's (n+1)-th largest value
    (:func:`dptbd.model.segmentation.threshold_level`: ``-inf`` when n >= H*W), and how
    many lie in the detection gate (image ``i`` is segment ``i % len(plan.ends)``)."""
    count = plan.spec.candidate_count
    level = threshold_level(values[:, None, :], count).astype(np.float64)
    idx, n_cand, _, _ = _empty_lists(values.shape[0], count)
    _select_above(values, level, idx, n_cand)
    images = np.arange(values.shape[0])
    gate = plan.near_flat[images % len(plan.ends)]
    listed = np.arange(idx.shape[1])[None, :] < n_cand[:, None]
    near_count = (np.take_along_axis(gate, idx, axis=1) & listed).sum(axis=1).astype(np.int64)
    return idx, n_cand, near_count > 0, near_count


def gateware_rule(flat: np.ndarray, plan: "Plan", keys: np.ndarray,
                  cfg: DPConfig | None) -> tuple:
    """``gateware``: the segmenter's selection with the image's own histogram at s = 0,
    ``E > v_(n+1)``, a tie at the boundary dropped whole (``keys`` unused)."""
    return _above_next_largest(flat, plan)


def gateware_bins_rule(flat: np.ndarray, plan: "Plan", keys: np.ndarray,
                       cfg: DPConfig | None) -> tuple:
    """``gateware-bins``: the same on ``min(E >> s, 2**b - 1)`` of ``cfg``, the detector's
    configuration (``None``: a float model, selected on E)."""
    values = flat if cfg is None else histogram_bins(flat, cfg)
    return _above_next_largest(values, plan)


#: The candidate rule of each ``tie_rule`` (:data:`dptbd.evaluation.compare.spec.TIE_RULES`).
RULES = {"random": random_rule, "gateware": gateware_rule, "gateware-bins": gateware_bins_rule}


def _candidates(energy: np.ndarray, direction: np.ndarray, plan: "Plan", keys: np.ndarray,
                cfg: DPConfig | None = None) -> _Candidates:
    """The candidate lists of one detector on one batch under the run's rule
    (``plan.spec.tie_rule``, :data:`RULES`); ``keys``: :func:`image_keys`; ``cfg``: the
    fixed configuration the detector runs with, ``None`` for a float model."""
    flat = energy.reshape(-1, energy.shape[-1] * energy.shape[-2])
    idx, n_cand, hit, near_count = RULES[plan.spec.tie_rule](flat, plan, keys, cfg)
    return _Candidates(idx, n_cand, hit, near_count, direction.reshape(flat.shape[0], -1))
