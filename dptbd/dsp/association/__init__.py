"""DSP-style binary track association of paper 001 §3, written the way DSP firmware is.

001 §3 (二值轨迹关联) takes the candidate points of each accumulated frame (the first-level
detections of §2, at a false-alarm rate of 0.001–0.002 and a detection probability of
0.6–0.8) and links them into tracks:

    建立一记录结构体数组，记录目标轨迹信息，记录的内容包括轨迹最近两点、预测点、轨迹总长度、
    总匹配点数、匹配允许偏差距离、连续丢失目标点数。

"An array of record structures holds the tracks: the last two points of the track, the
predicted point, the total length, the total number of matched points, the allowed match
deviation and the number of consecutive misses." That is :data:`TRACK_DTYPE`, a numpy
structured array of fixed capacity, plus a fixed (capacity x ``max_points``) point history
per record for the output. Association runs in three steps per accumulated frame
(one segment, :meth:`Tracker.step`):

(1) **Matching in the prediction space.** "对预测空间中所有轨迹的预测点，在输入匹配图像中
    寻找最佳匹配点，并把轨迹延伸至该点。搜索窗的大小应根据轨迹总长和检测概率来确定，轨迹越长，
    检测概率越高，则搜索窗越大。匹配点的选取应考虑与预测点距离远近及轨迹速度方向两个因素" —
    each track takes the best candidate inside its gate around its predicted point; the
    gate grows with the track's length and detection ratio; the score combines the
    distance to the predicted point with the agreement between the track's velocity and
    the candidate's heading. "对匹配空间所有候选点，若该点未被处理，则把该点作为起始点，建立
    新轨迹" — candidates left over start new tracks.
(2) **Prediction.** "根据轨迹延伸至当前帧内点、轨迹前第1点、第2点，采用线性预测来预测下一
    轨迹点，预测时考虑了目标的机动" — linear prediction from the new point and the two before
    it, allowing for manoeuvres.
(3) **Output and deletion.** "对于检测次数、检测概率均达到一定门限的轨迹…作为结果输出；而对于
    检测次数、检测概率很小的轨迹…予以剔除。显然，输出目标轨迹门限值最高，预测轨迹门限值次之，
    剔除虚警轨迹门限值最低。" — three thresholds on (detection count, detection ratio):
    output > predict > delete.

Where 001 is silent the choices are ours; ``docs/association.md`` lists and motivates
them. In short:

* **Fixed point.** Positions and velocities are integers in 1/16 pixel (Q4, ``ONE = 16``);
  ratios are compared as ``hits * 256 >= ratio_q8 * length``; distances squared;
  divisions round half up (:func:`div_round`); the one square root is an integer one
  (:func:`math.isqrt`). Parameters are given in pixels and ratios
  (:class:`AssociationConfig`) and quantised once to integer codes.
* **Candidates** arrive as fixed-capacity records (:data:`CANDIDATE_DTYPE`): the FPGA's
  (row, col, E, d) plus the start ``(row0, col0)`` of the candidate's best path in its
  segment, found by backtracking the direction maps (:mod:`dptbd.dsp.backtrack`).
  Heading of a candidate: ``(row - row0, col - col0) / (K - 1)`` per frame, or the move of
  d alone when no path is given.
* **Cluster suppression.** DP energy spreads into a small cluster around a target (001 §2,
  "团聚效应"). A candidate with a stronger candidate within ``merge_radius`` (Chebyshev)
  is dropped before matching, so one target gives one point.
* **Classes and priority.** A track is *confirmed* once it passes the output threshold,
  in the *prediction space* while it passes the predict threshold, otherwise
  *tentative*. Matching is greedy in that priority order (confirmed, predicted,
  tentative; within a class the track with more hits first, then the older one), each
  track taking its lowest-cost unclaimed candidate.
* **Gate** (the record's allowed deviation): tracks in the prediction space get
  ``gate_base + gate_growth * min(length, gate_growth_segments) * ratio`` (longer and more
  often detected: larger, as 001 says) plus ``gate_miss`` per consecutive miss (the
  prediction's uncertainty grows while coasting), capped at ``gate_max``; tentative
  tracks get ``seed_gate`` plus ``gate_miss`` per miss.
* **Heading** is a cost, not a gate, by default (``reject_reversed = False``): 001 §3
  ranks candidates by "与轨迹速度方向偏差" and a candidate's backtracked heading is
  unreliable inside the DP's cluster (the strongest pixel's path may run backwards);
  ``link_gate`` (accept a candidate outside the gate whose path starts at the track's
  newest point) is off by default. Both measured in ``docs/association.md``.
* **Prediction** from the newest point p_k and the two before (p_{k-1}, p_{k-2}): step
  velocities ``v1 = (p_k - p_{k-1}) / gap1``, ``v2 = (p_{k-1} - p_{k-2}) / gap2`` (per
  segment, gaps in segments so misses are allowed for); ``v = (v1 + v2) / 2`` smooths
  the pixel rounding, unless the two steps differ by more than ``manoeuvre`` pixels
  (Chebyshev) — a manoeuvre — and then ``v = v1``, the newest step alone. A track with
  two points uses ``v1``; a new track uses its candidate's heading scaled to a segment.
  The predicted point is ``p_k + v * (segments since p_k)``, so a coasting track keeps
  moving.
* **Overlapping segments** (``segment_stride < segment_frames``): with
  ``confirm_disjoint`` a hit counts toward ``confirm_hits`` only when its list shares no
  frame with the list of the previous counted hit (``counted``, ``count_seg``: every
  ``ceil(K / S_t)`` segments at most), so one noise peak in two consecutive lists counts
  once; off by default (every hit counts, ``counted == hits``).
* **Wake** (``wake_radius``, off by default): after matching, a candidate left over within
  ``wake_radius`` of a live track's recent path (its newest ``wake_points`` history points
  and their path starts) starts no track — the recursive DP's energy stays on the pixels a
  target has just left.
* **Capacity overflow.** When every record is in use, candidates left over are *not*
  given a track: they are dropped and counted (``stats["dropped_candidates"]``);
  existing tracks are never evicted (they carry more evidence than one point). New tracks
  are started in decreasing E, so the weakest candidates are the ones dropped. Records
  freed by deletions are reused from the next segment on.

Worst-case work per segment, with C = ``capacity`` records and n <= ``max_candidates``
candidates: cluster suppression n(n-1) distance tests; matching 3 class scans of C
records, each sorting its tracks by evidence (at most C(C-1)/2 compares over the three
classes) and at most C x n cost evaluations in all (a track is in one class; each a few
multiplies and one integer square root); updates C; duplicate test m(m-1)/2 pairs of the m <= min(C, n) extended tracks; wake
suppression (when on) at most n x C x min(wake_points, max_points) point tests; new
tracks n(n-1)/2 insertion-sort compares and at most n + C free-slot probes. For C = 64,
n = 33: about 1 100 + 2 000 + 2 100 + 64 + 2 000 + 530 + 100 operations, independent
of the data (``tests/dsp/association/test_init.py::test_work_per_segment_is_bounded``). Nothing is
allocated per segment: every array, and the blank record written over freed records, is
created in ``__init__`` (``test_no_allocation_per_segment_and_input_capacity``).

The records and their fixed-point layout are in :mod:`dptbd.dsp.records`, the parameters
in :mod:`dptbd.dsp.association.config`; their names are importable from here too. This
module holds :class:`Tracker`: its integer codes, its state allocated once, the order of the
steps of one segment and the read-out; the steps themselves are in its base classes, one
module each: the candidates (:mod:`~dptbd.dsp.association.candidates`: headings, cluster and
wake suppression), the matching (:mod:`~dptbd.dsp.association.matching`: classes, gates and
costs) and the track records (:mod:`~dptbd.dsp.association.tracks`: extension, prediction,
thresholds, duplicates, deletion, new tracks).
"""

