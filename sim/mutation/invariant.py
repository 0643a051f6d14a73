"""Equivalence from reset under a reachability invariant, the invariant proven with it.

:func:`~.reachable.prove_reachable` leaves a mutant unproven when its equivalence rests on
an invariant of the reachable states that signal correspondence (``&scorr``) cannot find
by itself: it proves only equalities of the miter's nodes (two signals equal, or a signal
constant) by induction, and an address that stays below W * H, or a flag that is 1 except
in the cycle after a reset, is neither. :func:`prove_under_invariant` names the invariant
(:class:`Invariant`: signals of the original's prepared netlist and a Verilog expression
over them) and makes it one of those nodes:

1. the invariant is proven on the original alone (:func:`prove_invariant`): the prepared
   top with a checker of the expression and an ``$assert`` on its result, ``miter -assert``
   (an output 1 where the assertion fails), ABC's ``&scorr`` and PDR from reset as
   :func:`~.reachable.prove_reachable` does. One that does not hold, or is not proven, is
   refused (:class:`InvariantError`, with PDR's counterexample or its limit);
2. the mutant's miter is built with the checker and its assertion in the original's copy
   (``gold``; asserted, not assumed): ``miter -equiv -make_assert`` turns the outputs'
   equality into a second assertion, and ``miter -assert`` gives one output, 1 where
   either fails. ``&scorr`` then has the invariant's node among its candidates (a node 1
   in every state it simulates) and proves it by induction together with the copies'
   equalities, each assumed in the step for the others; PDR works on what is left.

The output constant 0, or PDR's ``UNSAT``, proves both from reset (nothing is assumed: a
step that needed a false candidate would have failed); a counterexample is the mutant's,
the invariant being proven in step 1. The verdicts are :func:`~.reachable.prove_reachable`'s.
Both steps use ABC's ``scorr`` (:data:`~.reachable.CORRESPONDENCE`): ``&scorr`` leaves an
invariant's node unproven even where it is inductive by itself (a row counter's ``row <=
9``).

The invariants of the registries' entries proven so (``why`` naming
``prove_under_invariant``) are in ``equivalents/invariants.toml``, one ``[[invariant]]``
table each (:func:`load_invariants`)::

    [[invariant]]
    design = "dp4"
    mutation = "mutate -mode const0 -module dptbd_dp -cell ... -src hw/controller.py:198"
    name = "row at most H - 1"
    signals = { r = "core.controller.row" }
    holds = "r <= 4'd9"
"""

from __future__ import annotations

import dataclasses
import functools
import pathlib
import re
import time
import tomllib

from dptbd.config import DPConfig
from dptbd.errors import DptbdError
from dptbd.sim.mutation.equivalence import CLOCK_UNPROVEN, Equivalence, clock_mutation
from dptbd.sim.mutation.netlist import DESIGN_TOPS, Mutation, _prepared, run_yosys, top_rtlil
from dptbd.sim.mutation.reachable import PDR_SECONDS, TIMEOUT, TO_AIGER, solve_miter

__all__ = ["CHECKER", "INVARIANTS", "Invariant", "InvariantError", "parse_invariants",
           "load_invariants", "prepared_rtlil", "signal_widths",
           "checker_verilog", "with_checker", "invariant_script", "miter_script",
           "prove_invariant", "prove_under_invariant"]

#: The checker module's name, its instance's and its output's (``holds``).
CHECKER = "dptbd_invariant"

#: The invariants of the registries' entries proven under one (module doc).
INVARIANTS = pathlib.Path(__file__).resolve().parent / "equivalents" / "invariants.toml"

_KEYS = ("design", "mutation", "name", "signals", "holds")


class InvariantError(DptbdError):
    """An invariant that does not hold, or is not proven, or names a signal the netlist
    does not have: a refusal."""


@dataclasses.dataclass(frozen=True)
class Invariant:
    """``holds``, a Verilog expression over the names of ``signals`` (each a wire of the
    original's prepared, flattened netlist: ``core.state_store__write_addr``), is 1 in every
    state reachable from reset; ``name`` says what it states (for the messages)."""

    name: str
    signals: tuple[tuple[str, str], ...]
    holds: str


