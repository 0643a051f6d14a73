"""A wrapper registering every port of a component: the core measured as inside a design.

:func:`~dptbd.hw.flow.synth.synthesize` brings every port of the synthesised module to a
package pin, with the pins unconstrained. A flip-flop that drives an output port, or logic
fed by an input port, is then placed next to its pin, and the core's own register-to-
register paths through it (the input credit of ``DPCore``: ``states.ready`` → ``pixels.ready``)
cross the chip: an artefact of the measurement, not of the core, which in a design sits
behind other registers (the AXI top level's adapters). ``RegisteredPorts(core)`` has the
core's signature and puts one register between every port and the core (on an ECP5 or
iCE40 the I/O-to-register paths are then the only ones at the pins and, unconstrained, are
not timed), as an out-of-context flow does. Its cells are counted with the core's, so the
``core-regio`` variant is for Fmax only.
"""

from __future__ import annotations

from amaranth.hdl import Module
from amaranth.lib import wiring
from amaranth.lib.wiring import Flow

__all__ = ["RegisteredPorts"]


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
        for path, member, outer in self.signature.flatten(self):
            inner = core
            for part in path:
                inner = inner[part] if isinstance(part, int) else getattr(inner, part)
            if member.flow == Flow.In:
                m.d.sync += inner.eq(outer)
            else:
                m.d.sync += outer.eq(inner)
        return m
