"""Whether an AXI4 manager port is quiet: no burst in flight and no valid offered, the only
state in which a reset other than ``aresetn`` may hit the manager (AXI4 lets nothing but
``aresetn`` drop a valid or abandon a burst).

:class:`AxiQuiet` watches the handshakes of the port from outside (it is not reset with
the manager it watches): a read burst is in flight from its AR handshake to its last R
beat's, a write burst from its AW handshake to its B handshake. ``dptbd_axi`` built with
the state store in external memory holds a soft reset's restart until its port is quiet
(:class:`~dptbd.hw.axi_store.top.AXITopStore`).
"""

from __future__ import annotations

from amaranth.hdl import Module
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

__all__ = ["QUIET_INPUTS", "AxiQuiet"]

#: The port signals :class:`AxiQuiet` watches (AXI names).
QUIET_INPUTS = ("arvalid", "arready", "rvalid", "rready", "rlast", "awvalid", "awready",
                "wvalid", "bvalid", "bready")


class AxiQuiet(wiring.Component):
    """Quiet detector of an AXI4 manager port (see the module doc).

    Parameters
    ----------
    outstanding : int
        Most bursts the manager keeps in flight per direction.

    Members
    -------
    arvalid … bready : In(1)
        The port's handshake signals (:data:`QUIET_INPUTS`).
    quiet : Out(1)
        Combinational: no read or write burst in flight and ``ARVALID``, ``AWVALID`` and
        ``WVALID`` low in this cycle.
    reads, writes : Out(range(outstanding + 1))
        Bursts in flight per direction.
    """

    def __init__(self, outstanding: int):
        self._outstanding = outstanding
        super().__init__({**{name: In(1) for name in QUIET_INPUTS},
                          "quiet": Out(1),
                          "reads": Out(range(outstanding + 1)),
                          "writes": Out(range(outstanding + 1))})

    def elaborate(self, platform):
        m = Module()
        read_issued = self.arvalid & self.arready
        read_done = self.rvalid & self.rready & self.rlast
        write_issued = self.awvalid & self.awready
        write_done = self.bvalid & self.bready
        m.d.sync += [self.reads.eq(self.reads + read_issued - read_done),
                     self.writes.eq(self.writes + write_issued - write_done)]
        m.d.comb += self.quiet.eq((self.reads == 0) & (self.writes == 0) & ~self.arvalid
                                  & ~self.awvalid & ~self.wvalid)
        return m
