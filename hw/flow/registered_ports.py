"""A wrapper registering every port of a component: the core measured as inside a design.

:func:`~dptbd.hw.flow.synth.synthesize` brings every port of the synthesised module to a
package pin, with the pins unconstrained. A flip-flop that drives an output port, or logic
fed by an input port, is then placed next to its pin, and the core's own register-to-
register paths through it (the input credit of ``DPCore``: ``states.ready`` → ``pixels.ready``)
cross the chip: an artefact of the measurement, not of the core, which in a design sits
behind other registers (the AXI top level's adapters). ``RegisteredPorts(core)`` has the
core's signature and puts one register between every port and the core (on an ECP5 or
iCE40 the I/O-to-register paths are then the only ones at the pins and, unconstrained, are
not timed), as an out-of-context flow does; a top level with its own ``aclk`` / ``aresetn``
(:class:`~dptbd.hw.axi_top.AXITop`) keeps those two as they are, its port registers on that
clock, reset by ``aresetn``. Its cells are counted with the core's, so the ``core-regio``
and ``axi-regio`` variants are for Fmax only. :class:`FoldedPorts` folds the ports of a top level
with more ports than the package has pins onto two pins.
"""

from __future__ import annotations

from amaranth.hdl import Cat, ClockDomain, Module, Signal, Value
from amaranth.lib import wiring
from amaranth.lib.wiring import Flow, In, Out

__all__ = ["RegisteredPorts", "FoldedPorts"]


class RegisteredPorts(wiring.Component):
    """``core`` with a register on each of its ports (module docstring).

    Parameters
    ----------
    core : amaranth.lib.wiring.Component
        The component to wrap; the wrapper has its signature, and delays every input and
        every output by one cycle. Its ``latency``, ``schedule``, ``lut_style``,
        ``core_options`` and ``output_fifo_depth`` are the core's (for the manifest).
    """

    def __init__(self, core: wiring.Component):
        self._core = core
        super().__init__(core.signature)

    def __getattr__(self, name):
        if name in ("latency", "schedule", "lut_style", "core_options", "output_fifo_depth",
                    "config"):
            return getattr(self._core, name)
        raise AttributeError(name)

    def elaborate(self, platform):
        m = Module()
        m.submodules.core = core = self._core
        domain = m.d.sync
        if "aclk" in self.signature.members:
            # a top level with its own clock and reset (AXITop): both pass straight through,
            # the port registers are on a domain of the same clock and reset
            # (from the core's aclk, as the core's own domain: one edge in simulation)
            m.domains.regio = regio = ClockDomain("regio", local=True)
            m.d.comb += [core.aclk.eq(self.aclk), core.aresetn.eq(self.aresetn),
                         regio.clk.eq(core.aclk), regio.rst.eq(~core.aresetn)]
            domain = m.d.regio
        for path, member, outer in self.signature.flatten(self):
            if path in (("aclk",), ("aresetn",)):
                continue
            inner = core
            for part in path:
                inner = inner[part] if isinstance(part, int) else getattr(inner, part)
            if member.flow == Flow.In:
                domain += inner.eq(outer)
            else:
                domain += outer.eq(inner)
        return m


class FoldedPorts(wiring.Component):
    """A top level with its own ``aclk`` / ``aresetn`` (:class:`~dptbd.hw.axi_top.AXITop`)
    behind two pins: every other input fed from a shift register on ``fold_in``, every
    output registered and XOR-folded, one register per level of 4, onto ``fold_out``.

    For measuring a core with more ports than the package has pins (``dptbd_axi`` with its
    state store outside, 221 pins, on the iCE40 HX8K's ct256, 206 I/O): the inputs take any
    value and every output bit reaches ``fold_out``, so synthesis removes nothing, and the
    wrapper's own paths are one LUT level between registers. Its cells are counted with the
    core's (about one flip-flop per port bit), so the ``axi-ext`` variant is for Fmax and an
    upper bound of the cost. Members: ``aclk``, ``aresetn``, ``fold_in`` (In), ``fold_out``
    (Out); ``config``, ``latency`` and ``core_options`` are the core's. A core without
    ``aclk`` (on the ``sync`` domain: :class:`~dptbd.hw.dp_core.DPCore`,
    :class:`~dptbd.hw.wide.DPCoreWide`) is wrapped on that domain, with the members
    ``fold_in`` and ``fold_out`` only.
    """

    def __init__(self, core: wiring.Component):
        self._core = core
        # a core without aclk (DPCore, DPCoreWide) runs on the sync domain, and so does the
        # wrapper: then its members are fold_in and fold_out only
        self._own_clock = "aclk" in core.signature.members
        clock = {"aclk": In(1), "aresetn": In(1)} if self._own_clock else {}
        super().__init__({**clock, "fold_in": In(1), "fold_out": Out(1)})

    def __getattr__(self, name):
        if name in ("latency", "core_options", "config"):
            return getattr(self._core, name)
        raise AttributeError(name)

    def elaborate(self, platform):
        m = Module()
        m.submodules.core = core = self._core
        if self._own_clock:
            # the wrapper's own domain on the same clock and reset as the core's
            m.domains.fold = fold = ClockDomain("fold", local=True)
            m.d.comb += [fold.clk.eq(self.aclk), fold.rst.eq(~self.aresetn),
                         core.aclk.eq(self.aclk), core.aresetn.eq(self.aresetn)]
            domain = m.d.fold
        else:
            domain = m.d.sync
        inputs, outputs = [], []
        for path, member, inner in core.signature.flatten(core):
            if path[-1] in ("aclk", "aresetn"):
                continue
            (inputs if member.flow == Flow.In else outputs).append(inner)
        width = sum(len(Value.cast(v)) for v in inputs)
        chain = Signal(width)
        domain += chain.eq(Cat(self.fold_in, chain[:-1]))
        offset = 0
        for value in inputs:
            n = len(Value.cast(value))
            m.d.comb += value.eq(chain[offset:offset + n])
            offset += n
        level = Signal(sum(len(Value.cast(v)) for v in outputs))
        domain += level.eq(Cat(*outputs))
        while len(level) > 1:
            folded = Signal((len(level) + 3) // 4)
            domain += folded.eq(Cat(*[level[i:i + 4].xor() for i in range(0, len(level), 4)]))
            level = folded
        m.d.comb += self.fold_out.eq(level)
        return m
