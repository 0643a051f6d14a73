"""The register block of ``dptbd_axi``, decoded from :func:`dptbd.hw.register_map.register_map`.

:class:`RegisterFile` answers the register bus of the :class:`~dptbd.hw.axi_lite.AXILiteSubordinate`
it contains. Every register, field and reset value comes from the map; this package only
implements the field kinds (:data:`!dptbd.hw.register_map.FIELD_KINDS`):

- an address that is not a multiple of 4 is **unaligned**: a read returns 0 with SLVERR; a
  write is refused (nothing changes, ``ERROR.write_refused`` set, SLVERR);
- a read of a mapped register returns its fields (OKAY); a read inside the LUT window
  returns 0 with SLVERR (the window is write-only); any other address returns 0 with SLVERR;
- a write is merged with the register's current value under ``wstrb`` (bytes not strobed
  keep their value) and then, by kind: ``setting``: taken if the whole merged word lies in
  the field's ``limits``, else **refused** (value not taken, ``ERROR.write_refused`` set,
  SLVERR); ``enable``: taken; ``sticky`` / ``interrupt``: bits written 1 clear; ``pulse``:
  bits written 1 pulse for one cycle (the cycle after the write); ``constant`` / ``counter``
  / ``status`` and unmapped addresses: refused with SLVERR only;
- a read's address is decoded at its AR handshake and the register read in the next cycle
  (``rvalid`` rises the cycle after that, two cycles after the handshake; three with
  ``read_registered``); a ``status``
  field reads its input port (of the same name) in that cycle, the one after the handshake;
- a LUT window write is taken if all four bytes are strobed (``wstrb`` = 1111) and the word
  lies in the code's ``limits``; otherwise refused (entry unchanged,
  ``ERROR.write_refused`` set, SLVERR);
- counters add 1 per cycle their event is high (registered first: counted a cycle later) and
  wrap modulo 2**32;
- ``irq`` is high while any ``IRQ_STATUS`` bit and its ``IRQ_ENABLE`` bit are both 1.

Modules: this one (``RegisterFile``: decode, read, write, events), :mod:`.bounds` (the
range check of a written setting, by word or by bytes).
"""

from __future__ import annotations

import functools
import operator

from amaranth.hdl import Cat, Module, Signal
from amaranth.lib import data, wiring
from amaranth.lib.wiring import In, Out

from dptbd.config import DPConfig
from dptbd.hw.axi_lite import AXILiteSubordinate, axi_lite_signature
from dptbd.hw.register_file.bounds import byte_check, word_check
from dptbd.hw.register_map import ADDRESS_BITS, COUNTER_BITS, EVENTS, register_map

__all__ = ["event_port_layout", "RegisterFile"]

#: ``read_registered``: the registers ORed into each first-level register of a read.
READ_GROUP = 4


def event_port_layout(events=EVENTS) -> data.StructLayout:
    """One bit per counted event pulse (default :data:`~dptbd.hw.register_map.EVENTS`)."""
    return data.StructLayout({name: 1 for name in events})


