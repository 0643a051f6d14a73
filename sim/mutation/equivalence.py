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

A mutated signal itself usually differs (an inverted low bit of a partial sum that the
truncation drops, a register bit nothing reads), and so do the signals it feeds before
the difference is masked; paired, they are unprovable and make every pair whose
induction leans on them unprovable too. The proof therefore *unpairs* them, in rounds
(:data:`ROUNDS`): first the mutated wire (its gate copy renamed, so ``equiv_make`` keeps
gold's and gate's copies apart, each driven by its own logic), then every internal wire
left with an unproven pair, and when those are unpaired already, the other names of
their bits (:func:`aliases`, e.g. a port of a flattened submodule and the wire it drives).
Unpairing only drops assumptions, so what is then proven
still holds; the mutant is ``equivalent`` when every remaining pair, the top's outputs
always among them, is proven, and ``not proven`` when an output is unproven or a round
unpairs nothing new.
"""

from __future__ import annotations

import dataclasses
import functools
import re
import subprocess
import time

from dptbd.config import DPConfig
from dptbd.sim.mutation.netlist import DESIGN_TOPS, Mutation, _prepared, run_yosys, top_rtlil

__all__ = ["SEQ", "ROUNDS", "TIMEOUT", "Equivalence", "CLOCK_UNPROVEN", "clock_mutation",
           "equivalence_script", "unproven_wires",
           "unproven_count", "top_ports", "aliases", "prove_equivalent"]

#: Cycles of ``equiv_simple`` / ``equiv_induct`` (4: a partial sum's constant-zero low bits
#: are three register levels of the shift-and-add tree behind its constant leaves).
SEQ = 4
#: Proof attempts, each unpairing more signals.
ROUNDS = 4
#: Seconds one proof may take before it is reported ``timeout``.
TIMEOUT = 900.0


@dataclasses.dataclass(frozen=True)
class Equivalence:
    """``verdict``: ``equivalent`` (proven), ``not proven`` (a pair Yosys could not prove
    equal), ``timeout`` or ``error`` (Yosys failed otherwise); the last lines of its log."""

    verdict: str
    detail: str
    seconds: float


#: The verdict on a mutated clock input (:func:`clock_mutation`), given without a run.
CLOCK_UNPROVEN = Equivalence("not proven", "a clock input mutated: the proof takes every "
                             "flip-flop as one step of one clock, whatever its edge", 0.0)


def clock_mutation(command: str) -> bool:
    """Whether the ``mutate`` command ``command`` changes a flip-flop's clock input (its
    edge): both proofs take every flip-flop as one step of one clock (``equiv_*``'s model, the
    AIGER miter of :mod:`.reachable`), so they would prove such a mutant equivalent whatever
    it does."""
    return re.search(r"-port (?:CLK|C)(?: |$)", command) is not None


def equivalence_script(rtlil: str, design: str, command: str, seq: int = SEQ,
                       unpaired: tuple[str, ...] = ()) -> str:
    """The Yosys script proving ``command`` (a ``mutate`` command) equivalent on the top
    ``design`` read from ``rtlil``, the wires ``unpaired`` left unpaired (their gate copies
    renamed ``<name>$unpaired``); it writes ``equiv_status``'s report to ``status.txt``."""
    top = DESIGN_TOPS[design]
    renames = [f"rename \\{name} \\{name}$unpaired" for name in unpaired]
    return "\n".join([
        # the mutant first: a fresh session numbers Yosys' own cells ($procmux$N) as the
        # session that listed the mutations did
        _prepared(rtlil, design), command, f"rename {top} gate", "design -stash gate",
        _prepared(rtlil, design), f"rename {top} gold", "design -stash gold",
        "design -copy-from gold -as gold gold", "design -copy-from gate -as gate gate",
        "memory_map", "opt_clean", *(["cd gate", *renames, "cd .."] if renames else []),
        "equiv_make gold gate equiv", "hierarchy -top equiv",
        "equiv_struct", f"equiv_simple -seq {int(seq)}", f"equiv_induct -seq {int(seq)}",
        "tee -q -o status.txt equiv_status"])


def unproven_wires(status: str) -> list[str]:
    """The names of the wires with an unproven pair in ``equiv_status``'s report, sorted: a
    bit of a wide wire (``\\name_gold [3]``) or a one-bit wire (``\\name_gold``, no index)."""
    return sorted(set(re.findall(r"^\s*Unproven \$equiv \S+: \\(\S+?)_gold(?: \[\d+\])? \\",
                                 status, flags=re.M)))


