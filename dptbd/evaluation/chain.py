"""The whole chain of paper 001 on one sequence: FPGA stage, then DSP stage.

001 §5: "方向加权的动态规划算法可采用高速FPGA器件实现，二级关联部分可以采用高速DSP实现" —
the direction-weighted DP runs on an FPGA, the second-level association on a DSP.

* **FPGA stage** — the bit-accurate golden model of the DP (``run_fixed_fast``, eqs (8)–(11),
  ``docs/arithmetic.md`` §1–§5) and the constant-false-alarm-count histogram threshold
  (§6): candidate records (row, col, E, d) per accumulated frame. ``lists="gateware"``
  (the default) hands the DSP exactly what the gateware segmenter emits
  (:func:`dptbd.model.segmentation.segment_sequence`, threshold from the previous segment's
  histogram, §6.1–§6.4; the first list after reset is empty); ``lists="ideal"`` uses the
  ideal rule on each segment's own image (:func:`dptbd.model.segmentation.candidates`,
  at most n records), which no single-pass gateware can produce.
* **Between the stages** — the direction maps of every frame of each segment (the
  gateware streams every frame's state), used to backtrack each candidate's path
  (:mod:`dptbd.dsp.backtrack`).
* **DSP stage** — the fixed-capacity track association of 001 §3
  (:class:`dptbd.dsp.association.Tracker`), one step per segment.
"""

from __future__ import annotations

import dataclasses
from typing import Callable, Iterable

import numpy as np

from dptbd.config import DPConfig
from dptbd.dsp.association import (AssociationConfig, ConfirmedTrack, make_candidates,
                                     trim_to_count)
from dptbd.dsp.backtrack import candidate_paths, segment_direction_maps, track_positions
from dptbd.dsp.c_tracker import tracker_class
from dptbd.model.segmentation import candidates as segment_candidates, segment_sequence
from dptbd.model.segments import SegmentOutput

__all__ = ["LISTS", "PipelineResult", "run_pipeline", "segmenter_settings"]


@dataclasses.dataclass
class PipelineResult:
    """Everything the two stages produced for one sequence.

    Attributes
    ----------
    cfg, assoc : DPConfig, AssociationConfig
        The parameters.
    count : int
        n, candidates per accumulated frame.
    segments : SegmentOutput
        Accumulated images, direction maps and end frames of every segment.
    maps : numpy.ndarray
        ``(S, K, H, W)`` direction map after every frame of every segment.
    candidates : list of numpy.ndarray
        Per segment, :data:`dptbd.dsp.association.CANDIDATE_DTYPE` records.
    tracks : list of ConfirmedTrack
        Every track the DSP confirmed.
    positions : dict
        Track id -> ``(frames, positions, measured)`` (:func:`track_positions`).
    stats : dict
        The tracker's counters.
    lists : str
        Which candidate lists the DSP received (:data:`LISTS`).
    dsp : str
        Which association ran: ``"python"`` (the reference model) or ``"c"`` (the C
        firmware, :mod:`dptbd.dsp.c_tracker`).
    """

    cfg: DPConfig
    assoc: AssociationConfig
    count: int
    segments: SegmentOutput
    maps: np.ndarray
    candidates: list
    tracks: list[ConfirmedTrack]
    positions: dict
    stats: dict
    lists: str = "gateware"
    dsp: str = "python"


def _accumulate(frames: np.ndarray, cfg: DPConfig) -> SegmentOutput:
    try:
        from dptbd.model.fast import run_fixed_fast as run
    except ImportError:  # pragma: no cover - numba missing: the reference gives the same bits
        from dptbd.model.fixed import run_fixed as run
    return run(frames, cfg)


#: The candidate lists the DSP can receive.
LISTS = ("gateware", "ideal")


