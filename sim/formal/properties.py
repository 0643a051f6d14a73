"""Property building blocks of the formal harnesses (:mod:`dptbd.sim.formal.harnesses`).

Each function adds, to a harness's module, the ``Assert`` (rules the design under proof
must keep) or ``Assume`` (rules its environment keeps) statements of one interface rule set,
with the past-value registers it needs. Amaranth 0.5 has no ``Past``: a past value is a
``reset_less`` register of the harness, so it survives the design's reset; ``past_rst`` (1
in the first cycle) tells a check that the previous cycle was a reset.

Conventions: ``rst`` is the harness's synchronous reset (``~aresetn``): high in cycle t
means every register of the design takes its reset value at the end of cycle t. A rule
"held until accepted" therefore binds cycle t + 1 only when cycle t was not a reset.
"""

from __future__ import annotations

from amaranth.hdl import Assert, Assume, Cat, Signal, Value

__all__ = ["Past", "axis_manager", "axis_subordinate", "axil_subordinate", "packet_open"]


class Past:
    """Past values for one harness: ``past(value)`` is ``value`` one cycle ago (a
    ``reset_less`` register, X-free: 0 at start)."""

    def __init__(self, m, rst):
        self._m = m
        self.rst = Signal(init=1, reset_less=True, name="past_rst")
        m.d.sync += self.rst.eq(rst)

    def __call__(self, value, name: str = "past") -> Signal:
        value = Value.cast(value)
        reg = Signal(len(value), reset_less=True, name=name)
        self._m.d.sync += reg.eq(value)
        return reg


def _stream_rules(m, past, kind, tvalid, tready, payload, *, name):
    """Valid held until taken, payload stable while held (``kind`` = Assert or Assume)."""
    payload = Cat(*payload)
    stall = past(tvalid & ~tready, f"{name}_past_stall")
    held_payload = past(payload, f"{name}_past_payload")
    with m.If(stall & ~past.rst):
        m.d.comb += [
            kind(tvalid, f"{name}: tvalid dropped before the handshake"),
            kind(payload == held_payload, f"{name}: payload changed while held"),
        ]


def axis_manager(m, past, *, tvalid, tready, payload, name):
    """Assert the AXI4-Stream manager rules of a port the design drives: once ``tvalid`` is
    high it stays high, with ``payload`` (tdata, tuser, tlast …) unchanged, until the cycle
    of the handshake; only the reset (``aresetn``) may drop it."""
    _stream_rules(m, past, Assert, tvalid, tready, payload, name=name)


def axis_subordinate(m, past, *, tvalid, tready, payload, name):
    """Assume the same rules of the manager driving a port of the design."""
    _stream_rules(m, past, Assume, tvalid, tready, payload, name=name)


def packet_open(m, *, tvalid, tready, tlast, name):
    """``(opened, after)``: ``opened`` is a register, a word without ``tlast`` was
    transferred since the last ``tlast`` (or the reset; a caller that resets the design in
    other ways clears it too); ``after`` is the same after this cycle's transfer."""
    opened = Signal(name=f"{name}_open")
    after = Signal(name=f"{name}_open_after")
    take = tvalid & tready
    m.d.comb += after.eq(Cat(take & ~tlast, opened & ~(take & tlast)).any())
    m.d.sync += opened.eq(after)
    return opened, after


def axil_subordinate(m, past, axil, *, name="s_axil", bound: int = 1):
    """ZipCPU-style AXI4-Lite subordinate checks (outstanding counters), on ``axil`` (the
    design's ``axi_lite_signature`` as the manager sees it). The manager's rules are assumed
    (AW, W, AR held until taken, stable payload); the design's are asserted: B and R held
    until taken with a stable payload, never a response without its request (a write
    response only after both its AW and its W), at most ``bound`` transactions outstanding
    per channel. Returns the outstanding counters (aw, w, ar) for cover statements."""
    aw, w, b, ar, r = axil.aw, axil.w, axil.b, axil.ar, axil.r
    axis_subordinate(m, past, tvalid=aw.awvalid, tready=aw.awready,
                     payload=[aw.awaddr, aw.awprot], name=f"{name}_aw")
    axis_subordinate(m, past, tvalid=w.wvalid, tready=w.wready,
                     payload=[w.wdata, w.wstrb], name=f"{name}_w")
    axis_subordinate(m, past, tvalid=ar.arvalid, tready=ar.arready,
                     payload=[ar.araddr, ar.arprot], name=f"{name}_ar")
    axis_manager(m, past, tvalid=b.bvalid, tready=b.bready, payload=[b.bresp], name=f"{name}_b")
    axis_manager(m, past, tvalid=r.rvalid, tready=r.rready, payload=[r.rdata, r.rresp],
                 name=f"{name}_r")
    width = (bound + 1).bit_length() + 1
    counters = []
    for channel, req, resp in (("aw", aw.awvalid & aw.awready, b.bvalid & b.bready),
                               ("w", w.wvalid & w.wready, b.bvalid & b.bready),
                               ("ar", ar.arvalid & ar.arready, r.rvalid & r.rready)):
        count = Signal(width, name=f"{name}_{channel}_outstanding")
        m.d.sync += count.eq(count + req - resp)
        m.d.comb += Assert(count <= bound,
                           f"{name}: more than {bound} {channel.upper()} outstanding")
        counters.append(count)
    aw_out, w_out, ar_out = counters
    with m.If(b.bvalid):
        m.d.comb += Assert((aw_out != 0) & (w_out != 0),
                           f"{name}: write response without both AW and W accepted")
    with m.If(r.rvalid):
        m.d.comb += Assert(ar_out != 0, f"{name}: read response without AR accepted")
    return aw_out, w_out, ar_out
