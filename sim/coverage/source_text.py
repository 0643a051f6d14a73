"""The Verilog text of the coverage build: Amaranth's processes kept, every decision marked
with its Amaranth source line.

Why not the text of the other builds: :func:`dptbd.hw.flow.to_verilog.to_verilog` runs
Yosys' full ``proc``, so every ``m.If`` / ``m.Switch`` / ``m.FSM`` becomes a multiplexer in
a continuous ``assign``, and the flip-flops are ``always @(posedge clk) q <= d;``: on that
text Verilator's line points are one per always block (each runs every cycle) and a branch
of the gateware has no point at all.

So the coverage build converts as :func:`amaranth.back.verilog.convert` does (Yosys
``proc -nomux -norom``): each Amaranth process stays an ``always @*`` block of ``if`` /
``casez`` statements, one per ``m.If``/``m.Elif``/``m.Else`` chain, ``m.Switch`` and
``m.FSM`` state, and Verilator puts a line point on each of their branches. Amaranth's own
RTLIL writer puts a ``src`` attribute on the process only (the signal's declaration);
:class:`!_SourceEmitter` also gives every ``switch`` the ``src`` of its first ``m.If`` /
``m.Case`` and every ``case`` the ``src`` of its ``m.If`` / ``m.Elif`` / ``m.Case``
(an ``m.Else`` or default case: the first statement inside it), which Yosys writes as
``(* src = "file.py:line" *)`` before the ``if`` / ``casez`` (and the case items) —
:mod:`dptbd.sim.coverage.code` maps each point back through them.

The ``always @*`` start-up problem (``to_verilog``'s docstring) is Icarus' (4-state): a
Verilator model evaluates every block at time 0, so this text simulates as the other. The
coverage build's runs are checked bit-exact against the golden model like every other run,
which verifies the text itself.
"""

from __future__ import annotations

import contextlib
import pathlib
import threading

import amaranth
from amaranth.back import rtlil
from amaranth.hdl import _nir

__all__ = ["coverage_verilog", "coverage_text"]

#: Yosys' commands after ``read_rtlil``: Amaranth's own conversion
#: (:func:`amaranth.back.verilog.convert`), processes kept.
YOSYS_PASSES = ("proc -nomux -norom", "memory_collect", "write_verilog -norename")

_LOCK = threading.Lock()


#: The attribute on every switch listing the ``src`` of each of its cases in order, ``|``
#: between them: Yosys writes an ``if`` / ``else if`` chain with the switch's attributes
#: only, so the k-th branch of a chain is the k-th entry.
CASES_ATTRIBUTE = "dptbd_cases"

_AMARANTH = str(pathlib.Path(amaranth.__file__).resolve().parent)


class _Switch(rtlil.Switch):
    def __init__(self, sel, src_loc):
        super().__init__(sel)
        self.src_loc = src_loc

    def case(self, patterns, src_loc=None):
        res = _Case(patterns, src_loc)
        if patterns:                     # as Amaranth: an empty pattern list is no case
            self.cases.append(res)
        return res

    def default(self, src_loc=None):
        res = _Case((), src_loc)
        self.cases.append(res)
        return res

    def emit(self, line):
        if self.src_loc is not None:
            line(f"attribute \\src {rtlil._const(rtlil._src(self.src_loc))}")
        cases = "|".join(rtlil._src(c.src_loc) if c.src_loc else "" for c in self.cases)
        line(f"attribute \\{CASES_ATTRIBUTE} {rtlil._const(cases)}")
        super().emit(line)


class _Case(rtlil.Case):
    def __init__(self, patterns, src_loc):
        super().__init__(patterns)
        self.src_loc = src_loc

    def emit(self, line):
        if self.src_loc is not None:
            line(f"attribute \\src {rtlil._const(rtlil._src(self.src_loc))}")
        super().emit(line)


def _first_src(cell, start, cond_net, netlist):
    """The src of the first assignment at or after ``start`` nested in ``cond_net``."""
    for assign in cell.assignments[start:]:
        search = assign.cond
        while True:
            if search == cond_net:
                return assign.src_loc
            if search == _nir.Net.from_const(1):
                break
            search = netlist.cells[search.cell].en
    return None