from __future__ import annotations

import math

import numpy as np

from dptbd.dsp.association.candidates import CandidateSteps, check_candidate_list
from dptbd.dsp.association.config import AssociationConfig, AssociationError
from dptbd.dsp.association.matching import (CLASS_CONFIRMED, CLASS_PREDICTED, CLASS_TENTATIVE,
                                            Matching)
from dptbd.dsp.association.tracks import TrackUpdates
from dptbd.dsp.records import (CANDIDATE_DTYPE, CONFIRMED, FREE, ONE, POINT_DTYPE, Q_BITS,
                               RATIO_BITS, RATIO_ONE, TENTATIVE, TRACK_DTYPE, ConfirmedTrack,
                               div_round, make_candidates, trim_to_count)

# the records stay importable from here (they lived in this module before the split)
__all__ = ["Q_BITS", "ONE", "RATIO_BITS", "RATIO_ONE", "FREE", "TENTATIVE", "CONFIRMED",
           "CANDIDATE_DTYPE", "TRACK_DTYPE", "POINT_DTYPE", "ConfirmedTrack", "div_round",
           "make_candidates", "trim_to_count",
           "AssociationConfig", "AssociationError", "Tracker", "check_candidate_list"]


def _q(x: float, bits: int) -> int:
    return int(math.floor(x * (1 << bits) + 0.5))


