"""The generic in-order checker: receive word by word or in blocks, first mismatch kept with
its position, extra and missing words, the report's three summaries."""

from __future__ import annotations

import numpy as np
import pytest

from dptbd.sim.checker import InOrderChecker, describe_field_mismatch, differing_fields


class Bytes(InOrderChecker):
    """A checker of 8-bit words split into two 4-bit fields ``low`` and ``high``."""

    def __init__(self, expected, words_per_line=4):
        super().__init__(np.asarray(expected, dtype=np.uint64))
        self.lines: list[int] = []
        self.per_line = words_per_line

    def compare(self, index, got, want):
        split = {"low": lambda w: w & 15, "high": lambda w: w >> 4}
        got_f = {k: f(got) for k, f in split.items()}
        want_f = {k: f(want) for k, f in split.items()}
        return (index, differing_fields(("low", "high"), got, want, got_f, want_f), got_f,
                want_f)

    def matched(self, start, stop):
        self.lines += range(start // self.per_line, stop // self.per_line)


def outcome(checker):
    return checker.count, checker.mismatch, checker.extra, checker.done, checker.failed


def test_every_word_in_order_is_bit_exact():
    checker = Bytes(range(8))
    assert all(checker.receive(w) for w in range(8))
    assert checker.done and not checker.failed
    assert checker.lines == [0, 1]
    assert checker.report() == "bit-exact: 8 words"


def test_the_first_mismatch_is_kept_with_its_position_and_nothing_after_it_counts():
    checker = Bytes([0x12, 0x34, 0x56])
    assert checker.receive(0x12)
    assert not checker.receive(0x38)
    assert checker.mismatch == (1, ("low",), {"low": 8, "high": 3}, {"low": 4, "high": 3})
    assert not checker.receive(0x56)
    assert checker.count == 1 and checker.failed and not checker.done


def test_missing_and_extra_words():
    checker = Bytes([1, 2])
    checker.receive(1)
    assert checker.report() == "incomplete: 1 of 2 words received, all bit-exact"
    checker.receive(2)
    assert not checker.receive(3)
    assert checker.extra == 1 and checker.failed
    assert checker.report() == "1 word(s) beyond the 2 expected (2 words)"


@pytest.mark.parametrize("got, cuts", [
    (list(range(10)), [3, 4]),                  # exact
    ([0, 1, 2, 3, 4, 99, 6, 7, 8, 9], [5]),     # a flip at a block's first word
    ([0, 1, 2, 99, 4], [2]),                    # a flip inside a block
    (list(range(7)), [1, 6]),                   # missing words
    (list(range(12)), [10]),                    # extra words
    ([], []),
])
def test_blocks_have_the_outcome_of_word_by_word(got, cuts):
    one, blocks = Bytes(range(10)), Bytes(range(10))
    for w in got:
        if not one.receive(w):
            break
    for block in np.split(np.array(got, dtype=np.uint64), cuts):
        blocks.receive_array(block)
    assert outcome(blocks) == outcome(one)
    assert blocks.lines == one.lines
    assert blocks.report() == one.report()


def test_a_failed_checker_takes_no_block():
    checker = Bytes([1, 2, 3])
    assert not checker.receive(7)
    assert not checker.receive_array(np.array([2, 3], dtype=np.uint64))
    assert checker.count == 0


def test_bits_outside_every_field_are_reported_as_the_payload():
    got, want = {"a": 1}, {"a": 1}
    assert differing_fields(("a",), 0x101, 0x001, got, want) == ("payload",)
    assert got == {"a": 1, "payload": 0x101} and want == {"a": 1, "payload": 1}


def test_field_mismatch_names_the_first_field_and_all_values():
    text = describe_field_mismatch(("b", "a"), {"a": 1, "b": 2}, {"a": 0, "b": 3})
    assert text == ("field b: expected 3, got 2 (differing fields ['b', 'a']; expected "
                    "{'a': 0, 'b': 3}, got {'a': 1, 'b': 2})")


def test_a_checker_must_say_how_words_compare():
    checker = InOrderChecker(np.array([1], dtype=np.uint64))
    with pytest.raises(NotImplementedError, match=r"^$"):
        checker.receive(2)