def parse_invariants(text: str, name: str = "invariants") -> dict[tuple[str, str], Invariant]:
    """The invariants of a file's ``text`` (``name``: the file, for the messages), keyed by
    design and :func:`~.equivalents.mutation_key` of the mutation.

    Raises
    ------
    ValueError
        Not TOML, a table other than ``[[invariant]]``, a key missing, empty or unknown, a
        design without mutants, or a mutation listed twice.
    """
    from dptbd.sim.mutation.equivalents import mutation_key

    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{name}: not TOML: {exc}") from None
    if set(data) - {"invariant"} or not isinstance(data.get("invariant", []), list):
        raise ValueError(f"{name}: the file holds [[invariant]] tables only")
    out: dict[tuple[str, str], Invariant] = {}
    for i, item in enumerate(data.get("invariant", []), 1):
        where = f"{name}: invariant {i}"
        if set(item) != set(_KEYS):
            raise ValueError(f"{where}: keys {', '.join(sorted(item))}; every invariant has "
                             f"exactly {', '.join(_KEYS)}")
        signals = item["signals"]
        if (not all(isinstance(item[k], str) and item[k].strip() for k in _KEYS if k !=
                    "signals") or not isinstance(signals, dict) or not signals
                or not all(isinstance(w, str) and w for w in signals.values())):
            raise ValueError(f"{where}: design, mutation, name and holds are non-empty "
                             f"strings, signals a non-empty table of wire names")
        if item["design"] not in DESIGN_TOPS:
            raise ValueError(f"{where}: design must be one of {', '.join(DESIGN_TOPS)}, got "
                             f"{item['design']!r}")
        key = (item["design"], mutation_key(item["mutation"]))
        if key in out:
            raise ValueError(f"{where}: a second invariant for the same mutation")
        out[key] = Invariant(item["name"], tuple(signals.items()), item["holds"])
    return out


def load_invariants(path: str | pathlib.Path = INVARIANTS) -> dict[tuple[str, str], Invariant]:
    """The invariants of ``path`` (default the registries', module doc); none if the file
    is absent."""
    path = pathlib.Path(path)
    return parse_invariants(path.read_text(), path.name) if path.is_file() else {}


@functools.lru_cache(maxsize=4)
def prepared_rtlil(rtlil: str, design: str) -> str:
    """``design``'s top read from ``rtlil`` and prepared (:data:`~.netlist.PREPARE`), as
    RTLIL."""
    return run_yosys(_prepared(rtlil, design) + "\nwrite_rtlil prepared.il",
                     ("prepared.il",))["prepared.il"]


def _module(prepared: str, design: str) -> tuple[int, int]:
    start = prepared.index(f"\nmodule \\{DESIGN_TOPS[design]}\n")
    return start, prepared.index("\nend\n", start)


def signal_widths(prepared: str, design: str, invariant: Invariant) -> dict[str, int]:
    """The width of each of ``invariant``'s signals in ``design``'s top of the prepared
    RTLIL ``prepared``.

    Raises
    ------
    InvariantError
        A signal that is no wire of the top.
    """
    start, end = _module(prepared, design)
    body = prepared[start:end]
    out = {}
    for name, wire in invariant.signals:
        found = re.search(rf"^  wire (?:width (\d+) )?(?:\S+ \d+ )?\\{re.escape(wire)}$", body,
                          flags=re.M)
        if found is None:
            raise InvariantError(f"invariant {invariant.name!r}: {DESIGN_TOPS[design]} has no "
                                 f"wire {wire!r} (signal {name!r}); name a wire of the "
                                 f"prepared, flattened netlist")
        out[name] = int(found.group(1) or 1)
    return out


def checker_verilog(invariant: Invariant, widths: dict[str, int]) -> str:
    """The checker module: an input per signal (``widths``), the output ``holds``."""
    ports = [f"input [{widths[name] - 1}:0] {name}" for name, _ in invariant.signals]
    return (f"module {CHECKER}({', '.join(ports)}, output holds);\n"
            f"  assign holds = {invariant.holds};\nendmodule\n")


def with_checker(prepared: str, design: str, invariant: Invariant) -> str:
    """``prepared`` with the checker instantiated in ``design``'s top on the invariant's
    signals and an ``$assert`` on its output (the checker module itself is read from
    :func:`checker_verilog`)."""
    signal_widths(prepared, design, invariant)
    start, end = _module(prepared, design)
    lines = [f"  wire \\{CHECKER}_holds", f"  cell \\{CHECKER} \\{CHECKER}",
             *(f"    connect \\{name} \\{wire}" for name, wire in invariant.signals),
             f"    connect \\holds \\{CHECKER}_holds", "  end",
             f"  cell $assert \\{CHECKER}_assert", f"    connect \\A \\{CHECKER}_holds",
             "    connect \\EN 1'1", "  end"]
    return prepared[:end] + "\n" + "\n".join(lines) + prepared[end:]


