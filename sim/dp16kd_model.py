"""A behavioural ECP5 DP16KD, as :func:`dptbd.hw.dp16kd.dp16kd_memory` uses it, to simulate
the ``"dp16kd"`` styles' wiring in Amaranth (the flow has no simulation model of the
primitive): port A writes ``DIA`` at ``ADA`` when ``WEA``; port B registers ``ADB`` when
``CEB`` (the array's read) and loads the array's word into ``DOB``'s output register when
``OCEB`` (``REGMODE_B = "OUTREG"``), both at the same edge. The address is ``ADx[13:k]`` with
k = 4, 3, 2, 1, 0 for 18, 9, 4, 2, 1 data bits (Yosys's mapping); at 18 bits ``ADA[1:0]``
are byte enables, which must both be set.

The tests simulate with it (``tests/helpers/dp16kd_model.py``) and the formal harnesses of
the ECP5 build prove through it (:mod:`dptbd.sim.formal.harnesses`): Yosys has the DP16KD
as a blackbox only. :func:`modelled_dp16kd` builds every DP16KD of the designs elaborated
inside it as this model (for tops whose DP16KD styles take no ``cell`` argument)."""

from __future__ import annotations

import contextlib

from amaranth.hdl import Cat, Elaboratable, Module, Signal
from amaranth.lib.memory import Memory

__all__ = ["ADDRESS_LSB", "DP16KDModel", "modelled_dp16kd"]

ADDRESS_LSB = {18: 4, 9: 3, 4: 2, 2: 1, 1: 0}


class DP16KDModel(Elaboratable):
    """One DP16KD from :func:`~dptbd.hw.dp16kd.dp16kd_memory`'s ``Instance`` keyword
    arguments (its ``cell``), in the configuration given (the module doc)."""

    def __init__(self, **ports):
        assert ports["p_REGMODE_B"] == "OUTREG" and ports["p_REGMODE_A"] == "NOREG"
        assert ports["p_DATA_WIDTH_A"] == ports["p_DATA_WIDTH_B"]
        self.width = ports["p_DATA_WIDTH_B"]
        self.lsb = ADDRESS_LSB[self.width]
        if self.width == 18:
            assert ports["i_ADA0"] == 1 and ports["i_ADA1"] == 1, "both bytes written"
        self.ports = ports

    def elaborate(self, platform):
        m = Module()
        p = self.ports
        # the array's words up to the highest address pin not tied to 0 (the others can be
        # neither written nor read): the same behaviour, a smaller memory for a solver
        pins = [k - self.lsb + 1 for k in range(self.lsb, 14)
                if not all(isinstance(p[f"i_AD{x}{k}"], int) and p[f"i_AD{x}{k}"] == 0
                           for x in "AB")]
        m.submodules.array = array = Memory(shape=self.width, depth=1 << max(pins, default=1),
                                            init=[])
        write = array.write_port()
        read = array.read_port()
        out = Signal(self.width)
        m.d.comb += [
            write.addr.eq(Cat(*[p[f"i_ADA{k}"] for k in range(self.lsb, 14)])[:len(write.addr)]),
            write.data.eq(Cat(*[p[f"i_DIA{k}"] for k in range(self.width)])),
            write.en.eq(p["i_WEA"]),
            read.addr.eq(Cat(*[p[f"i_ADB{k}"] for k in range(self.lsb, 14)])[:len(read.addr)]),
            read.en.eq(p["i_CEB"]),
        ]
        m.d.comb += [p[f"o_DOB{k}"].eq(out[k]) for k in range(self.width) if f"o_DOB{k}" in p]
        with m.If(p["i_OCEB"]):
            m.d.sync += out.eq(read.data)
        return m


@contextlib.contextmanager
def modelled_dp16kd():
    """Within the block every DP16KD that :func:`~dptbd.hw.dp16kd.dp16kd_memory` builds
    without a ``cell`` is a :class:`DP16KDModel` (elaborate the design inside it:
    :class:`~dptbd.sim.formal.harness.Elaborated`)."""
    import dptbd.hw.dp16kd as dp16kd

    original = dp16kd.Instance

    def instance(kind, **ports):
        if kind != "DP16KD":
            return original(kind, **ports)
        return DP16KDModel(**ports)

    dp16kd.Instance = instance
    try:
        yield
    finally:
        dp16kd.Instance = original
