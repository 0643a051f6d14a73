"""Golden-model reference for paper 000's family on the gateware (``docs/arithmetic.md`` §8).

``family_reference_states`` is :func:`hw_harness.reference_states` for a §8 configuration:
what ``DPPipeline`` must put out, frame by frame, from ``dptbd.model.family``'s
``family_start`` / ``family_step`` (K-frame segments, or the recursion of §8.6), with LUTs
rewritten at run time from a given pixel index on. ``family_writes`` turns a table change
into the ``(port, address, code)`` writes that :func:`hw_harness.run_stream` issues.
:func:`variant` holds the §8.9 variants on small scenes that the gateware tests share.
"""

from __future__ import annotations

import numpy as np

from dptbd.config import DPConfig
from dptbd.weights import plain_weights
from dptbd.evaluation.detectors.unified_fixed import quantise_unified
from dptbd.evaluation.detectors.transitions import velocity_log_penalty
from dptbd.evaluation.detectors.merits import amplitude_merit, likelihood_difference_merit
from dptbd.model.family import family_start, family_step
from helpers.hw_harness import FIELDS


def start_frame(cfg: DPConfig, t: int) -> bool:
    """Frame ``t`` restarts the DP: t = 0 when recursive, every K-th frame otherwise."""
    return t == 0 if cfg.recursive else t % cfg.segment_frames == 0


def family_reference_states(cfg: DPConfig, frames: np.ndarray, changes=()) -> np.ndarray:
    """Expected ``states`` ``(T, H, W, 5)`` in :data:`hw_harness.FIELDS` order.

    ``changes`` is a sequence of ``(pixel_index, cfg_variant)``: from that global pixel
    index on, the tables are ``cfg_variant``'s (a LUT written at run time).
    """
    frames = np.asarray(frames)
    n_frames, height, width = frames.shape
    tables = [(0, cfg), *changes]
    out = np.zeros((n_frames, height, width, len(FIELDS)), dtype=np.int64)
    energy = direction = None
    for t in range(n_frames):
        index = t * height * width + np.arange(height * width).reshape(height, width)
        new_e = np.zeros((height, width), dtype=np.int64)
        new_d = np.zeros((height, width), dtype=np.int64)
        for n, (first, table) in enumerate(tables):
            stop = tables[n + 1][0] if n + 1 < len(tables) else index.max() + 1
            mask = (index >= first) & (index < stop)
            if mask.any():
                e, d = (family_start(frames[t], table) if start_frame(cfg, t)
                        else family_step(energy, direction, frames[t], table))
                new_e[mask], new_d[mask] = e[mask], d[mask]
        energy, direction = new_e, new_d
        k = cfg.segment_frames
        out[t, ..., 0], out[t, ..., 1] = energy, direction
        out[t, :, -1, 2] = 1
        out[t, -1, -1, 3] = 1
        out[t, -1, -1, 4] = 1 if cfg.recursive else int(t % k == k - 1)
    return out


def family_writes(cfg: DPConfig, new: DPConfig) -> list[tuple[str, int, int]]:
    """``(port, address, code)`` writes turning ``cfg``'s merit and penalty LUTs into ``new``'s."""
    writes = []
    old_merit, new_merit = cfg.merit_code_array, new.merit_code_array
    writes += [("merit", int(x), int(new_merit[x])) for x in np.flatnonzero(old_merit != new_merit)]
    old_q, new_q = cfg.penalty_code_array, new.penalty_code_array
    writes += [("penalty", cfg.lut_address(int(p), int(m)), int(new_q[p, m]))
               for p, m in zip(*np.nonzero(old_q != new_q))]
    return writes


def eq22_penalty(radius, scale=20.0):
    """000 eq (22)'s penalty, quantised as ``docs/arithmetic.md`` §8.2 says (Qc = round(s * -Q))."""
    return quantise_unified(amplitude_merit(), velocity_log_penalty(radius), radius=radius,
                            scale=scale).penalty_codes


def likelihood_merit(scale=40.0, gain=32.0, offset=64.0):
    """000 eqs (19)-(20)'s S(z) as signed merit codes round(s * S(z(x))), z(x) = (x - offset) / gain
    (§8.1): negative for most noise pixels."""
    s = likelihood_difference_merit(amplitude=3.0, epsilon=0.85, sigma=1.0).function
    z = (np.arange(256) - offset) / gain
    return np.floor(scale * s(z) + 0.5).astype(np.int64)


def variant(name):
    """The §8.9 variants on small scenes: (config, number of frames)."""
    r1 = dict(width=6, height=5, weights=plain_weights(1))
    r2 = dict(width=7, height=6, radius=2, weights=plain_weights(2))
    return {
        # 000 eq (24): amplitude DP with eq (22)'s penalty
        "amplitude-penalty-r1": (dict(**r1, segment_frames=3, energy_bits=11,
                                      penalty_codes=eq22_penalty(1)), 6),
        "amplitude-penalty-r2": (dict(**r2, segment_frames=2, energy_bits=11,
                                      penalty_codes=eq22_penalty(2)), 4),
        # 000 eqs (19)-(23): likelihood-difference merit with eq (22)'s penalty
        "likelihood-penalty-r1": (dict(**r1, segment_frames=4, energy_bits=10,
                                       merit_codes=likelihood_merit(),
                                       penalty_codes=eq22_penalty(1)), 5),
        "likelihood-r2": (dict(**r2, segment_frames=3, energy_bits=10,
                               merit_codes=likelihood_merit()), 3),
        # forgetting alpha < 1, both rounding modes, with and without signed candidates
        "forgetting-truncate-penalty": (dict(**r1, segment_frames=4, energy_bits=11,
                                             forgetting=0.85, penalty_codes=eq22_penalty(1),
                                             merit_codes=likelihood_merit()), 5),
        "forgetting-half_up": (dict(width=6, height=5, segment_frames=3, rounding="half_up",
                                    forgetting=0.55, forgetting_bits=4), 5),
        "forgetting-half_up-penalty-paper-weights": (dict(
            width=6, height=5, segment_frames=3, rounding="half_up", forgetting=0.85,
            energy_bits=10, penalty_codes=eq22_penalty(1, 40.0),
            merit_codes=likelihood_merit(60.0)), 4),
        # recursive: a start frame only after reset
        "recursive-r1": (dict(**r1, segment_frames=2, recursive=True, rounding="half_up",
                              forgetting=0.85, energy_bits=10, merit_codes=likelihood_merit(),
                              penalty_codes=eq22_penalty(1)), 7),
        "recursive-r2-truncate": (dict(**r2, segment_frames=3, recursive=True, forgetting=0.75,
                                       forgetting_bits=3, energy_bits=11,
                                       penalty_codes=eq22_penalty(2)), 5),
        "recursive-only-saturating": (dict(width=5, height=4, recursive=True, input_bits=4,
                                           energy_bits=6), 6),
    }[name]


VARIANTS = ["amplitude-penalty-r1", "amplitude-penalty-r2", "likelihood-penalty-r1",
            "likelihood-r2", "forgetting-truncate-penalty", "forgetting-half_up",
            "forgetting-half_up-penalty-paper-weights", "recursive-r1", "recursive-r2-truncate",
            "recursive-only-saturating"]
