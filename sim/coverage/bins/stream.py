"""The bins of a compiled run of a stream design, ``dp``, ``core`` or ``segmenter``
(:func:`dptbd.sim.campaign.check_run`): what the run can fill (:func:`declared_stream`) and
what it filled (:func:`stream_bins`); the groups are described in
:mod:`dptbd.sim.coverage.bins`."""

from __future__ import annotations

from typing import Iterable

import numpy as np

from dptbd.sim.coverage.bins.groups import (FIFO, LIST_LABELS, LUT_CODES, LUT_STAGES,
                                            SATURATION, TIES, band, declared_stall, key,
                                            words_in_flight)
from dptbd.sim.coverage.bins.view import (count_lut, count_outputs, count_positions,
                                          count_recovered, view_of)

__all__ = ["declared_stream", "stream_bins"]


def declared_stream(design: str, faults: Iterable[str], lut: bool, latency: int
                    ) -> dict[str, int]:
    """Every bin (0 hits) a run of ``design`` can fill: its case's ``faults``, ``lut``
    whether its case writes the LUT, ``latency`` the DP pipeline's L."""
    faults = tuple(faults)
    out = declared_stall()
    if "reset" in faults:
        out.update({key("reset", words_in_flight(k)): 0 for k in range(latency + 1)})
        if design != "segmenter":
            out[key("reset", FIFO)] = 0
    out.update({key("fault", f"{f} recovered"): 0 for f in faults})
    if lut:
        out.update({key("LUT", label): 0 for label in LUT_STAGES + LUT_CODES})
    out[SATURATION] = 0
    if design == "segmenter":
        out.update({key("lists", label): 0 for label in LIST_LABELS})
        out[TIES] = 0
    return out


def _reset_occupancy(design: str, resets, accept: np.ndarray, out_cycles: np.ndarray,
                     latency: int) -> list[int]:
    """Words in the pipeline at each reset's first cycle (the ``reset`` group of
    :mod:`dptbd.sim.coverage.bins`)."""
    occupancy, prev_in, prev_out = [], 0, 0
    for cycle in sorted(c for c, _ in resets):
        n_in = int(np.searchsorted(accept, cycle))
        n_out = int(np.searchsorted(out_cycles, cycle))
        if design == "segmenter":
            occupancy.append(n_in - max(prev_in, int(np.searchsorted(accept, cycle - latency))))
        else:
            occupancy.append((n_in - prev_in) - (n_out - prev_out))
        prev_in, prev_out = n_in, n_out
    return occupancy


def stream_bins(case, stimulus, result, events: Iterable[tuple[str, int]] = (),
                latency: int = 0) -> dict[str, int]:
    """The bins of one compiled run of a ``dp``, ``core`` or ``segmenter`` case.

    Parameters
    ----------
    case : dptbd.sim.campaign.Case
    stimulus : dptbd.sim.rtl.check.Stimulus
    result : dptbd.sim.rtl.check.CheckResult
    events : iterable of (fault, word index)
        The framing faults injected (``misaligned_first``, ``short_frame``,
        ``long_frame``) and the first word they touch; resets, LUT and settings writes and
        the store's garbage are read from ``stimulus``.
    latency : int
        The DP pipeline's L of the build.
    """
    cfg = case.cfg
    lut = "lut" in case.faults or case.random_lut
    counts = declared_stream(case.design, case.faults, lut, latency)
    if not result.passed:
        return counts
    pieces = [(a, exp, board.lists if case.design == "segmenter" else None, board.count)
              for a, exp, board in result.scored]
    view = view_of(cfg, pieces)
    count_positions(view, cfg, counts, f"gaps {band(stimulus.valid_gap)}, "
                                       f"back-pressure {band(stimulus.ready_pause)}")
    raw = result.raw
    accept = raw.accept_cycles[:result.words_in // cfg.pixels_per_clock].astype(np.int64)
    if "reset" in case.faults:
        for k in _reset_occupancy(case.design, stimulus.resets, accept,
                                  raw.out_cycles.astype(np.int64), latency):
            counts[key("reset", words_in_flight(k) if k <= latency else FIFO)] += 1
    # the view counts pixels; at P > 1 the stimulus's indices and the harness's accept
    # cycles count beats of P pixels
    p = cfg.pixels_per_clock
    found = list(events)
    found += [("reset", p * int(np.searchsorted(accept, c))) for c, _ in stimulus.resets]
    found += [("lut", p * int(i)) for i, _ in stimulus.lut_changes if int(i) > 0]
    found += [("settings", p * int(i)) for i, _ in stimulus.settings_changes]
    if stimulus.store_init == "random":
        found.append(("store_garbage", 0))
    count_recovered(view, [e for e in found if e[0] in case.faults], counts)
    if lut:
        count_lut(view, cfg, [(p * int(i), codes) for i, codes in stimulus.lut_changes],
                  counts)
    count_outputs(view, cfg, counts)
    return counts
