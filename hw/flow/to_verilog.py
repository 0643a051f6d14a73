"""Verilog text of a component, with no combinational ``always @*`` block.

:func:`amaranth.back.verilog.convert` keeps every combinational process as an ``always @*``
block (``proc -nomux``). Such a block runs only when one of its inputs changes, and Yosys'
trigger for time 0 (a dummy ``reg … = 0`` read by the block) raises no event where
declaration initialisers are SystemVerilog ones (``iverilog -g2012``): a block whose inputs
are all constant from time 0 — a reset held from power-up, idle inputs — never runs before
the first clock edge, and the flip-flop it feeds loads X. A register's reset value is then
X during the reset and in the first cycle after it (``pixels.ready`` among them, so a pixel
offered in that cycle is accepted as X), and a register that feeds only itself (a counter,
an FSM state) stays X for good: the segmenter never left its clearing scan.

:func:`to_verilog` runs the same conversion with Yosys' ``proc`` in full: every process
becomes multiplexers, written as continuous ``assign`` statements, which every simulator
evaluates at time 0, and flip-flops ``always @(posedge clk) q <= d;``. The logic is the
same (a synthesis tool runs this ``proc`` itself); only the text differs. Internal nets
get Yosys' ``_NNNN_`` names (with ``-norename``, the ``$pmux`` functions' escaped
``\\$procmux$…`` names are taken for system functions by Icarus 11); every named signal
keeps its name.
"""

from __future__ import annotations

import contextvars

from amaranth._toolchain.yosys import find_yosys
from amaranth.back import rtlil

__all__ = ["to_verilog"]

#: Yosys' commands after ``read_rtlil``: processes to multiplexers, ROMs and flip-flops
#: (the ``proc`` a synthesis tool runs on Amaranth's own conversion, so both texts map to
#: the same cells: a ``case`` of constants becomes a ROM as it would there), memories
#: collected as Amaranth's conversion does.
YOSYS_PASSES = ("proc", "memory_collect", "write_verilog")

#: Another text for every generator in this context, ``(component, name) -> str``: the
#: coverage build's (:func:`dptbd.sim.coverage.source_text.coverage_text`); None: this one.
TEXT: contextvars.ContextVar = contextvars.ContextVar("dptbd_verilog_text", default=None)


def to_verilog(component, name: str) -> str:
    """The Verilog text of ``component`` as module ``name`` (see the module doc); ports as
    :func:`amaranth.back.verilog.convert` names them (from the component's signature)."""
    if TEXT.get() is not None:
        return TEXT.get()(component, name)
    text = rtlil.convert(component, name=name, emit_src=False)
    yosys = find_yosys(lambda version: version >= (0, 40))   # Amaranth's own requirement
    script = "\n".join([f"read_rtlil <<rtlil\n{text}\nrtlil", *YOSYS_PASSES])
    # ignore_warnings as in Amaranth's conversion (Yosys warns on attributes it keeps)
    return yosys.run(["-q", "-"], script, ignore_warnings=True)
