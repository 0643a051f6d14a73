"""What the tracker (:class:`~dptbd.dsp.association.Tracker`) does to one segment's
candidates around the matching: the check of the list against the input buffer, each
candidate's heading, the suppression of a cluster to its strongest point and, after
matching, the wake suppression (``docs/association.md``).

:class:`CandidateSteps` is a base class of ``Tracker`` holding these steps; the state they
read and write (``inbuf``, ``_keep``, ``_claimed``, ``_head_row``, ``_head_col``, ``stats``)
is allocated once by ``Tracker``.
"""

from __future__ import annotations

import numpy as np

from dptbd.dsp.association.config import AssociationConfig, AssociationError
from dptbd.dsp.records import CANDIDATE_DTYPE, FREE, ONE, div_round

__all__ = ["CandidateSteps", "check_candidate_list"]


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


class CandidateSteps:
    """The candidate steps of :class:`~dptbd.dsp.association.Tracker` (see the module
    docstring)."""

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
