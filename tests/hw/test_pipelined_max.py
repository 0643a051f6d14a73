"""SplitMaxTree against ``argmax_lowest_index`` (the vectors and the reference of
``helpers.max_tree_bench``): the same answers as MaxTree, two cycles per level."""

import pytest
from amaranth.back import rtlil

from dptbd.hw.max_tree import tree_levels
from dptbd.hw.pipelined_max import SplitMaxTree
from helpers.hw_harness import refused
from helpers.max_tree_bench import (
    cases, ref_max_tree, ref_signed_max_tree, rtl_max_tree, signed_cases,
)


def rtl_split_max_tree(count, value_bits, vectors, signed=False):
    """``rtl_max_tree``'s bench, run on SplitMaxTree (it reads ``latency``)."""
    return rtl_max_tree(count, value_bits, vectors, signed=signed, tree=SplitMaxTree)


@pytest.mark.parametrize("count, value_bits", [(9, 6), (25, 4), (5, 3), (2, 8)])
def test_matches_argmax_lowest_index(count, value_bits):
    vectors = list(cases(count, value_bits))
    assert rtl_split_max_tree(count, value_bits, vectors) == \
        [ref_max_tree(*v) for v in vectors]


@pytest.mark.parametrize("count, value_bits", [(9, 6), (25, 5), (5, 3)])
def test_signed_matches_argmax_lowest_index(count, value_bits):
    """Paper 000's family (``docs/arithmetic.md`` §8.4): the signed tree, split."""
    vectors = list(signed_cases(count, value_bits))
    assert rtl_split_max_tree(count, value_bits, vectors, signed=True) == \
        [ref_signed_max_tree(*v) for v in vectors]


def test_latency_is_two_stages_per_level():
    trees = [SplitMaxTree(n, 4) for n in (1, 2, 3, 9, 25)]
    for tree in trees:
        rtlil.convert(tree)             # elaborates (and silences UnusedElaboratable)
    assert [t.latency for t in trees] == [2 * tree_levels(n) for n in (1, 2, 3, 9, 25)] \
        == [0, 2, 4, 8, 10]


def test_refuses_no_candidates():
    with refused(ValueError, match=r"^count must be an integer in \[1, inf\), got 0$"):
        SplitMaxTree(0, 4)
