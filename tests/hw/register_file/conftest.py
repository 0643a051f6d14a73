"""Fixtures of the ``RegisterFile`` tests."""

import pytest

from helpers.seg_harness import make_config


@pytest.fixture
def cfg():
    """An 8 x 6 frame, 5 candidates per list, 4 histogram bits."""
    return make_config(width=8, height=6, candidate_count=5, histogram_bits=4)
