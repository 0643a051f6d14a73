"""AXI4-Lite subordinate: the five channels as wiring signatures, and a one-transaction
adapter to a simple register bus.

Signal names are the AXI ones (``awaddr``, ``wstrb``, ``bresp`` …); a top level that
flattens them with a prefix gets ``s_axil_awaddr`` and so on. 32-bit data, byte addresses,
``prot`` ignored.

:class:`AXILiteSubordinate` takes one transaction at a time: while a response is pending
it accepts nothing new; a write (AW and W, in either order or together) wins over a read
arriving in the same cycle. A write reaches the register bus one cycle after its last
handshake and its response (``bvalid``) follows in the next cycle; a read reaches the bus
(``r_stb``) one cycle after its AR handshake and ``rvalid`` follows in the next cycle: two
cycles after the handshake. The register bus answers with ``r_err`` / ``w_err``, turned
into ``SLVERR``; otherwise ``OKAY``. The bus also shows each AR, AW and W handshake as it
happens (``ar_in_*``, ``aw_in_*``, ``w_in_*``), so that a register block can decode the
addresses and check the data in those cycles and answer from registers.

Whether a response is pending or being prepared (``bvalid``, ``rvalid`` or a read between
its handshake and ``r_stb``) is a register of its own, ``busy``, computed a cycle ahead: it
holds off every ready.

With ``late_read=True`` (the ECP5 build's register block, ``RegisterFile(read_registered=True)``)
the read's answer (``r_data``, ``r_err``) is taken a cycle after ``r_stb`` (``reading_late``),
so that the register block can register a first level of its read there: ``rvalid`` rises
three cycles after the AR handshake; the block still reads its registers in the ``r_stb``
cycle.

With ``handshake_apart=True`` (the ECP5 build's) the AW and W handshakes the block sees
(``aw_in_stb``, ``w_in_stb``) are formed from a copy of ``not busy`` of their own (a
register, so that synthesis keeps the two apart), not from the ``awready`` / ``wready``
ports: the logic that drives those pins does not also drive the handshakes' enables.
Same cycles.

With ``read_apart=True`` (the ECP5 build's) the AR handshake the block sees
(``ar_in_stb``) is formed from a register of its own, ``ar_open`` (``not busy``, no AW or
W held, computed a cycle ahead), and the ``awvalid`` / ``wvalid`` / ``arvalid`` ports, not
from the ``arready`` port: one LUT from a register to the read decode's enables and to
``busy``'s next value; and the write's cycle (``w_stb``: an AW and a W held) is a
register of its own (``write_now``, computed a cycle ahead), not an AND of the two.
Same cycles.
"""

from __future__ import annotations

from amaranth.hdl import Module, Mux, Signal
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

__all__ = ["RESP_OKAY", "RESP_SLVERR", "axi_lite_signature", "register_bus_signature",
           "AXILiteSubordinate"]

RESP_OKAY = 0b00
RESP_SLVERR = 0b10


def axi_lite_signature(address_bits: int, data_bits: int = 32) -> wiring.Signature:
    """AXI4-Lite as the manager sees it: channels ``aw``, ``w``, ``b``, ``ar``, ``r``, each a
    signature whose members carry the AXI signal names."""
    strobe = data_bits // 8
    return wiring.Signature({
        "aw": Out(wiring.Signature({"awaddr": Out(address_bits), "awprot": Out(3),
                                    "awvalid": Out(1), "awready": In(1)})),
        "w": Out(wiring.Signature({"wdata": Out(data_bits), "wstrb": Out(strobe),
                                   "wvalid": Out(1), "wready": In(1)})),
        "b": Out(wiring.Signature({"bresp": In(2), "bvalid": In(1), "bready": Out(1)})),
        "ar": Out(wiring.Signature({"araddr": Out(address_bits), "arprot": Out(3),
                                    "arvalid": Out(1), "arready": In(1)})),
        "r": Out(wiring.Signature({"rdata": In(data_bits), "rresp": In(2), "rvalid": In(1),
                                   "rready": Out(1)})),
    })