class Tracker(CandidateSteps, Matching, TrackUpdates):
    """The DSP's track table and its per-segment association (001 §3).

    Parameters
    ----------
    cfg : AssociationConfig
        Parameters.
    segment_frames, segment_stride : int
        K and S_t of the DP (``docs/arithmetic.md`` §5): a candidate's path spans K - 1
        moves, consecutive segments end S_t frames apart.
    height, width : int
        Image size: a track whose predicted point leaves the image by more than its gate
        is deleted.
    radius : int
        DP search radius r (moves of a direction code d).

    Notes
    -----
    Call :meth:`step` once per segment with that segment's candidates (possibly none);
    :meth:`confirmed_tracks` reads out every track that was ever confirmed.
    """

    def __init__(self, cfg: AssociationConfig, *, segment_frames: int, segment_stride: int,
                 height: int, width: int, radius: int = 1) -> None:
        self.cfg = cfg
        self.k = int(segment_frames)
        self.stride = int(segment_stride)
        if self.k < 1 or not 1 <= self.stride:
            raise AssociationError(f"segment_frames and segment_stride must be an integer in [1, inf), got "
                                   f"{segment_frames}, {segment_stride}")
        self.height, self.width = int(height), int(width)
        span = np.arange(-radius, radius + 1)
        dy, dx = np.meshgrid(span, span, indexing="ij")
        self._moves = [(int(a), int(b)) for a, b in zip(dy.ravel(), dx.ravel())]
        # ---- integer codes (quantised once) ----
        self.seed_gate = _q(cfg.seed_gate, Q_BITS)
        self.gate_base = _q(cfg.gate_base, Q_BITS)
        self.gate_growth = _q(cfg.gate_growth, Q_BITS)
        self.gate_miss = _q(cfg.gate_miss, Q_BITS)
        gate_max = cfg.max_speed * self.stride + 1.0 if cfg.gate_max is None else cfg.gate_max
        self.gate_max = min(_q(gate_max, Q_BITS), 65535)
        self.manoeuvre = _q(cfg.manoeuvre, Q_BITS)
        self.link_gate = _q(cfg.link_gate, Q_BITS)
        self.heading_weight = _q(cfg.heading_weight, RATIO_BITS)
        self.heading_min = _q(cfg.heading_min, Q_BITS)
        self.confirm_ratio = _q(cfg.confirm_ratio, RATIO_BITS)
        self.predict_ratio = _q(cfg.predict_ratio, RATIO_BITS)
        self.delete_ratio = _q(cfg.delete_ratio, RATIO_BITS)
        # segments from one counted hit to the next: lists s and s' share no frame when
        # (s - s') * S_t >= K
        self.confirm_gap = -(-self.k // self.stride) if cfg.confirm_disjoint else 1
        # ---- fixed-capacity state, allocated once ----
        self.tracks = np.zeros(cfg.capacity, dtype=TRACK_DTYPE)
        self.history = np.zeros((cfg.capacity, cfg.max_points), dtype=POINT_DTYPE)
        self.archive = np.zeros(cfg.output_capacity, dtype=TRACK_DTYPE)
        self.archive_history = np.zeros((cfg.output_capacity, cfg.max_points), dtype=POINT_DTYPE)
        self.n_archived = 0
        self.inbuf = np.zeros(cfg.max_candidates, dtype=CANDIDATE_DTYPE)
        self.n_in = 0
        self._keep = np.zeros(cfg.max_candidates, dtype=bool)
        self._claimed = np.zeros(cfg.max_candidates, dtype=bool)
        self._order = np.zeros(cfg.max_candidates, dtype=np.int32)
        self._head_row = np.zeros(cfg.max_candidates, dtype=np.int32)  # Q4 per segment
        self._head_col = np.zeros(cfg.max_candidates, dtype=np.int32)
        self._class = np.zeros(cfg.capacity, dtype=np.uint8)
        self._match = np.zeros(cfg.capacity, dtype=np.int32)
        self._order_tracks = np.zeros(cfg.capacity, dtype=np.int32)
        self._blank = np.zeros((), dtype=TRACK_DTYPE)       # written over freed records
        self.segment = -1
        self.next_id = 1
        self.stats = {"segments": 0, "candidates": 0, "suppressed": 0, "matched": 0,
                      "started": 0, "confirmed": 0, "deleted": 0, "left_image": 0,
                      "dropped_candidates": 0, "dropped_outputs": 0, "history_wrapped": 0,
                      "duplicates": 0, "peak_active": 0, "wake_suppressed": 0}

    # ---- the per-segment association ------------------------------------------------
    def step(self, candidates: np.ndarray) -> None:
        """Associate one segment's candidates (:data:`CANDIDATE_DTYPE`, at most ``max_candidates``)."""
        cfg = self.cfg
        n = check_candidate_list(candidates, cfg)
        self.inbuf[:n] = candidates
        self.n_in = n
        self.segment += 1
        s = self.segment
        self.stats["segments"] += 1
        self.stats["candidates"] += n
        self._headings(n)
        self._suppress_clusters(n)
        self._classify()
        for cls in (CLASS_CONFIRMED, CLASS_PREDICTED, CLASS_TENTATIVE):
            self._match_class(cls, n)
        for i in range(cfg.capacity):
            if self.tracks["state"][i] == FREE:
                continue
            j = int(self._match[i])
            if j >= 0:
                self._extend(i, j, s)
            else:
                self.tracks["misses"][i] = min(int(self.tracks["misses"][i]) + 1, 255)
            self._update(i, s)
        self._remove_duplicates()
        self._suppress_wake(n)
        self._start_tracks(n, s)
        self.stats["peak_active"] = max(self.stats["peak_active"], self.active())

    # ---- host-side read-out -----------------------------------------------------------
    def _readout(self, rec: np.ndarray, hist: np.ndarray, alive: bool) -> ConfirmedTrack:
        n_pts = int(rec["n_points"])
        mp = self.cfg.max_points
        if n_pts <= mp:
            points = hist[:n_pts].copy()
        else:
            start = n_pts % mp
            points = np.concatenate([hist[start:], hist[:start]])
        return ConfirmedTrack(
            id=int(rec["id"]), first_segment=int(rec["first_seg"]),
            confirm_segment=int(rec["confirm_seg"]), last_segment=int(rec["p_seg"][1]),
            hits=int(rec["hits"]), length=int(rec["p_seg"][1]) - int(rec["first_seg"]) + 1,
            alive=alive, points=points)

    def confirmed_tracks(self) -> list[ConfirmedTrack]:
        """Every track ever confirmed: finished ones (archive) then live ones, by id."""
        out = [self._readout(self.archive[a], self.archive_history[a], False)
               for a in range(self.n_archived)]
        for i in range(self.cfg.capacity):
            if int(self.tracks["state"][i]) == CONFIRMED:
                out.append(self._readout(self.tracks[i], self.history[i], True))
        return sorted(out, key=lambda tr: tr.id)

    def active(self) -> int:
        """Records in use."""
        return int(np.count_nonzero(self.tracks["state"] != FREE))
