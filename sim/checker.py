"""The one in-order checker every scoreboard uses: monitor -> model -> checker.

As in cocotb's ``examples/matrix_multiplier``: a monitor hands each word it sees on an
output stream to :meth:`InOrderChecker.receive`; the model computed beforehand the words
that must come out, in order; the checker compares them one by one, stops at the first
mismatch and keeps it (with its position in the stream) for the report. Words beyond the
expected stream count as a failure too.

A scoreboard subclasses :class:`InOrderChecker` and supplies what depends on the stream:
:meth:`~InOrderChecker.compare` (the mismatch, located by frame, row, column and field for
``states``, by segment, record and field for ``candidates``), :meth:`~InOrderChecker.matched`
(progress callbacks) and the three summaries of :meth:`~InOrderChecker.report`.

Plain numpy and Python (no cocotb import), so that pytest can test it without a simulator.
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np

__all__ = ["InOrderChecker", "differing_fields", "describe_field_mismatch"]


def differing_fields(names: Sequence[str], got_word: int, want_word: int, got: dict,
                     want: dict) -> tuple[str, ...]:
    """The fields of ``names`` (in that order) whose values differ between ``got`` and
    ``want``; ``("payload",)`` if none does (bits outside every field), in which case both
    dicts gain a ``payload`` entry with the whole words."""
    fields = tuple(name for name in names if got[name] != want[name])
    if fields:
        return fields
    got["payload"], want["payload"] = int(got_word), int(want_word)
    return ("payload",)


def describe_field_mismatch(fields: Sequence[str], got: dict, want: dict) -> str:
    """``field F: expected E, got G (differing fields [...]; expected {...}, got {...})``
    for the first differing field ``F``."""
    first = fields[0]
    return (f"field {first}: expected {want[first]}, got {got[first]} (differing fields "
            f"{list(fields)}; expected {want}, got {got})")


class InOrderChecker:
    """Compares received words, in order, with the expected ones; stops at the first
    mismatch.

    Parameters
    ----------
    expected : numpy.ndarray
        The expected words in stream order (one dimension; a scoreboard flattens its own).

    Attributes
    ----------
    count : int
        Words received and matched.
    mismatch : object or None
        What :meth:`compare` returned for the first differing word.
    extra : int
        Words received beyond the expected stream (the checker stops at the first).
    """

    #: What a word is called in :meth:`report` ("1 output word(s) beyond …").
    unit = "word"

    def __init__(self, expected: np.ndarray):
        self._expected = expected
        self.count = 0
        self.mismatch: Any = None
        self.extra = 0

    # ---- what a scoreboard supplies -----------------------------------------------------
    def compare(self, index: int, got: int, want: int) -> Any:
        """The mismatch of word ``index`` (``got`` differs from ``want``), for the report."""
        raise NotImplementedError

    def matched(self, start: int, stop: int) -> None:
        """Called after words ``start`` … ``stop - 1`` matched (progress callbacks)."""

    def expected_summary(self) -> str:
        """The expected stream in the stream's own terms, e.g. ``4 frames``."""
        return f"{self.total} {self.unit}s"

    def received_summary(self) -> str:
        """Appended to ``incomplete: c of t words received``, e.g. `` (2 of 3 lists)``."""
        return ""

    def exact_summary(self) -> str:
        """What ``bit-exact:`` is followed by once every word matched."""
        return f"{self.count} words"

    # ---- the checker --------------------------------------------------------------------
    @property
    def total(self) -> int:
        """Number of words expected."""
        return len(self._expected)

    @property
    def done(self) -> bool:
        """Every expected word arrived and matched, and nothing more came."""
        return self.mismatch is None and self.extra == 0 and self.count == self.total

    @property
    def failed(self) -> bool:
        """A word differed or came beyond the end of the expected stream."""
        return self.mismatch is not None or self.extra > 0

    def receive(self, word: int) -> bool:
        """Check the next received word; False once anything went wrong."""
        if self.failed:
            return False
        if self.count >= self.total:
            self.extra += 1
            return False
        want = int(self._expected[self.count])
        if int(word) != want:
            self.mismatch = self.compare(self.count, int(word), want)
            return False
        self.count += 1
        self.matched(self.count - 1, self.count)
        return True

    def receive_array(self, words: np.ndarray) -> bool:
        """Check a block of consecutive received words at once (numpy; the same outcome as
        :meth:`receive` on each in turn): stops at the first mismatch or extra word."""
        if self.failed:
            return False
        got = np.asarray(words).ravel()
        want = self._expected[self.count:self.count + len(got)]
        take = len(want)
        bad = np.flatnonzero(got[:take].astype(want.dtype) != want)
        good = take if bad.size == 0 else int(bad[0])
        before = self.count
        self.count += good
        if good:
            self.matched(before, self.count)
        if bad.size:
            return self.receive(int(got[good]))
        if len(got) > take:
            self.extra += 1          # receive() stops at the first extra word
            return False
        return True

    def report(self) -> str:
        """One line: bit-exact, incomplete, extra words, or the first mismatch."""
        if self.mismatch is not None:
            return str(self.mismatch)
        if self.extra:
            return (f"{self.extra} {self.unit}(s) beyond the {self.total} expected "
                    f"({self.expected_summary()})")
        if self.count < self.total:
            return (f"incomplete: {self.count} of {self.total} words received"
                    f"{self.received_summary()}, all bit-exact")
        return f"bit-exact: {self.exact_summary()}"
