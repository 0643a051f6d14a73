"""One stream to several consumers, each word delivered to every one of them: the Amaranth
counterpart of verilog-axis's ``axis_broadcast``.

:class:`StreamBroadcast` holds one word in a register with a *pending* bit per output. An
output's ``valid`` is its pending bit (registered, never a function of any ``ready``); a bit
clears when that output takes the word. The input is taken when every output is either
empty or taking its word in this cycle, so with every consumer ready the broadcast passes one
word per cycle, one cycle late. A consumer that holds ``ready`` low stalls the input (and so
the producer) after at most one word: back-pressure on any output is back-pressure on all.
"""

from __future__ import annotations

from amaranth.hdl import Cat, Module, Signal
from amaranth.lib import stream, wiring
from amaranth.lib.wiring import In, Out

from dptbd.errors import check_int

__all__ = ["StreamBroadcast"]


class StreamBroadcast(wiring.Component):
    """Every word of ``input`` to each of ``count`` outputs (see the module doc).

    Parameters
    ----------
    shape : shape-like
        The payload shape (a ``data.Layout`` or a width).
    count : int
        Number of outputs, in [2, 16].

    Members
    -------
    input : In(stream.Signature(shape))
    outputs : Out(stream.Signature(shape)).array(count)
    """

    def __init__(self, shape, count: int = 2):
        try:
            self._count = check_int("count", count, 2, 16)
        except ValueError:
            self._MustUse__silence = True      # refused: never meant to be elaborated
            raise
        super().__init__({
            "input": In(stream.Signature(shape)),
            "outputs": Out(stream.Signature(shape)).array(self._count),
        })

    def elaborate(self, platform):
        m = Module()
        outputs = list(self.outputs)
        pending = Signal(self._count)
        taken = Cat(out.ready for out in outputs) & pending
        m.d.comb += self.input.ready.eq((pending & ~taken) == 0)
        for i, out in enumerate(outputs):
            m.d.comb += out.valid.eq(pending[i])
        with m.If(self.input.valid & self.input.ready):
            m.d.sync += pending.eq(-1)
            for out in outputs:
                m.d.sync += out.payload.eq(self.input.payload)
        with m.Else():
            m.d.sync += pending.eq(pending & ~taken)
        return m
