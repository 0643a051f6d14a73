"""Hypothesis settings, configurations and frame strategies shared by the golden model's
property tests (``test_fixed.py``, ``test_operators.py``, ``test_segments.py``)."""

from __future__ import annotations

import warnings

import numpy as np
from hypothesis import HealthCheck, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from dptbd.config import DPConfig, EnergyWidthWarning

SETTINGS = settings(max_examples=100, deadline=None, database=None,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
FAST = settings(SETTINGS, max_examples=300)


def make_cfg(**kw):
    """A DPConfig built with EnergyWidthWarning silenced (tests that care check it)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        return DPConfig(**kw)


def no_saturation_cfg(**kw):
    """A DPConfig whose energy_bits is at least energy_bits_needed: must not warn."""
    probe = make_cfg(**kw)
    kw["energy_bits"] = probe.energy_bits_needed
    with warnings.catch_warnings():
        warnings.simplefilter("error", EnergyWidthWarning)
        return DPConfig(**kw)


@st.composite
def shapes(draw, max_k=4):
    return dict(height=draw(st.integers(3, 6)), width=draw(st.integers(3, 6)),
                radius=draw(st.sampled_from([1, 2])), segment_frames=draw(st.integers(1, max_k)))


def frames_for(draw, shape, high, n_frames=None):
    n_frames = shape["segment_frames"] if n_frames is None else n_frames
    return draw(arrays(np.int64, (n_frames, shape["height"], shape["width"]),
                       elements=st.integers(0, high)))
