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
in :mod:`dptbd.dsp.association.config`; their names are importable from here too.
"""

from __future__ import annotations

import math

import numpy as np

from dptbd.dsp.association.config import AssociationConfig, AssociationError
from dptbd.dsp import records
from dptbd.dsp.records import (CANDIDATE_DTYPE, CONFIRMED, FREE, ONE, POINT_DTYPE, Q_BITS,
                               RATIO_BITS, RATIO_ONE, TENTATIVE, TRACK_DTYPE, ConfirmedTrack,
                               div_round, make_candidates, trim_to_count)

# the records stay importable from here (they lived in this module before the split)
__all__ = [*records.__all__, "AssociationConfig", "AssociationError", "Tracker",
           "check_candidate_list"]

#: Matching classes (priority order).
_CLASS_CONFIRMED, _CLASS_PREDICTED, _CLASS_TENTATIVE, _CLASS_NONE = 0, 1, 2, 3


def _q(x: float, bits: int) -> int:
    return int(math.floor(x * (1 << bits) + 0.5))


def check_candidate_list(candidates: np.ndarray, cfg: AssociationConfig) -> int:
    """The length of one segment's candidate list, refused (:class:`AssociationError`) when
    it is longer than the input buffer or not :data:`CANDIDATE_DTYPE` records; every
    implementation of the tracker (this model, the C firmware's binding) checks with it."""
    n = len(candidates)
    if n > cfg.max_candidates:
        raise AssociationError(f"{n} candidates in one segment but the input buffer holds "
                               f"max_candidates={cfg.max_candidates}")
    if n and np.asarray(candidates).dtype != CANDIDATE_DTYPE:
        raise AssociationError(f"candidates must be CANDIDATE_DTYPE records "
                               f"(make_candidates), got dtype {np.asarray(candidates).dtype}")
    return n


class Tracker:
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
        for cls in (_CLASS_CONFIRMED, _CLASS_PREDICTED, _CLASS_TENTATIVE):
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

    def _headings(self, n: int) -> None:
        """Heading of each candidate, Q4 pixels per segment (S_t frames)."""
        for j in range(n):
            c = self.inbuf[j]
            if c["path"] and self.k > 1:
                hr = div_round((int(c["row"]) - int(c["row0"])) * ONE * self.stride, self.k - 1)
                hc = div_round((int(c["col"]) - int(c["col0"])) * ONE * self.stride, self.k - 1)
            elif int(c["direction"]) < len(self._moves):
                dy, dx = self._moves[int(c["direction"])]
                hr, hc = dy * ONE * self.stride, dx * ONE * self.stride
            else:
                hr = hc = 0
            self._head_row[j], self._head_col[j] = hr, hc

    def _suppress_clusters(self, n: int) -> None:
        """Keep a candidate unless a stronger one (ties: earlier) is within ``merge_radius``."""
        rad = self.cfg.merge_radius
        rows, cols, energy = self.inbuf["row"], self.inbuf["col"], self.inbuf["energy"]
        for j in range(n):
            keep = True
            if rad > 0:
                rj, cj, ej = int(rows[j]), int(cols[j]), int(energy[j])
                for i in range(n):
                    if i == j:
                        continue
                    if abs(int(rows[i]) - rj) <= rad and abs(int(cols[i]) - cj) <= rad:
                        ei = int(energy[i])
                        if ei > ej or (ei == ej and i < j):
                            keep = False
                            break
            self._keep[j] = keep
            self._claimed[j] = False
            if not keep:
                self.stats["suppressed"] += 1

    def _ratio_at_least(self, hits: int, length: int, ratio_q8: int) -> bool:
        return hits * RATIO_ONE >= ratio_q8 * length

    def _classify(self) -> None:
        t = self.tracks
        for i in range(self.cfg.capacity):
            self._match[i] = -1
            state = int(t["state"][i])
            if state == FREE:
                self._class[i] = _CLASS_NONE
            elif state == CONFIRMED:
                self._class[i] = _CLASS_CONFIRMED
            elif self._in_prediction_space(i):
                self._class[i] = _CLASS_PREDICTED
            else:
                self._class[i] = _CLASS_TENTATIVE

    def _in_prediction_space(self, i: int) -> bool:
        t = self.tracks
        hits, length = int(t["hits"][i]), int(t["length"][i])
        return (int(t["state"][i]) == CONFIRMED
                or (hits >= self.cfg.predict_hits
                    and self._ratio_at_least(hits, length, self.predict_ratio)))

    def _cost(self, i: int, j: int) -> int:
        """Match cost of candidate j for track i (Q8), or -1 outside the gate / reversed."""
        t = self.tracks
        dr = int(self.inbuf["row"][j]) * ONE - int(t["pred_row"][i])
        dc = int(self.inbuf["col"][j]) * ONE - int(t["pred_col"][i])
        gate = int(t["gate"][i])
        d2 = dr * dr + dc * dc
        if d2 > gate * gate:
            return self._link_cost(i, j)
        cost = (d2 * RATIO_ONE) // max(gate * gate, 1)
        vr, vc = int(t["v_row"][i]), int(t["v_col"][i])
        hr, hc = int(self._head_row[j]), int(self._head_col[j])
        v2, h2 = vr * vr + vc * vc, hr * hr + hc * hc
        hmin2 = self.heading_min * self.heading_min
        if v2 >= hmin2 and h2 >= hmin2 and v2 > 0 and h2 > 0:
            dot = vr * hr + vc * hc
            if self.cfg.reject_reversed and dot < 0:
                return -1
            norm = math.isqrt(v2 * h2)          # |v||h|, integer square root
            if norm > 0:
                # (1 - cos theta) / 2 in [0, 1], scaled by the heading weight (Q8)
                cost += (self.heading_weight * max(norm - dot, 0)) // (2 * norm)
        return cost

    def _link_cost(self, i: int, j: int) -> int:
        """Cost of a candidate outside the prediction gate whose DP path starts where track i
        ended (a manoeuvre), or -1.

        Only for tracks in the prediction space detected in the previous segment, with
        back-to-back segments (S_t = K: the path's first frame follows the track's newest
        point by one frame) and a backtracked path. Ranked after every candidate inside the
        prediction gate: ``RATIO_ONE * (1 + heading_weight) + link distance cost``.
        """
        t = self.tracks
        if (self.link_gate <= 0 or self.stride != self.k or not self.inbuf["path"][j]
                or self._class[i] > _CLASS_PREDICTED or int(t["p_seg"][i][1]) != self.segment - 1):
            return -1
        lr = int(self.inbuf["row0"][j]) * ONE - int(t["p_row"][i][1])
        lc = int(self.inbuf["col0"][j]) * ONE - int(t["p_col"][i][1])
        l2 = lr * lr + lc * lc
        if l2 > self.link_gate * self.link_gate:
            return -1
        return RATIO_ONE + self.heading_weight + (l2 * RATIO_ONE) // (self.link_gate * self.link_gate)

    def _match_class(self, cls: int, n: int) -> None:
        """Each track of class ``cls``, the best-supported first (more hits, then the older id),
        takes its lowest-cost unclaimed candidate."""
        m = 0
        for i in range(self.cfg.capacity):            # insertion sort by evidence
            if self._class[i] != cls:
                continue
            k = m
            while k > 0 and self._stronger(i, int(self._order_tracks[k - 1])):
                self._order_tracks[k] = self._order_tracks[k - 1]
                k -= 1
            self._order_tracks[k] = i
            m += 1
        for x in range(m):
            i = int(self._order_tracks[x])
            best, best_cost = -1, -1
            for j in range(n):
                if not self._keep[j] or self._claimed[j]:
                    continue
                cost = self._cost(i, j)
                if cost >= 0 and (best < 0 or cost < best_cost):
                    best, best_cost = j, cost
            if best >= 0:
                self._claimed[best] = True
                self._match[i] = best
                self.stats["matched"] += 1

    def _extend(self, i: int, j: int, s: int) -> None:
        """Extend track i to candidate j of segment s; new velocity (prediction step (2))."""
        t = self.tracks
        c = self.inbuf[j]
        row, col = int(c["row"]) * ONE, int(c["col"]) * ONE
        hits = int(t["hits"][i])
        seg1, row1, col1 = int(t["p_seg"][i][1]), int(t["p_row"][i][1]), int(t["p_col"][i][1])
        gap1 = s - seg1
        v1r, v1c = div_round(row - row1, gap1), div_round(col - col1, gap1)
        if hits >= 2:
            seg0, row0, col0 = int(t["p_seg"][i][0]), int(t["p_row"][i][0]), int(t["p_col"][i][0])
            gap2 = seg1 - seg0
            v2r, v2c = div_round(row1 - row0, gap2), div_round(col1 - col0, gap2)
            if max(abs(v1r - v2r), abs(v1c - v2c)) > self.manoeuvre:
                vr, vc = v1r, v1c                      # manoeuvre: follow the newest step
            else:
                vr, vc = div_round(v1r + v2r, 2), div_round(v1c + v2c, 2)
        else:
            vr, vc = v1r, v1c
        t["p_seg"][i][0], t["p_row"][i][0], t["p_col"][i][0] = seg1, row1, col1
        t["p_seg"][i][1], t["p_row"][i][1], t["p_col"][i][1] = s, row, col
        t["v_row"][i], t["v_col"][i] = vr, vc
        t["hits"][i] = min(hits + 1, 65535)
        if s - int(t["count_seg"][i]) >= self.confirm_gap:
            t["counted"][i] = min(int(t["counted"][i]) + 1, 65535)
            t["count_seg"][i] = s
        t["misses"][i] = 0
        self._record_point(i, j, s)

    def _record_point(self, i: int, j: int, s: int) -> None:
        t = self.tracks
        n_pts = int(t["n_points"][i])
        slot = n_pts % self.cfg.max_points
        if n_pts >= self.cfg.max_points:
            self.stats["history_wrapped"] += 1
        c = self.inbuf[j]
        h = self.history[i, slot]
        h["seg"], h["row"], h["col"], h["energy"] = s, c["row"], c["col"], c["energy"]
        h["row0"], h["col0"], h["path"] = c["row0"], c["col0"], c["path"]
        t["n_points"][i] = n_pts + 1

    def _update(self, i: int, s: int) -> None:
        """Thresholds (step (3)), then the predicted point and gate for segment s + 1."""
        cfg, t = self.cfg, self.tracks
        length = s - int(t["first_seg"][i]) + 1
        t["length"][i] = min(length, 65535)
        hits, misses = int(t["hits"][i]), int(t["misses"][i])
        if (not self._ratio_at_least(hits, length, self.delete_ratio)) or misses > cfg.max_misses:
            self._delete(i)
            return
        if (int(t["state"][i]) == TENTATIVE and int(t["counted"][i]) >= cfg.confirm_hits
                and self._ratio_at_least(hits, length, self.confirm_ratio)):
            t["state"][i] = CONFIRMED
            t["confirm_seg"][i] = s
            self.stats["confirmed"] += 1
        ahead = s + 1 - int(t["p_seg"][i][1])
        pr = int(t["p_row"][i][1]) + int(t["v_row"][i]) * ahead
        pc = int(t["p_col"][i][1]) + int(t["v_col"][i]) * ahead
        if self._in_prediction_space(i):
            grow = div_round(self.gate_growth * min(length, cfg.gate_growth_segments) * hits, length)
            gate = self.gate_base + grow + self.gate_miss * misses
        else:
            gate = self.seed_gate + self.gate_miss * misses
        gate = min(gate, self.gate_max)
        if (pr < -gate or pc < -gate or pr > (self.height - 1) * ONE + gate
                or pc > (self.width - 1) * ONE + gate):
            self.stats["left_image"] += 1
            self._delete(i)
            return
        t["pred_row"][i], t["pred_col"][i], t["gate"][i] = pr, pc, gate

    def _stronger(self, a: int, b: int) -> bool:
        """Track a outranks track b: class priority, then more hits, then the older id."""
        t = self.tracks
        ca, cb = int(self._class[a]), int(self._class[b])
        if ca != cb:
            return ca < cb
        ha, hb = int(t["hits"][a]), int(t["hits"][b])
        if ha != hb:
            return ha > hb
        return int(t["id"][a]) < int(t["id"][b])

    def _remove_duplicates(self) -> None:
        """Delete the weaker of two tracks that matched close points with close velocities."""
        rad = self.cfg.duplicate_radius * ONE
        if rad <= 0:
            return
        t = self.tracks
        m = 0
        for i in range(self.cfg.capacity):        # the tracks extended in this segment
            if self._match[i] >= 0 and int(t["state"][i]) != FREE:
                self._order_tracks[m] = i
                m += 1
        for x in range(m):
            a = int(self._order_tracks[x])
            if int(t["state"][a]) == FREE:
                continue
            for y in range(x + 1, m):
                b = int(self._order_tracks[y])
                if int(t["state"][b]) == FREE:
                    continue
                if (abs(int(t["p_row"][a][1]) - int(t["p_row"][b][1])) <= rad
                        and abs(int(t["p_col"][a][1]) - int(t["p_col"][b][1])) <= rad
                        and abs(int(t["v_row"][a]) - int(t["v_row"][b])) <= self.manoeuvre
                        and abs(int(t["v_col"][a]) - int(t["v_col"][b])) <= self.manoeuvre):
                    weaker = b if self._stronger(a, b) else a
                    self.stats["duplicates"] += 1
                    self._delete(weaker)
                    if weaker == a:
                        break

    def _suppress_wake(self, n: int) -> None:
        """Drop each candidate left over within ``wake_radius`` (Chebyshev) of a live track's
        recent path: its newest ``wake_points`` history points and their path starts."""
        rad = self.cfg.wake_radius
        if rad <= 0:
            return
        t, mp = self.tracks, self.cfg.max_points
        for j in range(n):
            if not self._keep[j] or self._claimed[j]:
                continue
            rj, cj = int(self.inbuf["row"][j]), int(self.inbuf["col"][j])
            near = False
            for i in range(self.cfg.capacity):
                if int(t["state"][i]) == FREE:
                    continue
                n_pts = int(t["n_points"][i])
                for q in range(min(self.cfg.wake_points, n_pts, mp)):
                    h = self.history[i, (n_pts - 1 - q) % mp]
                    if ((abs(int(h["row"]) - rj) <= rad and abs(int(h["col"]) - cj) <= rad)
                            or (h["path"] and abs(int(h["row0"]) - rj) <= rad
                                and abs(int(h["col0"]) - cj) <= rad)):
                        near = True
                        break
                if near:
                    break
            if near:
                self._keep[j] = False
                self.stats["wake_suppressed"] += 1

    def _delete(self, i: int) -> None:
        """Free record i; a confirmed track goes to the output archive first."""
        t = self.tracks
        if int(t["state"][i]) == CONFIRMED:
            if self.n_archived < self.cfg.output_capacity:
                self.archive[self.n_archived] = t[i]
                self.archive_history[self.n_archived] = self.history[i]
                self.n_archived += 1
            else:
                self.stats["dropped_outputs"] += 1
        t[i] = self._blank
        self.stats["deleted"] += 1

    def _start_tracks(self, n: int, s: int) -> None:
        """New tentative tracks from the candidates left over, strongest first."""
        m = 0
        for j in range(n):                         # insertion sort by decreasing E
            if not self._keep[j] or self._claimed[j]:
                continue
            e = int(self.inbuf["energy"][j])
            k = m
            while k > 0 and int(self.inbuf["energy"][self._order[k - 1]]) < e:
                self._order[k] = self._order[k - 1]
                k -= 1
            self._order[k] = j
            m += 1
        free = 0
        t = self.tracks
        for k in range(m):
            j = int(self._order[k])
            while free < self.cfg.capacity and int(t["state"][free]) != FREE:
                free += 1
            if free == self.cfg.capacity:
                self.stats["dropped_candidates"] += m - k
                return
            i = free
            row, col = int(self.inbuf["row"][j]) * ONE, int(self.inbuf["col"][j]) * ONE
            t[i] = self._blank
            t["state"][i] = TENTATIVE
            t["id"][i] = self.next_id
            self.next_id += 1
            t["first_seg"][i], t["confirm_seg"][i] = s, -1
            t["p_seg"][i][1], t["p_row"][i][1], t["p_col"][i][1] = s, row, col
            t["p_seg"][i][0], t["p_row"][i][0], t["p_col"][i][0] = s, row, col
            t["v_row"][i], t["v_col"][i] = self._head_row[j], self._head_col[j]
            t["length"][i] = t["hits"][i] = t["counted"][i] = 1
            t["count_seg"][i] = s
            self._record_point(i, j, s)
            self.stats["started"] += 1
            if self.cfg.confirm_hits <= 1:          # a one-point output threshold
                t["state"][i] = CONFIRMED
                t["confirm_seg"][i] = s
                self.stats["confirmed"] += 1
            t["pred_row"][i] = row + int(self._head_row[j])
            t["pred_col"][i] = col + int(self._head_col[j])
            t["gate"][i] = min(self.seed_gate, self.gate_max)

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
