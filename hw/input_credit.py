"""The DP core's input credit: accept a pixel only when the output FIFO is sure to have room.

Every accepted pixel comes out of the pipeline a fixed number of cycles later and must find
a place in the output FIFO of ``depth`` words, whatever the consumer does meanwhile. The
credit counts the pixels *committed*: accepted but not yet handed out on the output stream
(those in flight plus those in the FIFO). The decision is taken a cycle early: ``ready`` in
cycle t + 1 iff committed(t) < depth - 1. As committed(t + 1) <= committed(t) + 1 and
``ready`` is a register, committed never exceeds ``depth``, and ``ready`` closes no loop
through the acceptance net. It costs one FIFO word: a FIFO of latency + 2 words sustains one
pixel per clock without back-pressure.

:class:`InputCredit` keeps committed in a
:class:`~dptbd.hw.thermometer_counter.ThermometerCounter` of ``depth`` levels, so
"committed(t) < depth - 1" is a register of its own (no adder, no comparator behind it),
and ``ready`` copies it.
"""

from __future__ import annotations

from amaranth.hdl import Module
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

from dptbd.errors import check_int
from dptbd.hw.thermometer_counter import ThermometerCounter

__all__ = ["InputCredit"]


class InputCredit(wiring.Component):
    """``ready`` for a pipeline in front of a FIFO of ``depth`` words (see the module doc).

    Parameters
    ----------
    depth : int
        Words of the FIFO, in [3, inf) (a ``SyncFIFOBuffered`` of 2 words refuses a word
        while its one memory word moves to the output register, so committed <= 2 does not
        guarantee room; from 3 words on it does).

    Members
    -------
    accept : In(1)
        A pixel is accepted in this cycle (``valid & ready`` of the input stream).
    handed_out : In(1)
        A word leaves the FIFO in this cycle (``valid & ready`` of the output stream).
    ready : Out(1)
        Register: ready in cycle t + 1 iff committed(t) < depth - 1. Low in the cycle after
        a reset, high from the next.
    """

    def __init__(self, depth: int):
        try:
            self._depth = check_int("depth", depth, 3)
        except ValueError:
            self._MustUse__silence = True      # refused: never meant to be elaborated
            raise
        super().__init__({"accept": In(1), "handed_out": In(1), "ready": Out(1)})

    @property
    def depth(self) -> int:
        """Words of the FIFO."""
        return self._depth

    def elaborate(self, platform):
        m = Module()
        m.submodules.committed = committed = ThermometerCounter(self._depth)
        m.d.comb += [
            committed.up.eq(self.accept),
            committed.down.eq(self.handed_out),
        ]
        m.d.sync += self.ready.eq(~committed.at_least[self._depth - 2])
        return m
