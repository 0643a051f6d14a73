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

``copies=n`` gives ``ready`` ``n`` bits, each a register of its own holding the same value
in every cycle, so that each group of far loads (the credit's own count, the input port,
the controller, the line buffer) has a copy placed beside it instead of one register
routed across the chip (the ECP5 build's, ``credit_ready="per_load"``). Synthesis merges
registers whose next values are the same function of the same signals, so each copy's is
a different one that is equal on every thermometer code: copy 2j holds
~(at_least[depth - 2] & at_least[depth - 2 - j]) (for j = 0 the flag alone), copy 2j + 1
the same stored inverted (its register holds ``~ready``); as at_least[k + 1] implies
at_least[k], each is ~at_least[depth - 2].
"""

from __future__ import annotations

from amaranth.hdl import Module, Signal
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
    copies : int
        Registers holding ``ready``, in [1, 2 * (depth - 1)] (see the module doc).

    Members
    -------
    accept : In(1)
        A pixel is accepted in this cycle (``valid & ready`` of the input stream).
    handed_out : In(1)
        A word leaves the FIFO in this cycle (``valid & ready`` of the output stream).
    ready : Out(copies)
        Registers, each: ready in cycle t + 1 iff committed(t) < depth - 1. Low in the
        cycle after a reset, high from the next.
    """

    def __init__(self, depth: int, *, copies: int = 1):
        try:
            self._depth = check_int("depth", depth, 3)
            self._copies = check_int("copies", copies, 1, 2 * (self._depth - 1))
        except ValueError:
            self._MustUse__silence = True      # refused: never meant to be elaborated
            raise
        super().__init__({"accept": In(1), "handed_out": In(1), "ready": Out(self._copies)})

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
        full = committed.at_least[self._depth - 2]
        if self._copies == 1:
            m.d.sync += self.ready.eq(~full)
            return m
        for copy in range(self._copies):
            pair = copy // 2
            taken = full if pair == 0 else full & committed.at_least[self._depth - 2 - pair]
            if copy % 2:
                # stored inverted: the register holds ~ready and starts at 1 (ready low)
                busy = Signal(init=1, name=f"busy_{copy}")
                m.d.sync += busy.eq(taken)
                m.d.comb += self.ready[copy].eq(~busy)
            else:
                m.d.sync += self.ready[copy].eq(~taken)
        return m
