"""Formal equivalence of a mutant and the original design (Yosys ``equiv_*``).

A mutant that survives the slice either escapes the checks or cannot change any output
(an *equivalent* mutant: a bit the design never reads, a fraction bit truncation drops, a
select whose both inputs are equal whenever it matters). :func:`prove_equivalent` asks
Yosys: the original (``gold``) and the mutant (``gate``, the one ``mutate`` command applied
with no ``mutsel``) are prepared as for the mutant design (:data:`~.netlist.PREPARE`),
memories mapped to flip-flops, then ``equiv_make gold gate`` pairs their signals by name,
``equiv_struct`` merges the pairs driven by the same cells from the same inputs (most of
them), ``equiv_simple -seq N`` proves each pair from its input cone over N cycles and
``equiv_induct -seq N`` proves the rest by temporal induction (every pair equal in N
consecutive cycles implies equal in the next), and ``equiv_status -assert`` fails if any
pair is unproven. A proof holds for every input sequence from every state where the paired
signals agree (in particular from reset); an unproven pair is not a counterexample: the
mutant is then reported ``not proven``.
"""

from __future__ import annotations

import dataclasses
import subprocess
import time

from dptbd.config import DPConfig
from dptbd.sim.mutation.netlist import DESIGN_TOPS, Mutation, _prepared, run_yosys, top_rtlil

__all__ = ["SEQ", "TIMEOUT", "Equivalence", "equivalence_script", "prove_equivalent"]

#: Cycles of ``equiv_simple`` / ``equiv_induct``.
SEQ = 2
#: Seconds one proof may take before it is reported ``timeout``.
TIMEOUT = 900.0


@dataclasses.dataclass(frozen=True)
class Equivalence:
    """``verdict``: ``equivalent`` (proven), ``not proven`` (a pair Yosys could not prove
    equal), ``timeout`` or ``error`` (Yosys failed otherwise); the last lines of its log."""

    verdict: str
    detail: str
    seconds: float


def equivalence_script(rtlil: str, design: str, command: str, seq: int = SEQ) -> str:
    """The Yosys script proving ``command`` (a ``mutate`` command) equivalent on the top
    ``design`` read from ``rtlil``."""
    top = DESIGN_TOPS[design]
    return "\n".join([
        # the mutant first: a fresh session numbers Yosys' own cells ($procmux$N) as the
        # session that listed the mutations did
        _prepared(rtlil, design), command, f"rename {top} gate", "design -stash gate",
        _prepared(rtlil, design), f"rename {top} gold", "design -stash gold",
        "design -copy-from gold -as gold gold", "design -copy-from gate -as gate gate",
        "memory_map", "opt_clean", "equiv_make gold gate equiv", "hierarchy -top equiv",
        "equiv_struct", f"equiv_simple -seq {int(seq)}", f"equiv_induct -seq {int(seq)}",
        "equiv_status -assert"])


def prove_equivalent(cfg: DPConfig, design: str, mutation: Mutation | str, *,
                     seq: int = SEQ, timeout: float = TIMEOUT) -> Equivalence:
    """Prove ``mutation`` of ``design``'s top for ``cfg`` equivalent to the original."""
    command = mutation.command if isinstance(mutation, Mutation) else str(mutation)
    text, _ = top_rtlil(cfg, design)
    start = time.perf_counter()
    try:
        run_yosys(equivalence_script(text, design, command, seq), timeout=timeout)
    except subprocess.TimeoutExpired:
        return Equivalence("timeout", f"no proof within {timeout:g} s",
                           time.perf_counter() - start)
    except RuntimeError as exc:
        lines = [line for line in str(exc).splitlines() if line.strip()]
        verdict = "not proven" if "unproven $equiv cells" in str(exc) else "error"
        return Equivalence(verdict, "\n".join(lines[-4:]), time.perf_counter() - start)
    return Equivalence("equivalent", "", time.perf_counter() - start)
