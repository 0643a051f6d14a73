"""``adder_tree``: the sum of its leaves, neighbouring pairs first, as few adders deep as a
binary tree allows (``BankedHistogram``'s merge of its banks)."""

import pytest

from dptbd.hw.adder_tree import adder_tree


class _Node:
    """A term that records its value and how many adders lie in series above its leaves."""

    def __init__(self, value, depth=0, text=None):
        self.value, self.depth, self.text = value, depth, text or str(value)

    def __add__(self, other):
        return _Node(self.value + other.value, max(self.depth, other.depth) + 1,
                     f"({self.text} + {other.text})")


@pytest.mark.parametrize("count, depth, text", [
    (1, 0, "1"),
    (2, 1, "(1 + 2)"),
    (3, 2, "((1 + 2) + 3)"),
    (4, 2, "((1 + 2) + (3 + 4))"),
    (5, 3, "(((1 + 2) + (3 + 4)) + 5)"),
])
def test_the_tree_sums_neighbouring_pairs_first(count, depth, text):
    root = adder_tree([_Node(v) for v in range(1, count + 1)])
    assert (root.value, root.depth, root.text) == (count * (count + 1) // 2, depth, text)
