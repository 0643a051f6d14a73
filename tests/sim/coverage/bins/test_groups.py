"""The bins' vocabulary (:mod:`dptbd.sim.coverage.bins.groups`): the stall bands."""

from __future__ import annotations

from dptbd.sim.coverage import bins


def test_stall_bands_have_their_edges():
    assert [bins.band(p) for p in (0.0, 1e-9, 0.3499, 0.35, 0.7, 0.999)] == \
        ["none", "light", "light", "heavy", "heavy", "heavy"]

