"""Max/argmax tree against ``argmax_lowest_index``: ties to the lowest index, invalid never wins.

The vectors (``cases()``), the golden model's answers (``ref_max_tree``) and the gateware's
(``rtl_max_tree``), one per vector, are in ``helpers.max_tree_bench`` (shared with
``test_pipelined_max.py``).
"""

import pytest

from dptbd.hw.max_tree import tree_levels
from helpers.max_tree_bench import (
    cases, ref_max_tree, ref_signed_max_tree, rtl_max_tree, signed_cases,
)


@pytest.mark.parametrize("count, value_bits", [(9, 6), (25, 4), (5, 3), (2, 8)])
def test_matches_argmax_lowest_index(count, value_bits):
    vectors = list(cases(count, value_bits))
    assert rtl_max_tree(count, value_bits, vectors) == [ref_max_tree(*v) for v in vectors]


def test_latency_is_ceil_log2():
    assert [tree_levels(n) for n in (1, 2, 3, 4, 5, 9, 16, 17, 25)] == [0, 1, 2, 2, 3, 4, 4, 5, 5]


@pytest.mark.parametrize("count, value_bits", [(9, 7), (25, 5), (5, 2), (2, 9)])
def test_signed_matches_argmax_lowest_index(count, value_bits):
    vectors = list(signed_cases(count, value_bits))
    got = rtl_max_tree(count, value_bits, vectors, signed=True)
    assert got == [ref_signed_max_tree(*v) for v in vectors]
