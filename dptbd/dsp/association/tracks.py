"""The track records' bookkeeping in the tracker (:class:`~dptbd.dsp.association.Tracker`):
extending a matched track and its new velocity, its point history, the thresholds, the
prediction and the gate for the next segment (steps (2) and (3) of 001 §3), the removal of
duplicate tracks, deletion into the output archive and new tentative tracks from the
candidates left over (``docs/association.md``).

:class:`TrackUpdates` is a base class of ``Tracker`` holding these steps; the records they
write (``tracks``, ``history``, ``archive``, ``stats``) are allocated once by ``Tracker``.
"""

from __future__ import annotations

from dptbd.dsp.records import CONFIRMED, FREE, ONE, TENTATIVE, div_round

__all__ = ["TrackUpdates"]


class TrackUpdates:
    """The track-record steps of :class:`~dptbd.dsp.association.Tracker` (see the module
    docstring)."""

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
