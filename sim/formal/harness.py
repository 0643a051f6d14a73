"""The base of every formal harness: a top-level ``Elaboratable`` with its own clock and
reset, free inputs, and the first cycle a reset.
"""

from __future__ import annotations

from amaranth.hdl import (Assume, ClockDomain, Const, Elaboratable, Fragment, MemoryInstance,
                          Module, Shape, Signal, Value)
from amaranth.lib import wiring

from dptbd.sim.formal.properties import Past

__all__ = ["Harness", "Elaborated"]


class Harness(Elaboratable):
    """A proof harness: :meth:`check` builds the design and its properties.

    ``clk`` and ``rst`` (the design's synchronous reset, ``~aresetn``) are ports; the solver
    chooses ``rst`` in every cycle but the first, which is a reset. Every input of the
    design that the harness does not drive is a free port (:meth:`free`,
    :meth:`free_inputs`), chosen by the solver in every cycle.
    """

    def __init__(self):
        self.clk = Signal()
        self.rst = Signal()
        self._inputs: list[Signal] = []

    def ports(self) -> list[Signal]:
        return [self.clk, self.rst, *self._inputs]

    def free(self, shape, name: str) -> Signal:
        """A new free input port."""
        signal = Signal(shape, name=name)
        self._inputs.append(signal)
        return signal

    def free_inputs(self, m, component: wiring.Component, prefix: str,
                    skip: tuple = ()) -> None:
        """Drive every ``In`` port of ``component`` not named in ``skip`` from a free input."""
        for path, member, value in component.signature.flatten(component):
            name = "__".join(str(p) for p in path)
            if member.flow == wiring.In and name not in skip and path[0] not in skip:
                width = len(Value.cast(value))
                m.d.comb += value.eq(self.free(width, f"{prefix}__{name}"))

    def elaborate(self, platform):
        m = Module()
        # the harness's own registers are in this domain; a design that defines a sync
        # domain of its own (dptbd_axi, from aclk / aresetn) is added renamed (harnesses/top.py)
        m.domains.sync = sync = ClockDomain("sync")
        m.d.comb += [sync.clk.eq(self.clk), sync.rst.eq(self.rst)]
        started = Signal(reset_less=True)
        m.d.sync += started.eq(1)
        with m.If(~started):
            m.d.comb += Assume(self.rst)
        self.check(m, Past(m, self.rst))
        return m

    def check(self, m, past) -> None:  # pragma: no cover - every harness overrides it
        raise NotImplementedError


class Elaborated:
    """A component elaborated once, so that a harness can reach its inner signals: add
    ``fragment`` as the submodule (not the component, which would be elaborated anew)
    and read :meth:`signal` / :meth:`sub` for invariants that k-induction needs."""

    def __init__(self, component):
        self.component = component
        self.fragment = Fragment.get(component, None)

    def sub(self, name: str) -> "Elaborated":
        """The submodule ``name`` of this component (its elaborated fragment)."""
        for fragment, sub_name, *_ in self.fragment.subfragments:
            if sub_name == name:
                view = Elaborated.__new__(Elaborated)
                view.component, view.fragment = fragment.origins[0], fragment
                return view
        raise KeyError(f"{type(self.component).__name__} has no submodule {name!r}")

    def rows(self, name: str) -> list[Signal]:
        """Every row of the memory ``name`` (a :class:`~amaranth.lib.memory.Memory` among
        this component's submodules, such as a FIFO's ``storage``), each read by an
        asynchronous port added to it for the proof: what a FIFO holds is state that
        k-induction must be told about. Call it once per memory."""
        memory = self.sub(name)
        if not isinstance(memory.fragment, MemoryInstance):
            raise KeyError(f"{type(self.component).__name__}'s submodule {name!r} is not a "
                           f"memory")
        depth, width = memory.component.depth, Shape.cast(memory.component.shape).width
        rows = []
        for index in range(depth):
            row = Signal(width, name=f"{name}_row{index}")
            memory.fragment.read_port(domain="comb", addr=Const(index, (depth - 1).bit_length()),
                                      data=row, en=Const(1), transparent_for=())
            rows.append(row)
        return rows

    def signal(self, name: str) -> Signal:
        """The signal ``name`` that this component's own statements drive."""
        for statements in self.fragment.statements.values():
            for statement in statements:
                for signal in statement._lhs_signals():
                    if signal.name == name:
                        return signal
        raise KeyError(f"{type(self.component).__name__} drives no signal {name!r}")
