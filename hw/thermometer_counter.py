"""An up/down counter kept in thermometer code: every "count >= k" is its own register.

A binary counter answers "count < k?" through its adder and a comparator, both on the path
from the events that move it to the flag. :class:`ThermometerCounter` keeps instead one
register per level, ``at_least[k - 1] = (count >= k)`` for k = 1 … ``limit``: counting up
shifts a 1 in at the bottom, counting down shifts a 0 in at the top, so each flag is a
register whose next value is a neighbour's (a 3-input LUT of ``up`` and the two neighbours)
under a clock enable that is ``up XOR down``. No carry chain, no comparator: the flags are
what a full/empty/credit decision reads. It costs ``limit`` registers where a binary counter
needs ``bitlen(limit)``, so it is for small limits (a FIFO's depth, a credit).

The count saturates at 0 and at ``limit`` (an ``up`` at ``limit`` or a ``down`` at 0 leaves it
unchanged); the users size it so that neither happens.
"""

from __future__ import annotations

from amaranth.hdl import Cat, Const, Module
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

from dptbd.errors import check_int

__all__ = ["ThermometerCounter"]


class ThermometerCounter(wiring.Component):
    """Up/down counter in [0, ``limit``] with a register per level (see the module doc).

    Parameters
    ----------
    limit : int
        The largest count, in [1, inf).

    Members
    -------
    up, down : In(1)
        Count up / down at the clock edge; both or neither: unchanged.
    at_least : Out(limit)
        Registers: bit ``k - 1`` is ``count >= k`` (so ``at_least[0]`` is "not zero" and
        ``at_least[limit - 1]`` is "at the limit"). 0 after a reset.
    """

    def __init__(self, limit: int):
        try:
            self._limit = check_int("limit", limit, 1)
        except ValueError:
            self._MustUse__silence = True      # refused: never meant to be elaborated
            raise
        super().__init__({"up": In(1), "down": In(1), "at_least": Out(self._limit)})

    @property
    def limit(self) -> int:
        """The largest count."""
        return self._limit

    def elaborate(self, platform):
        m = Module()
        flags = self.at_least
        # The clock enable is up XOR down; under it the data only needs `up` to choose the
        # direction, so the `down` event (often the later one) reaches the clock enable only.
        with m.If(self.up ^ self.down):
            with m.If(self.up):
                m.d.sync += flags.eq(Cat(Const(1, 1), flags[:-1]))
            with m.Else():
                m.d.sync += flags.eq(Cat(flags[1:], Const(0, 1)))
        return m