def _gold(prepared: str, design: str, invariant: Invariant) -> list[str]:
    """The commands reading the original with its checker, renamed ``gold``."""
    top = DESIGN_TOPS[design]
    verilog = checker_verilog(invariant, signal_widths(prepared, design, invariant))
    return [f"read_rtlil <<rtlil\n{with_checker(prepared, design, invariant)}\nrtlil",
            f"read_verilog -sv <<verilog\n{verilog}verilog", f"hierarchy -top {top}",
            "proc", "flatten", "opt_clean", f"rename {top} gold"]


def invariant_script(prepared: str, design: str, invariant: Invariant) -> str:
    """The Yosys script writing the original with ``invariant``'s assertion as a miter
    (``miter -assert``: 1 where the invariant fails), ``miter.aig``."""
    return "\n".join([*_gold(prepared, design, invariant), "memory_map", "opt_clean",
                      "setundef -zero -init", "miter -assert -flatten gold check",
                      "hierarchy -top check", *TO_AIGER])


def miter_script(rtlil: str, prepared: str, design: str, command: str,
                 invariant: Invariant) -> str:
    """The Yosys script writing the miter of the original with ``invariant``'s assertion
    and its mutant by ``command`` (module doc, step 2), ``miter.aig``."""
    top = DESIGN_TOPS[design]
    return "\n".join([
        # the mutant first, from the same RTLIL as prove_equivalent (the cells' numbers)
        _prepared(rtlil, design), command, f"rename {top} gate", "design -stash gate",
        *_gold(prepared, design, invariant), "design -stash gold",
        "design -copy-from gold -as gold gold", "design -copy-from gate -as gate gate",
        "memory_map", "opt_clean", "setundef -zero -init",
        # the equality asserted; its output renamed, miter -assert adds its own trigger
        "miter -equiv -flatten -make_assert gold gate miter", "cd miter",
        "rename trigger equal_trigger", "cd ..", "miter -assert -flatten miter check",
        "hierarchy -top check", *TO_AIGER])


def prove_invariant(cfg: DPConfig, design: str, invariant: Invariant, *,
                    pdr_seconds: float = PDR_SECONDS, timeout: float = TIMEOUT
                    ) -> Equivalence:
    """Prove ``invariant`` of ``design``'s original top for ``cfg`` from reset (module doc,
    step 1): the verdict ``holds``, ``fails`` (PDR's counterexample: the cycle), ``not
    proven``, ``timeout`` or ``error``."""
    text, _ = top_rtlil(cfg, design)
    proof = solve_miter(invariant_script(prepared_rtlil(text, design), design, invariant),
                        pdr_seconds=pdr_seconds, timeout=timeout, correspondence="scorr")
    verdict = {"equivalent": "holds", "not equivalent": "fails"}.get(proof.verdict,
                                                                    proof.verdict)
    detail = (proof.detail.replace("no output differs", "the invariant holds")
              .replace("an output differs", "the invariant fails"))
    return Equivalence(verdict, detail, proof.seconds)


def prove_under_invariant(cfg: DPConfig, design: str, mutation: Mutation | str,
                          invariant: Invariant, *, pdr_seconds: float = PDR_SECONDS,
                          timeout: float = TIMEOUT) -> Equivalence:
    """Prove ``mutation`` of ``design``'s top for ``cfg`` equivalent to the original from
    reset with ``invariant`` proven first and asserted in the original's copy (module
    doc): :func:`~.reachable.prove_reachable`'s verdicts; each step has ``pdr_seconds`` of
    PDR and ``timeout`` seconds in all.

    Raises
    ------
    InvariantError
        The invariant fails from reset, or is not proven, or names no wire of the top.
    """
    command = mutation.command if isinstance(mutation, Mutation) else str(mutation)
    if clock_mutation(command):
        return CLOCK_UNPROVEN
    start = time.perf_counter()
    held = prove_invariant(cfg, design, invariant, pdr_seconds=pdr_seconds, timeout=timeout)
    if held.verdict != "holds":
        raise InvariantError(f"invariant {invariant.name!r} of {design} refused: "
                             f"{held.verdict} ({held.detail}); a mutant is proven only "
                             f"under an invariant proven from reset")
    text, _ = top_rtlil(cfg, design)
    proof = solve_miter(miter_script(text, prepared_rtlil(text, design), design, command,
                                     invariant), pdr_seconds=pdr_seconds, timeout=timeout,
                        correspondence="scorr")
    return dataclasses.replace(proof, detail=f"under {invariant.name!r} "
                               f"({held.detail.split(':')[0]}): {proof.detail}",
                               seconds=time.perf_counter() - start)