def unproven_count(status: str) -> int:
    """The number of unproven ``$equiv`` cells ``equiv_status`` reports.

    Raises
    ------
    RuntimeError
        The report names no ``$equiv`` cells (nothing was compared: no proof).
    """
    found = re.search(r"Of those cells (\d+) are proven and (\d+) are unproven", status)
    if found is None:
        raise RuntimeError(f"equiv_status compared nothing: {status.strip()[:200]!r}")
    return int(found.group(2))


def top_ports(rtlil: str, design: str) -> frozenset[str]:
    """The port names of ``design``'s top module in ``rtlil``."""
    top = DESIGN_TOPS[design]
    body = rtlil.split(f"module \\{top}\n", 1)[1].split("\nend\n", 1)[0]
    return frozenset(re.findall(r"^\s*wire (?:width \d+ )?(?:input|output|inout) \d+\s+\\(\S+)$",
                                body, flags=re.M))


@functools.lru_cache(maxsize=4)
def aliases(rtlil: str, design: str) -> dict[str, frozenset[str]]:
    """Each public wire of ``design``'s prepared top read from ``rtlil`` and the wires
    connected to it directly (``connect``, whole or a slice): other names of its bits, which
    ``equiv_make`` pairs too."""
    prepared = run_yosys(_prepared(rtlil, design) + "\nwrite_rtlil prepared.il",
                         ("prepared.il",))["prepared.il"]
    near: dict[str, set[str]] = {}
    for a, b in re.findall(r"^  connect \\(\S+)(?: \[[\d:]+\])? \\(\S+)(?: \[[\d:]+\])?$",
                           prepared, flags=re.M):
        near.setdefault(a, set()).add(b)
        near.setdefault(b, set()).add(a)
    return {name: frozenset(others) for name, others in near.items()}


def prove_equivalent(cfg: DPConfig, design: str, mutation: Mutation | str, *,
                     seq: int = SEQ, timeout: float = TIMEOUT,
                     rounds: int = ROUNDS) -> Equivalence:
    """Prove ``mutation`` of ``design``'s top for ``cfg`` equivalent to the original, in
    up to ``rounds`` attempts, each unpairing the internal wires the last left unproven
    (module doc); ``timeout`` seconds for all of them."""
    command = mutation.command if isinstance(mutation, Mutation) else str(mutation)
    wire = mutation.wire if isinstance(mutation, Mutation) else None
    if clock_mutation(command):
        return CLOCK_UNPROVEN
    text, _ = top_rtlil(cfg, design)
    ports = top_ports(text, design)
    unpaired = () if wire is None or wire in ports else (wire,)
    start = time.perf_counter()
    for attempt in range(max(1, int(rounds))):
        left = timeout - (time.perf_counter() - start)
        try:
            status = run_yosys(equivalence_script(text, design, command, seq, unpaired),
                               ("status.txt",), timeout=max(1.0, left))["status.txt"]
        except subprocess.TimeoutExpired:
            return Equivalence("timeout", f"no proof within {timeout:g} s",
                               time.perf_counter() - start)
        except RuntimeError as exc:
            lines = [line for line in str(exc).splitlines() if line.strip()]
            return Equivalence("error", "\n".join(lines[-4:]), time.perf_counter() - start)
        try:
            count = unproven_count(status)
        except RuntimeError as exc:
            return Equivalence("error", str(exc), time.perf_counter() - start)
        wires = unproven_wires(status)
        if count == 0:
            return Equivalence("equivalent", _unpaired_note(unpaired),
                               time.perf_counter() - start)
        if not wires:                   # unproven cells whose lines were not understood
            return Equivalence("not proven", f"{count} unproven $equiv cells; "
                               f"{_unpaired_note(unpaired)}", time.perf_counter() - start)
        outputs = [w for w in wires if w in ports]
        new = tuple(w for w in wires if w not in ports and w not in unpaired)
        if not new and not outputs:     # still paired through another name of their bits
            near = aliases(text, design)
            new = tuple(sorted({a for w in wires for a in near.get(w, ())
                                if a not in ports and a not in unpaired}))
        if outputs or not new or attempt == rounds - 1:
            what = (f"output {', '.join(outputs)} unproven" if outputs else
                    f"{len(wires)} wires unproven: {', '.join(wires[:6])}"
                    + (" …" if len(wires) > 6 else ""))
            return Equivalence("not proven", f"{what}; {_unpaired_note(unpaired)}",
                               time.perf_counter() - start)
        unpaired = tuple(sorted(set(unpaired) | set(new)))
    raise AssertionError("unreachable")


def _unpaired_note(unpaired: tuple[str, ...]) -> str:
    return f"unpaired: {', '.join(unpaired)}" if unpaired else "every signal paired"
