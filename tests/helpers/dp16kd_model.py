"""A behavioural ECP5 DP16KD, as :func:`dptbd.hw.dp16kd.dp16kd_memory` uses it, to simulate
the ``"dp16kd"`` styles' wiring in Amaranth (the flow has no simulation model of the
primitive): port A writes ``DIA`` at ``ADA`` when ``WEA``; port B registers ``ADB`` when
``CEB`` (the array's read) and loads the array's word into ``DOB``'s output register when
``OCEB`` (``REGMODE_B = "OUTREG"``), both at the same edge. The address is ``ADx[13:k]`` with
k = 4, 3, 2, 1, 0 for 18, 9, 4, 2, 1 data bits (Yosys's mapping); at 18 bits ``ADA[1:0]``
are byte enables, which must both be set."""

from amaranth.hdl import Cat, Elaboratable, Module, Signal
from amaranth.lib.memory import Memory

ADDRESS_LSB = {18: 4, 9: 3, 4: 2, 2: 1, 1: 0}


class DP16KDModel(Elaboratable):
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
        m.submodules.array = array = Memory(shape=self.width, depth=1 << (14 - self.lsb),
                                            init=[])
        write = array.write_port()
        read = array.read_port()
        out = Signal(self.width)
        m.d.comb += [
            write.addr.eq(Cat(*[p[f"i_ADA{k}"] for k in range(self.lsb, 14)])),
            write.data.eq(Cat(*[p[f"i_DIA{k}"] for k in range(self.width)])),
            write.en.eq(p["i_WEA"]),
            read.addr.eq(Cat(*[p[f"i_ADB{k}"] for k in range(self.lsb, 14)])),
            read.en.eq(p["i_CEB"]),
        ]
        m.d.comb += [p[f"o_DOB{k}"].eq(out[k]) for k in range(self.width) if f"o_DOB{k}" in p]
        with m.If(p["i_OCEB"]):
            m.d.sync += out.eq(read.data)
        return m


def model_dp16kd_cells(monkeypatch):
    """Build every ``Instance("DP16KD", …)`` of :mod:`dptbd.hw.dp16kd` as a
    :class:`DP16KDModel` (for whole cores whose DP16KD styles take no cell argument)."""
    import dptbd.hw.dp16kd as dp16kd

    def instance(kind, **ports):
        assert kind == "DP16KD"
        return DP16KDModel(**ports)

    monkeypatch.setattr(dp16kd, "Instance", instance)
