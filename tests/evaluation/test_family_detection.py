"""``dptbd.evaluation.family_detection``: variants, their configurations, the counts."""

from __future__ import annotations

import re

import pytest

from dptbd.errors import DptbdError
from dptbd.evaluation import family_detection as fd
from dptbd.evaluation.table1 import table1_config


def test_segment_variant_is_table1s_configuration_with_stride_k():
    cfg = fd.variant_config(fd.segments(8))
    assert cfg == table1_config(8, 8) and cfg.is_paper001_datapath


def test_recursive_variant_configuration():
    cfg = fd.variant_config(fd.recursive(0.85))
    assert cfg.recursive and cfg.forgetting_code == 218 and cfg.energy_bits == 20
    assert not cfg.is_paper001_datapath


@pytest.mark.parametrize("call, message", [
    (lambda: fd.recursive(1.0), "forgetting must be a finite real number in (0, 1), got 1.0"),
    (lambda: fd.recursive(0.0), "forgetting must be a finite real number in (0, 1), got 0.0"),
    (lambda: fd.recursive(0.5, warmup=100), "warmup must be an integer in [0, 99], got 100"),
    (lambda: fd.segments(0), "segment_frames must be an integer in [1, 100], got 0"),
])
def test_refusals(call, message):
    with pytest.raises(DptbdError, match="^" + re.escape(message) + "$"):
        call()


@pytest.mark.parametrize("variant, maps", [(fd.segments(6), 16), (fd.recursive(0.8, warmup=7), 93)])
def test_counts_one_map_per_segment_or_per_frame(variant, maps):
    c = fd.variant_counts(variant, 2.3, (1.0, 1.0), trials=1, seed=5, size=32)
    assert c.frames == maps
    assert c.opportunities <= maps and 0 <= c.detections <= c.opportunities
    # n = count_for_rate(0.2 %, 32 x 32) = 2 candidates per map at most
    assert c.false_points <= 2 * maps