def register_bus_signature(address_bits: int, data_bits: int = 32) -> wiring.Signature:
    """The adapter's side of a register block, as the adapter sees it.

    A read: ``r_addr`` with ``r_stb`` (one cycle, the cycle after the AR handshake, which is
    ``ar_in_stb`` with its address ``ar_in_addr``); ``r_data`` and ``r_err`` are the register
    block's answers in the ``r_stb`` cycle (from its decode of ``ar_in_addr``, registered at
    the handshake). A write: ``w_addr``, ``w_data``, ``w_strb``
    with ``w_stb`` (one cycle, after both handshakes); ``w_err`` is the answer in that cycle.
    They hold from the handshakes until the write: the AW handshake is ``aw_in_stb`` with its
    address ``aw_in_addr`` (``w_addr`` from the next cycle on), the W handshake ``w_in_stb``
    with ``w_in_data`` / ``w_in_strb`` (``w_data`` / ``w_strb`` from the next cycle on).
    """
    return wiring.Signature({
        "r_addr": Out(address_bits),
        "r_stb": Out(1),
        "ar_in_stb": Out(1),
        "ar_in_addr": Out(address_bits),
        "w_addr": Out(address_bits),
        "w_stb": Out(1),
        "w_data": Out(data_bits),
        "w_strb": Out(data_bits // 8),
        "aw_in_stb": Out(1),
        "aw_in_addr": Out(address_bits),
        "w_in_stb": Out(1),
        "w_in_data": Out(data_bits),
        "w_in_strb": Out(data_bits // 8),
        "r_data": In(data_bits),
        "r_err": In(1),
        "w_err": In(1),
    })


class AXILiteSubordinate(wiring.Component):
    """AXI4-Lite subordinate port in front of a register bus (see the module doc).

    Members
    -------
    axil : In(axi_lite_signature(address_bits))
    bus : Out(register_bus_signature(address_bits))
    """

    def __init__(self, address_bits: int, data_bits: int = 32, *, late_read: bool = False,
                 handshake_apart: bool = False, read_apart: bool = False):
        self._late = bool(late_read)
        self._apart = bool(handshake_apart)
        self._ar_apart = bool(read_apart)
        super().__init__({
            "axil": In(axi_lite_signature(address_bits, data_bits)),
            "bus": Out(register_bus_signature(address_bits, data_bits)),
        })

    def elaborate(self, platform):
        m = Module()
        aw, w, b, ar, r = (self.axil.aw, self.axil.w, self.axil.b, self.axil.ar, self.axil.r)
        bus = self.bus
        have_aw = Signal()
        have_w = Signal()
        aw_addr = Signal.like(aw.awaddr)
        ar_addr = Signal.like(ar.araddr)
        w_data = Signal.like(w.wdata)
        w_strb = Signal.like(w.wstrb)
        reading = Signal()                 # the cycle after the AR handshake: r_stb
        busy = Signal()                    # bvalid | rvalid | reading, a register
        if self._ar_apart:                 # have_aw & have_w, a register of its own
            writing = Signal(name="write_now")
        else:
            writing = have_aw & have_w

        m.d.comb += [
            aw.awready.eq(~have_aw & ~busy),
            w.wready.eq(~have_w & ~busy),
            ar.arready.eq(~busy & ~have_aw & ~have_w & ~aw.awvalid & ~w.wvalid),
            bus.r_addr.eq(ar_addr),
            bus.w_addr.eq(aw_addr),
            bus.w_stb.eq(writing),
            bus.w_data.eq(w_data),
            bus.w_strb.eq(w_strb),
            bus.r_stb.eq(reading),
            *([] if self._ar_apart else [bus.ar_in_stb.eq(ar.arvalid & ar.arready)]),
            bus.ar_in_addr.eq(ar.araddr),
            bus.aw_in_addr.eq(aw.awaddr),
            bus.w_in_data.eq(w.wdata),
            bus.w_in_strb.eq(w.wstrb),
        ]
        with m.If(bus.aw_in_stb):
            m.d.sync += [have_aw.eq(1), aw_addr.eq(aw.awaddr)]
        with m.If(bus.w_in_stb):
            m.d.sync += [have_w.eq(1), w_data.eq(w.wdata), w_strb.eq(w.wstrb)]
        with m.If(writing):
            m.d.sync += [have_aw.eq(0), have_w.eq(0), b.bvalid.eq(1),
                         b.bresp.eq(Mux(bus.w_err, RESP_SLVERR, RESP_OKAY))]
        with m.Elif(b.bvalid & b.bready):
            m.d.sync += b.bvalid.eq(0)
        m.d.sync += reading.eq(bus.ar_in_stb)
        with m.If(bus.ar_in_stb):
            m.d.sync += ar_addr.eq(ar.araddr)
        answer = reading
        if self._late:                     # the answer a cycle after r_stb
            reading_late = Signal()
            m.d.sync += reading_late.eq(reading)
            answer = reading_late
        with m.If(answer):
            m.d.sync += [r.rvalid.eq(1), r.rdata.eq(bus.r_data),
                         r.rresp.eq(Mux(bus.r_err, RESP_SLVERR, RESP_OKAY))]
        with m.Elif(r.rvalid & r.rready):
            m.d.sync += r.rvalid.eq(0)
        # busy of the next cycle: a response offered then (held, or raised now) or a read
        # being answered then
        busy_next = (writing | reading | bus.ar_in_stb
                     | (b.bvalid & ~b.bready) | (r.rvalid & ~r.rready))
        if self._late:
            busy_next = busy_next | reading_late
        m.d.sync += busy.eq(busy_next)
        if self._apart:                    # ~busy, a copy for the handshakes
            idle = Signal(init=1)
            m.d.sync += idle.eq(~busy_next)
            m.d.comb += [bus.aw_in_stb.eq(aw.awvalid & ~have_aw & idle),
                         bus.w_in_stb.eq(w.wvalid & ~have_w & idle)]
        else:
            m.d.comb += [bus.aw_in_stb.eq(aw.awvalid & aw.awready),
                         bus.w_in_stb.eq(w.wvalid & w.wready)]
        if self._ar_apart:                 # ~busy & ~have_aw & ~have_w, the AR's copy
            ar_open = Signal(init=1)
            # the next have_aw / have_w are 0 unless held or taken now (a write now makes
            # busy_next high)
            m.d.sync += ar_open.eq(~busy_next & ~have_aw & ~have_w
                                   & ~bus.aw_in_stb & ~bus.w_in_stb)
            m.d.comb += bus.ar_in_stb.eq(ar.arvalid & ~aw.awvalid & ~w.wvalid & ar_open)
            # both held in the next cycle: each held or taken now, and no write now
            m.d.sync += writing.eq(~writing & (have_aw | bus.aw_in_stb)
                                   & (have_w | bus.w_in_stb))
        return m