class RegisterFile(wiring.Component):
    """Registers of the AXI top level for ``cfg``.

    Members
    -------
    axil : In(axi_lite_signature(ADDRESS_BITS))
        The control port (:class:`~dptbd.hw.axi_lite.AXILiteSubordinate` inside).
    events : In(event_port_layout())
        One-cycle event pulses, counted and turned into sticky / interrupt bits, registered
        first: a pulse in cycle c is counted, sets its bit and raises ``irq`` at the end of
        c+1 (visible from c+2).
    segment_frames, candidate_count, histogram_shift : Out
        The run-time settings (one per ``setting`` field), reset to the build values.
    soft_reset, clear_counters : Out(1)
        One-cycle pulses (one per ``pulse`` field), registers.
    soft_reset_ahead, clear_counters_ahead : Out(1)
        Only with ``pulses_ahead=True``: each pulse of the next cycle (combinational, from
        the write's registers), for a register of the caller's own that must rise with it.
    soft_reset_busy : In(1)
        What the ``status`` field of that name reads.
    lut_addr, lut_data, lut_we : Out
        The weight LUT write port, one cycle after an accepted window write.
    irq : Out(1)

    With ``bounds_registered=True`` (the ECP5 build's, ``control_style="registered"``) a
    written setting is range-checked at its W handshake from byte-wise comparisons: each
    written byte against the limits' byte (constants), each byte not written by flags of
    the current value's byte kept in registers (set by the write that takes a value, from
    the same comparisons), so that no comparison runs from a setting's register to the
    write's decision. Same answers, same cycles.

    With ``refusal_registered=True`` (the ECP5 build's) a refused write sets
    ``ERROR.write_refused`` and ``IRQ_STATUS.fault`` from a register, at the end of the
    cycle after the write (visible two cycles after it, ``irq`` a cycle later than
    without): the refusal's OR over the decoded address and the checks ends at that
    register, not in the sticky bits' enables. No read can tell: the earliest read after
    a write reads the registers three cycles after it (the response, then the AR
    handshake).
    A write's address errors (unaligned, unmapped, not storing) are one register decoded
    at its AW handshake (``write_bad_address``). Same answers, same cycles.

    With ``read_registered=True`` (the ECP5 build's, ``register_read="two_level"``) a
    read's AND-OR is split in two: in the cycle after the AR handshake (as without) the
    selected words of each group of four registers are ORed into a register, in the next
    cycle the groups' registers are ORed into the read data: ``rvalid`` rises three
    cycles after the AR handshake (two without), with the registers of the cycle after it
    as without.

    With ``handshake_apart=True`` (the ECP5 build's) the AXI4-Lite port's AW and W
    handshakes come from a copy of its ``busy`` of their own, and its AR handshake from a
    register of its own (``read_apart``, :class:`~dptbd.hw.axi_lite.AXILiteSubordinate`),
    not from the ready pins' logic; the write's cycle (``w_stb``) is a register too.
    """

    def __init__(self, cfg: DPConfig, regmap=None, *, pulses_ahead: bool = False,
                 bounds_registered: bool = False, refusal_registered: bool = False,
                 read_registered: bool = False, handshake_apart: bool = False):
        # regmap: register_map(cfg) if None
        self._cfg = cfg
        self._map = register_map(cfg) if regmap is None else regmap
        self._ahead = bool(pulses_ahead)
        self._bounds = bool(bounds_registered)
        self._refusal = bool(refusal_registered)
        self._read_registered = bool(read_registered)
        self._apart = bool(handshake_apart)
        members = {
            "axil": In(axi_lite_signature(ADDRESS_BITS)),
            "events": In(event_port_layout(self._map.events)),
        }
        for _reg, field in self._map.fields("setting"):
            members[field.name] = Out(range(field.limits[1] + 1), init=field.reset)
        for _reg, field in self._map.fields("pulse"):
            members[field.name] = Out(1)
            if self._ahead:
                members[f"{field.name}_ahead"] = Out(1)
        for _reg, field in self._map.fields("status"):
            members[field.name] = In(field.width)
        members.update({"lut_addr": Out(range(cfg.lut_entries)),
                        "lut_data": Out(cfg.weight_bits), "lut_we": Out(1), "irq": Out(1)})
        super().__init__(members)

    @property
    def register_map(self):
        return self._map

    @property
    def handshake_apart(self) -> bool:
        """The AW, W and AR handshakes from registers of their own."""
        return self._apart

    @property
    def refusal_registered(self) -> bool:
        """A refusal's sticky bits from a register; the address's errors one register."""
        return self._refusal

    @property
    def read_registered(self) -> bool:
        """A read's first level registered (``rvalid`` three cycles after the AR handshake)."""
        return self._read_registered

    def elaborate(self, platform):
        m = Module()
        m.submodules.axil = port = AXILiteSubordinate(ADDRESS_BITS,
                                                      late_read=self._read_registered,
                                                      handshake_apart=self._apart,
                                                      read_apart=self._apart)
        wiring.connect(m, wiring.flipped(self.axil), port.axil)
        bus, regmap = port.bus, self._map
        byte_mask = Cat(bit.replicate(8) for bit in bus.w_strb)
        written_ones = bus.w_data & byte_mask
        refused = Signal()
        # The event pulses are registered first (they come from across the design): each
        # counts, sets its bit and reaches irq one cycle after its pulse.
        events = Signal(event_port_layout(regmap.events))
        m.d.sync += events.eq(self.events)
        raised = {}                                  # event name -> pulse this cycle
        for name in regmap.events:
            raised[name] = events[name]
        raised["write_refused"] = refused
        raised["fault"] = Cat(raised[f.event] for _r, f in regmap.fields("sticky")).any()

        storage = {}                                 # (register, field) -> signal
        for reg in regmap.registers:
            for field in reg.fields:
                if field.kind == "setting":
                    storage[reg.name, field.name] = getattr(self, field.name)
                elif field.kind == "counter":
                    storage[reg.name, field.name] = Signal(COUNTER_BITS, name=reg.name.lower())
                elif field.kind == "status":
                    storage[reg.name, field.name] = getattr(self, field.name)
                elif field.kind in ("enable", "sticky", "interrupt"):
                    storage[reg.name, field.name] = Signal(
                        field.width, init=field.reset, name=f"{reg.name}_{field.name}".lower())

        def value(reg) -> Signal:
            word = Signal(32, name=f"{reg.name.lower()}_value")
            for field in reg.fields:
                if field.kind == "constant":
                    m.d.comb += word[field.lsb:field.lsb + field.width].eq(field.reset)
                elif field.kind != "pulse":
                    m.d.comb += word[field.lsb:field.lsb + field.width].eq(
                        storage[reg.name, field.name])
            return word

        lut = regmap.window("LUT")
        for _reg, field in regmap.fields("pulse"):
            m.d.sync += getattr(self, field.name).eq(0)
        m.d.sync += self.lut_we.eq(0)
        values = {reg.name: value(reg) for reg in regmap.registers}

        # A read is decoded from its address at its AR handshake into registers, one select
        # per register, and answered in the next cycle (r_stb) by an AND-OR of the selected
        # word (the registers' addresses are distinct): unaligned, unmapped and LUT
        # addresses select none, read 0 and answer an error.
        ra = bus.ar_in_addr
        r_sel = []
        for reg in regmap.registers:
            sel = Signal(name=f"read_at_{reg.name.lower()}")
            with m.If(bus.ar_in_stb):
                m.d.sync += sel.eq(~ra[:2].any() & (ra[2:] == reg.address >> 2))
            r_sel.append(sel)
        read_none = Signal(name="read_unmapped")
        with m.If(bus.ar_in_stb):
            m.d.sync += read_none.eq(~Cat(*[~ra[:2].any() & (ra[2:] == reg.address >> 2)
                                            for reg in regmap.registers]).any())
        terms = [values[reg.name] & sel.replicate(32)
                 for reg, sel in zip(regmap.registers, r_sel)]
        if self._read_registered:       # groups of four registers ORed into a register
            groups = []
            for g in range(0, len(terms), READ_GROUP):
                group = Signal(32, name=f"read_group_{g // READ_GROUP}")
                m.d.sync += group.eq(functools.reduce(operator.or_, terms[g:g + READ_GROUP]))
                groups.append(group)
            terms = groups
        m.d.comb += [
            bus.r_data.eq(functools.reduce(operator.or_, terms)),
            bus.r_err.eq(read_none),
        ]

        # A write is decoded at its AW handshake and its data checked at its W handshake,
        # both into registers: the write's cycle (w_stb) only combines registers. A setting
        # cannot change between its W handshake and the write (only a write changes it, and
        # no W is taken until the write before it has been answered).
        def registered(strobe, name, condition):
            bit = Signal(name=name)
            with m.If(strobe):
                m.d.sync += bit.eq(condition)
            return bit

        aw = bus.aw_in_addr
        aligned = ~aw[:2].any()
        at_reg = {reg.name: aligned & (aw[2:] == reg.address >> 2) for reg in regmap.registers}
        unaligned = registered(bus.aw_in_stb, "write_unaligned", ~aligned)
        at = {name: registered(bus.aw_in_stb, f"write_at_{name.lower()}", hit)
              for name, hit in at_reg.items()}
        at_lut_in = (aligned & ~Cat(at_reg.values()).any()
                     & (aw >= lut.base) & (aw < lut.end))
        at_lut = registered(bus.aw_in_stb, "write_at_lut", at_lut_in)
        in_mask = Cat(bit.replicate(8) for bit in bus.w_in_strb)
        in_ones = bus.w_in_data & in_mask
        ok = {}
        takes = {}                                   # register -> stores on a taken write
        for reg in regmap.registers:
            if reg.kind == "setting" and self._bounds:
                ok[reg.name], takes[reg.name] = byte_check(reg, bus, registered)
            elif reg.kind == "setting":
                merged_in = (values[reg.name] & ~in_mask) | in_ones
                ok[reg.name] = registered(bus.w_in_stb, f"write_ok_{reg.name.lower()}",
                                          word_check(reg, merged_in))
        lut_ok = registered(bus.w_in_stb, "write_ok_lut",
                            bus.w_in_strb.all() & (bus.w_in_data <= lut.field.limits[1]))

        # the answer as flat logic of those registers (the selects are exclusive; an
        # unaligned address selects none): refused, SLVERR, or taken
        writing = bus.w_stb
        bad_lut = at_lut & ~lut_ok
        refusals = [unaligned, bad_lut]
        errors = [~Cat(*at.values(), at_lut).any(), bad_lut]    # unaligned or unmapped
        for reg in regmap.registers:
            if reg.kind in ("constant", "counter", "status"):
                errors.append(at[reg.name])
            elif reg.kind == "setting":
                refusals.append(at[reg.name] & ~ok[reg.name])
                errors.append(at[reg.name] & ~ok[reg.name])
        if self._refusal:            # the address's errors one register, beside the checks
            no_store = [at_reg[reg.name] for reg in regmap.registers
                        if reg.kind in ("constant", "counter", "status")]
            errors = [registered(bus.aw_in_stb, "write_bad_address",
                                 ~Cat(*at_reg.values(), at_lut_in).any() | Cat(*no_store).any()),
                      bad_lut] + [at[reg.name] & ~ok[reg.name] for reg in regmap.registers
                                  if reg.kind == "setting"]
        m.d.comb += bus.w_err.eq(Cat(*errors).any())
        domain = m.d.sync if self._refusal else m.d.comb
        domain += refused.eq(writing & Cat(*refusals).any())
        for reg in regmap.registers:
            with m.If(writing & at[reg.name]):
                current = values[reg.name]
                merged = (current & ~byte_mask) | written_ones
                self._write(m, reg, storage, merged, written_ones, ok.get(reg.name))
                if reg.name in takes:
                    with m.If(ok[reg.name]):
                        m.d.sync += takes[reg.name]
        with m.If(writing & at_lut & lut_ok):
            m.d.sync += [self.lut_addr.eq((bus.w_addr - lut.base)[2:]),
                         self.lut_data.eq(bus.w_data), self.lut_we.eq(1)]

        clear = self.clear_counters
        pending = []
        for reg in regmap.registers:
            for field in reg.fields:
                bit = storage.get((reg.name, field.name))
                if field.kind == "counter":
                    with m.If(clear):
                        m.d.sync += bit.eq(0)
                    with m.Elif(raised[field.event]):
                        m.d.sync += bit.eq(bit + 1)
                elif field.kind in ("sticky", "interrupt"):
                    with m.If(raised[field.event]):
                        m.d.sync += bit.eq(1)           # after the W1C clear: a set wins
        for _reg, field in regmap.fields("interrupt"):
            enable = storage["IRQ_ENABLE", field.name]
            pending.append(storage["IRQ_STATUS", field.name] & enable)
        m.d.comb += self.irq.eq(Cat(pending).any())
        return m

    def _write(self, m, reg, storage, merged, written_ones, ok):
        """The stores of a write to ``reg`` (in the write's cycle; ``ok``: a setting's
        data in its limits)."""
        kind = reg.kind
        if kind == "setting":
            (field,) = reg.fields
            with m.If(ok):
                m.d.sync += storage[reg.name, field.name].eq(merged)
            return
        for field in reg.fields:
            part = slice(field.lsb, field.lsb + field.width)
            if kind == "enable":
                m.d.sync += storage[reg.name, field.name].eq(merged[part])
            elif kind in ("sticky", "interrupt"):
                with m.If(written_ones[part].any()):
                    m.d.sync += storage[reg.name, field.name].eq(0)
            elif kind == "pulse":
                m.d.sync += getattr(self, field.name).eq(written_ones[part].any())
                if self._ahead:
                    m.d.comb += getattr(self, f"{field.name}_ahead").eq(
                        written_ones[part].any())