def segmenter_settings(cfg: DPConfig, frames: np.ndarray, count: int,
                       assoc: AssociationConfig, headroom: float = 2.0,
                       calibration_frames: int | None = None) -> DPConfig:
    """The segmenter's parameters for a run: n_hw, C and the histogram shift s.

    All three are **build-time** parameters of the gateware (elaborated into the Verilog:
    ``hw/segmenter.py`` has no register a host could write at run time), so in a real system
    they are fixed before the bitstream is built. Only fields the user left at ``None`` are
    set:

    * ``candidate_count`` n_hw = round(``headroom`` x ``count``), at most
      ``assoc.max_candidates``: the gateware selects with headroom, and the DSP trims each
      list to ``count`` (:func:`dptbd.dsp.association.trim_to_count`). The threshold comes
      from the *previous* segment's histogram (§6.1), so the gateware's count scatters
      around n_hw; headroom makes its list hold the segment's own top ``count`` (the
      ideal list, after trimming) in more segments (``docs/association.md`` §2 has the
      figures). From the configuration alone;
    * ``candidate_capacity`` C = min(2 n_hw, ``assoc.max_candidates``): the DSP's receive
      buffer bounds the list. From the configuration alone;
    * ``histogram_shift`` s: **not** from the configuration alone but a host-side
      **calibration** on recorded frames — the smallest s whose 2^b bins reach K times the
      largest pixel of the first ``calibration_frames`` frames (default K: the first
      segment, frames a host can record from the sensor before it builds and starts the
      FPGA stage), ``max(0, bitlen(K * max(x)) - b)``, capped at B_E - 1. The
      configuration-only rule (``DPConfig``'s default, 2^b bins over the full input range
      K (2^B_in - 1)) gives s = 5 for 001's 12-bit ADC whose noise sits at 480 LSB: bins
      32 levels wide, and a tied top bin holds so many pixels that the lists come out
      short of the requested length, which costs confirmed tracks (the figures:
      ``docs/association.md`` §2 and ``docs/arithmetic.md`` §6.6, where b = 12 is measured
      as the configuration-only alternative). Pixels above the calibrated
      range share the top bin, which is kept whenever it holds at most n pixels.
    """
    changes = {}
    n_hw = min(int(round(count * headroom)), assoc.max_candidates,
               cfg.candidate_capacity if cfg.candidate_capacity is not None else assoc.max_candidates)
    if cfg.candidate_count is None:
        changes["candidate_count"] = n_hw
        n_hw_eff = n_hw
    else:
        n_hw_eff = cfg.candidate_count
    if cfg.candidate_capacity is None:
        changes["candidate_capacity"] = max(n_hw_eff, min(2 * n_hw_eff, assoc.max_candidates))
    if cfg.histogram_shift is None:
        n_cal = cfg.segment_frames if calibration_frames is None else calibration_frames
        if n_cal < 1:
            raise ValueError(f"calibration_frames must be an integer in [1, inf), got {calibration_frames}")
        peak = int(np.max(frames[:n_cal])) * cfg.segment_frames
        changes["histogram_shift"] = min(cfg.energy_bits - 1,
                                         max(0, peak.bit_length() - cfg.histogram_bits))
    return dataclasses.replace(cfg, **changes) if changes else cfg


def run_pipeline(frames: np.ndarray, cfg: DPConfig, count: int, assoc: AssociationConfig, *,
                 lists: str = "gateware", dsp: str = "python",
                 progress: Callable[..., Iterable] | None = None) -> PipelineResult:
    """Run the FPGA stage and the DSP stage on integer frames ``(T, H, W)``.

    Parameters
    ----------
    frames : numpy.ndarray
        Unsigned ``cfg.input_bits``-bit integer frames.
    cfg : DPConfig
        DP parameters; frame size must match.
    count : int
        n, the constant false-alarm count per accumulated frame (<= ``assoc.max_candidates``).
    assoc : AssociationConfig
        Association parameters.
    lists : {"gateware", "ideal"}
        Which candidate lists the DSP receives (module docstring). With ``"gateware"`` the
        segmenter's n is ``count`` unless ``cfg.candidate_count`` sets it, and its record
        capacity C (``cfg.record_capacity``) must fit ``assoc.max_candidates``.
    dsp : {"python", "c"}
        The association that runs the DSP stage: the Python reference model
        (:class:`~dptbd.dsp.association.Tracker`) or the C firmware
        (:class:`~dptbd.dsp.c_tracker.CTracker`, built with the system C compiler on first
        use); both give the same tracks bit for bit.
    progress : callable, optional
        ``progress(iterable, desc=..., total=...)`` wrapper (``tqdm``) for the per-segment loops.
    """
    if lists not in LISTS:
        raise ValueError(f"lists must be one of {', '.join(LISTS)}, got {lists!r}")
    if lists == "gateware" and cfg.candidate_count is None:
        cfg = dataclasses.replace(cfg, candidate_count=count)
    limit = cfg.record_capacity if lists == "gateware" else count
    if limit > assoc.max_candidates:
        what = (f"the gateware segmenter emits up to candidate_capacity C = {limit} records"
                if lists == "gateware" else f"the segmentation keeps up to {limit} candidates")
        raise ValueError(f"{what} per accumulated frame but the association's input buffer "
                         f"holds max_candidates={assoc.max_candidates}; raise it, lower the "
                         f"capacity or the false-alarm rate")
    segments = _accumulate(frames, cfg)
    wrap = (lambda it, desc: it) if progress is None else \
        (lambda it, desc: progress(it, desc=desc, leave=False))
    maps = segment_direction_maps(frames, cfg, segment_direction=segments.direction,
                                  progress=lambda it: wrap(it, "direction maps"))
    tracker = tracker_class(dsp)(assoc, segment_frames=cfg.segment_frames,
                                 segment_stride=cfg.segment_stride, height=cfg.height,
                                 width=cfg.width, radius=cfg.radius)
    cands = []
    gateware = (segment_sequence(segments.energy, segments.direction, cfg)
                if lists == "gateware" else None)
    for s in wrap(range(len(segments.end_frames)), "association"):
        raw = (trim_to_count(gateware[s].records, count) if gateware is not None else
               segment_candidates(segments.energy[s], segments.direction[s], count))
        c = make_candidates(raw, candidate_paths(raw, maps[s], cfg))
        tracker.step(c)
        cands.append(c)
    tracks = tracker.confirmed_tracks()
    positions = {tr.id: track_positions(tr.points, maps, cfg) for tr in tracks}
    return PipelineResult(cfg, assoc, count, segments, maps, cands, tracks, positions,
                          dict(tracker.stats), lists, dsp)