class _SourceEmitter(rtlil.ModuleEmitter):
    """Amaranth 0.5's emitter with ``src`` on every switch and case (see the module doc).

    ``emit_assignment_list`` is Amaranth 0.5.4's, the attributes added."""

    def emit_assignment_list(self, cell_idx, cell):
        netlist = self.netlist
        pos = 0

        def src(loc):
            # Amaranth's own lines (the sync reset's m.If, in hdl/_ir.py): the signal's
            if loc is None or str(pathlib.Path(loc[0]).resolve()).startswith(_AMARANTH):
                return cell.src_loc
            return loc

        def emit_assignments(case, cond):
            nonlocal pos
            while pos < len(cell.assignments):
                assign = cell.assignments[pos]
                if assign.cond == cond:
                    case.assign(self.sigspec(lhs[assign.start:assign.start + len(assign.value)]),
                                self.sigspec(assign.value))
                    pos += 1
                else:
                    search_cond = assign.cond
                    while True:
                        if search_cond == cond:
                            break
                        if search_cond == _nir.Net.from_const(1):
                            return
                        priority_cell_idx = search_cond.cell
                        priority_cell = netlist.cells[priority_cell_idx]
                        assert isinstance(priority_cell, _nir.PriorityMatch)
                        search_cond = priority_cell.en
                    test = _nir.Value()
                    first_src = None
                    for net in priority_cell.inputs:
                        if net != _nir.Net.from_const(1):
                            matches_cell = netlist.cells[net.cell]
                            assert isinstance(matches_cell, _nir.Matches)
                            test = matches_cell.value
                            first_src = matches_cell.src_loc
                            break
                    switch = _Switch(self.sigspec(test), src(first_src or priority_cell.src_loc))
                    case.contents.append(switch)
                    for bit, net in enumerate(priority_cell.inputs):
                        subcond = _nir.Net.from_cell(priority_cell_idx, bit)
                        if net == _nir.Net.from_const(1):
                            emit_assignments(switch.default(
                                src(_first_src(cell, pos, subcond, netlist))), subcond)
                        else:
                            matches_cell = netlist.cells[net.cell]
                            assert isinstance(matches_cell, _nir.Matches)
                            assert test == matches_cell.value
                            emit_assignments(switch.case(matches_cell.patterns,
                                                         src(matches_cell.src_loc)), subcond)

        lhs = _nir.Value(_nir.Net.from_cell(cell_idx, bit) for bit in range(len(cell.default)))
        proc = self.builder.process(src_loc=cell.src_loc)
        proc.assign(self.sigspec(lhs), self.sigspec(cell.default))
        emit_assignments(proc, _nir.Net.from_const(1))
        assert pos == len(cell.assignments)


@contextlib.contextmanager
def _source_emitter():
    with _LOCK:
        saved = rtlil.ModuleEmitter
        rtlil.ModuleEmitter = _SourceEmitter
        try:
            yield
        finally:
            rtlil.ModuleEmitter = saved


def coverage_verilog(component, name: str) -> str:
    """The Verilog text of ``component`` as module ``name`` for the coverage build (see the
    module doc); ports named as :func:`dptbd.hw.flow.to_verilog.to_verilog` names them."""
    from amaranth._toolchain.yosys import find_yosys

    with _source_emitter():
        text = rtlil.convert(component, name=name, emit_src=True)
    yosys = find_yosys(lambda version: version >= (0, 40))
    script = "\n".join([f"read_rtlil <<rtlil\n{text}\nrtlil", *YOSYS_PASSES])
    return yosys.run(["-q", "-"], script, ignore_warnings=True)


@contextlib.contextmanager
def coverage_text():
    """Within this context, the Verilog generators (through
    :func:`~dptbd.hw.flow.to_verilog.to_verilog`) write the coverage build's text."""
    from dptbd.hw.flow import to_verilog

    token = to_verilog.TEXT.set(coverage_verilog)
    try:
        yield
    finally:
        to_verilog.TEXT.reset(token)
