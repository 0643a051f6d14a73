"""The matching of the tracker (:class:`~dptbd.dsp.association.Tracker`), step (1) of 001 §3:
each track's class (confirmed, in the prediction space, tentative), its priority, the cost of
a candidate inside its gate (distance and heading) or on its link gate, and the greedy
assignment in priority order (``docs/association.md``).

:class:`Matching` is a base class of ``Tracker`` holding these steps; the state they read
and write (``tracks``, ``_class``, ``_match``, ``_order_tracks``, the integer codes) is
allocated once by ``Tracker``.
"""

from __future__ import annotations

import math

from dptbd.dsp.records import CONFIRMED, FREE, ONE, RATIO_ONE

__all__ = ["Matching", "CLASS_CONFIRMED", "CLASS_PREDICTED", "CLASS_TENTATIVE", "CLASS_NONE"]

#: Matching classes (priority order).
CLASS_CONFIRMED, CLASS_PREDICTED, CLASS_TENTATIVE, CLASS_NONE = 0, 1, 2, 3


class Matching:
    """The matching steps of :class:`~dptbd.dsp.association.Tracker` (see the module
    docstring)."""

    def _ratio_at_least(self, hits: int, length: int, ratio_q8: int) -> bool:
        return hits * RATIO_ONE >= ratio_q8 * length

    def _classify(self) -> None:
        t = self.tracks
        for i in range(self.cfg.capacity):
            self._match[i] = -1
            state = int(t["state"][i])
            if state == FREE:
                self._class[i] = CLASS_NONE
            elif state == CONFIRMED:
                self._class[i] = CLASS_CONFIRMED
            elif self._in_prediction_space(i):
                self._class[i] = CLASS_PREDICTED
            else:
                self._class[i] = CLASS_TENTATIVE

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
                or self._class[i] > CLASS_PREDICTED or int(t["p_seg"][i][1]) != self.segment - 1):
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
