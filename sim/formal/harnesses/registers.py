"""The harness of the AXI4-Lite port and the register block (:class:`RegistersHarness`)."""

from __future__ import annotations

import operator

from amaranth.hdl import Assert, Cat, Cover, Value

from dptbd.config import DPConfig
from dptbd.hw.register_file import RegisterFile
from dptbd.sim.formal.harness import Elaborated, Harness
from dptbd.sim.formal.harnesses.tiny import tiny_config
from dptbd.sim.formal.properties import axil_subordinate

__all__ = ["RegistersHarness", "register_invariants", "setting_invariants"]


class RegistersHarness(Harness):
    """The AXI4-Lite port and the register block
    (:class:`~dptbd.hw.register_file.RegisterFile`, its :class:`~dptbd.hw.axi_lite.AXILiteSubordinate` inside), any event
    pulses, any manager that keeps the AXI4-Lite rules.

    Asserted: the AXI4-Lite subordinate rules
    (:func:`~dptbd.sim.formal.properties.axil_subordinate`: B and R held until taken and stable, no response without its request,
    a write response only after both AW and W, one transaction at a time); a refused write
    (SLVERR on a register that stores: a setting out of its limits, an unaligned address, a
    LUT word out of range or not fully strobed) changes no setting, no enable bit, clears no
    sticky / interrupt bit and writes no LUT entry; a sticky / interrupt bit (W1C) goes from
    1 to 0 only in the cycle after an accepted write of a 1 to it; every setting lies in
    its limits (:func:`setting_invariants`, which also holds the invariants of the range
    check; ``bounds_registered``: the ECP5 build's register block,
    :class:`~dptbd.hw.register_file.RegisterFile`'s ``bounds_registered`` and
    ``refusal_registered`` and ``handshake_apart``).
    Invariants (for the induction): while an AW is held, the register block's decode of it, registered at its
    handshake, is its address's; an accepted AR is the read being answered (the cycle after
    its handshake) or ``rvalid``, and the read's registered decode is its address's; the subordinate's registered ``busy`` is ``bvalid`` or
    ``rvalid`` or a read being answered.
    """

    def __init__(self, cfg: DPConfig | None = None, *, bounds_registered: bool = False):
        super().__init__()
        self.cfg = cfg or tiny_config()
        self.bounds_registered = bounds_registered

    def check(self, m, past):
        regs = Elaborated(RegisterFile(self.cfg, bounds_registered=self.bounds_registered,
                                       refusal_registered=self.bounds_registered,
                                       handshake_apart=self.bounds_registered))
        m.submodules.regs = regs.fragment
        rf = regs.component
        self.free_inputs(m, rf, "regs")
        aw_out, w_out, ar_out = axil_subordinate(m, past, rf.axil)
        bus = regs.sub("axil").component.bus
        regmap = rf.register_map
        refused = past(bus.w_stb & bus.w_err, "past_refused")
        past_addr = past(bus.w_addr, "past_addr")
        past_data = past(bus.w_data, "past_w_data")
        past_strb = past(bus.w_strb, "past_w_strb")
        past_write = past(bus.w_stb, "past_w_stb")
        for reg in regmap.registers:
            for field in reg.fields:
                if field.kind == "setting":
                    value = getattr(rf, field.name)
                elif field.kind in ("enable", "sticky", "interrupt"):
                    value = regs.signal(f"{reg.name}_{field.name}".lower())
                else:
                    continue
                before = past(value, f"past_{reg.name}_{field.name}".lower())
                what = f"{reg.name}.{field.name}"
                with m.If(refused & ~past.rst):
                    if field.kind in ("sticky", "interrupt"):
                        m.d.comb += Assert((before & ~value) == 0,
                                           f"{what}: cleared by a refused write")
                    else:
                        m.d.comb += Assert(value == before,
                                           f"{what}: changed by a refused write")
                if field.kind in ("sticky", "interrupt"):
                    for bit in range(field.width):
                        at = field.lsb + bit
                        ones = (past_write & ~refused & (past_addr == reg.address)
                                & past_strb[at // 8] & past_data[at])
                        with m.If(before[bit] & ~value[bit] & ~past.rst):
                            m.d.comb += Assert(ones, f"{what}[{bit}]: cleared without a "
                                                     f"written 1 (W1C)")
        with m.If(refused & ~past.rst):
            m.d.comb += Assert(~rf.lut_we, "LUT: written by a refused write")
        b, r = rf.axil.b, rf.axil.r
        m.d.comb += [
            Cover(b.bvalid & b.bready & (b.bresp == 0)),
            Cover(b.bvalid & b.bready & (b.bresp == 2) & refused),     # a refused write
            Cover(r.rvalid & r.rready & (r.rresp == 0)),
        ]
        for reg in regmap.registers:                    # an accepted write of a setting
            if reg.kind == "setting":
                m.d.comb += Cover(past_write & ~refused & (past_addr == reg.address))
                break
        register_invariants(m, regs, aw_out, w_out, ar_out)
        setting_invariants(m, regs, self.bounds_registered)
        irq_status = next(reg for reg in regmap.registers if reg.name == "IRQ_STATUS")
        field = irq_status.fields[0]
        bit = regs.signal(f"irq_status_{field.name}")
        m.d.comb += Cover(past(bit, "past_irq_bit") & ~bit & ~past.rst)      # a W1C clear


def setting_invariants(m, regs: Elaborated, bounds_registered: bool) -> None:
    """Assert that every setting lies in its limits (and is a multiple of its ``align``),
    and, for the induction, that a held W beat's registered check is its merged word's;
    with ``bounds_registered`` also that each byte flag kept for a setting is its current
    byte's and each flag of a held W beat its merged byte's."""
    rf, port = regs.component, regs.sub("axil")
    bus = port.component.bus
    have_w = port.signal("have_w")
    mask = Cat(bit.replicate(8) for bit in bus.w_strb)
    for reg in rf.register_map.registers:
        if reg.kind != "setting":
            continue
        (field,) = reg.fields
        lo, hi = field.limits
        name = reg.name.lower()
        value = getattr(rf, field.name)
        merged = (value & ~mask) | (bus.w_data & mask)

        def within(word):
            ok = (word >= lo) & (word <= hi)
            if field.align is not None and not lo:
                ok &= word % field.align == 0
            return ok
        m.d.comb += Assert(within(value), f"{reg.name}.{field.name}: outside its limits")
        with m.If(have_w):
            m.d.comb += Assert(regs.signal(f"write_ok_{name}") == within(merged),
                               f"write_ok_{name} != the held W beat's check")
        if not bounds_registered:
            continue
        for tag, limit, beyond in [("hi", hi, operator.lt)] + ([("lo", lo, operator.gt)]
                                                              if lo else []):
            for j in range(4):
                if 8 * j >= field.width:
                    break
                byte = (limit >> (8 * j)) & 0xFF
                for flag, test in (("in", lambda b: beyond(b, byte)),
                                   ("eq", lambda b: b == byte)):
                    m.d.comb += Assert(
                        regs.signal(f"{name}_{tag}{j}_{flag}")
                        == test(Value.cast(value)[8 * j:8 * j + 8]),
                        f"{name}_{tag}{j}_{flag} != the setting's byte's")
                    with m.If(have_w):
                        m.d.comb += Assert(
                            regs.signal(f"{name}_{tag}{j}_{flag}_w")
                            == test(merged[8 * j:8 * j + 8]),
                            f"{name}_{tag}{j}_{flag}_w != the held W beat's byte's")


def register_invariants(m, regs: Elaborated, aw_out, w_out, ar_out) -> None:
    """Assert what the register block's decode and its AXI4-Lite port's state mean
    (``regs``: a :class:`~dptbd.hw.register_file.RegisterFile`, elaborated), in terms of
    the outstanding counters of :func:`~dptbd.sim.formal.properties.axil_subordinate`: the
    invariants of :class:`RegistersHarness`'s induction."""
    rf, port = regs.component, regs.sub("axil")
    bus, regmap = port.component.bus, rf.register_map
    b, r = rf.axil.b, rf.axil.r
    # invariants for the induction: a held AW's registered decode is its address's
    w_addr = bus.w_addr
    with m.If(port.signal("have_aw")):
        m.d.comb += Assert(regs.signal("write_unaligned") == w_addr[:2].any(),
                           "write_unaligned != the held address's")
        for reg in regmap.registers:
            m.d.comb += Assert(
                regs.signal(f"write_at_{reg.name.lower()}")
                == (w_addr == reg.address), f"write_at_{reg.name.lower()} != the held "
                                            f"address's")
        lut = regmap.window("LUT")
        m.d.comb += Assert(regs.signal("write_at_lut")
                           == (~w_addr[:2].any() & (w_addr >= lut.base) & (w_addr < lut.end)),
                           "write_at_lut != the held address's")
        if rf.refusal_registered:          # the address's errors, one register
            stores = [w_addr == reg.address for reg in regmap.registers
                      if reg.kind not in ("constant", "counter", "status")]
            m.d.comb += Assert(regs.signal("write_bad_address")
                               == ~(Cat(*stores).any() | regs.signal("write_at_lut")),
                               "write_bad_address != the held address's")
    # ... and the read being answered, decoded at its AR handshake, is its address's
    r_addr = bus.r_addr
    late = rf.read_registered              # the answer a cycle after the read
    answering = port.signal("reading") | (port.signal("reading_late") if late else 0)
    in_flight = port.signal("reading") + (port.signal("reading_late") if late else 0)
    with m.If(answering):
        hits = []
        for reg in regmap.registers:
            hit = r_addr == reg.address
            hits.append(hit)
            m.d.comb += Assert(regs.signal(f"read_at_{reg.name.lower()}") == hit,
                               f"read_at_{reg.name.lower()} != the read address's")
        m.d.comb += Assert(regs.signal("read_unmapped") == ~Cat(*hits).any(),
                           "read_unmapped != the read address's")
    m.d.comb += [
        Assert(aw_out == port.signal("have_aw") + b.bvalid, "AW outstanding != held"),
        Assert(w_out == port.signal("have_w") + b.bvalid, "W outstanding != held"),
        Assert(ar_out == in_flight + r.rvalid,
               "AR outstanding != the read being answered + rvalid"),
        Assert(port.signal("busy") == (b.bvalid | r.rvalid | answering),
               "busy != bvalid | rvalid | the read being answered"),
    ]
    if rf.handshake_apart:                 # the handshakes' copies of ~busy
        m.d.comb += [
            Assert(port.signal("idle") == ~port.signal("busy"), "idle != ~busy"),
            Assert(port.signal("ar_open") == (~port.signal("busy") & ~port.signal("have_aw")
                                              & ~port.signal("have_w")),
                   "ar_open != ~busy & ~have_aw & ~have_w"),
            Assert(port.signal("write_now") == (port.signal("have_aw")
                                                & port.signal("have_w")),
                   "write_now != have_aw & have_w"),
        ]
