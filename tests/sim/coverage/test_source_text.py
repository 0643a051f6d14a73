"""``dptbd.sim.coverage.source_text``: the coverage build's text keeps Amaranth's processes
as ``if`` / ``casez``, every decision marked with its Amaranth line; mapped back by
:func:`~dptbd.sim.coverage.code.source_map` to the ``m.If`` / ``m.Elif`` / ``m.Else`` /
``m.Case`` lines; the generators write it only inside :func:`coverage_text`."""


import inspect

from amaranth import Module, Signal
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

from dptbd.sim.coverage.code import source_map
from dptbd.sim.coverage.source_text import coverage_text, coverage_verilog


class Chain(wiring.Component):
    a: In(1)
    b: In(1)
    sel: In(2)
    q: Out(2)
    r: Out(2)

    def elaborate(self, platform):
        m = Module()
        state = Signal(2)
        with m.If(self.a):                 # IF
            m.d.sync += state.eq(1)
        with m.Elif(self.b):               # ELIF
            m.d.sync += state.eq(2)
        with m.Else():                     # ELSE
            m.d.sync += state.eq(3)        # ELSE-BODY
        with m.Switch(self.sel):
            with m.Case(0):                # CASE0
                m.d.comb += self.r.eq(1)
            with m.Case(1, 2):             # CASE12
                m.d.comb += self.r.eq(2)
        m.d.comb += self.q.eq(state)
        return m


def _line(tag: str) -> str:
    lines, start = inspect.getsourcelines(Chain.elaborate)
    offset = next(i for i, text in enumerate(lines) if text.rstrip().endswith(f"# {tag}"))
    return f"tests/sim/coverage/test_source_text.py:{start + offset}"


def test_every_decision_carries_its_amaranth_line():
    text = coverage_verilog(Chain(), "chain")
    srcmap, _ = source_map(text)
    lines = text.splitlines()
    by_text = {}
    for number, src in srcmap.items():
        by_text.setdefault(lines[number - 1].strip().split(" (")[0].split(":")[0], set()).add(src)
    assert "always @*" in text and "casez" in text            # processes kept
    assert _line("IF") in by_text["if"]
    assert by_text["end else if"] == {_line("ELIF")}
    assert by_text["end else begin"] == {_line("ELSE-BODY")}  # m.Else: its first statement
    assert by_text["casez"] == {_line("CASE0")}               # a switch: its first case
    assert by_text["2'h0"] == {_line("CASE0")}
    assert _line("CASE12") in set().union(*by_text.values())


def test_generators_write_it_only_inside_the_context():
    from dptbd.hw.flow.to_verilog import to_verilog

    plain = to_verilog(Chain(), "chain")
    with coverage_text():
        covered = to_verilog(Chain(), "chain")
    assert "always @*" not in plain and "src" not in plain
    assert covered == coverage_verilog(Chain(), "chain")
    assert to_verilog(Chain(), "chain") == plain              # the context is left
