"""The equivalence registry: the mutants shown equivalent to the original, one home.

MCY's score leaves out the mutants that cannot change an output: killed / (total − shown
equivalent). A mutant is *shown equivalent* when it is in its design's file here
(``segmenter.toml``, ``axi.toml``, ``dp.toml``, ``dp2.toml``, ``dp4.toml``), one
``[[mutant]]`` table each::

    [[mutant]]
    mutation = "mutate -mode inv -module dptbd_seg -cell ... -src hw/segmenter.py:123"
    shown = "proven"                  # or "argued"
    source = "hw/segmenter.py:123"    # Mutation.source
    why = "why no output can ever differ (argued: the argument itself; proven: what the
           proof shows)"

``mutation`` is the ``mutate`` line Yosys printed (:attr:`Mutation.command
<dptbd.sim.mutation.netlist.Mutation>`) with its ``-src`` paths made independent of the
checkout (:func:`portable_command`: ``hw/segmenter.py:123``,
``amaranth/lib/memory.py:241``); an entry written with the absolute paths of another
checkout is read the same way. A run's survivors are matched by :func:`mutation_key`, that
string without the ``-src`` line numbers (the cell, port, bit and wire names identify a
mutation of a netlist): an edit that moves source lines but leaves the netlist unchanged
keeps every entry matching, while a netlist change, which renames cells, makes an entry
stop matching: it is never counted. ``shown = "proven"`` means
:func:`~dptbd.sim.mutation.equivalence.prove_equivalent` proves it, or
:func:`~dptbd.sim.mutation.reachable.prove_reachable` when its ``why`` names that method, or
:func:`~dptbd.sim.mutation.invariant.prove_under_invariant` under its invariant of
``invariants.toml`` when its ``why`` names that one (a slow test runs every one); ``"argued"`` is a written argument that no output can differ for any legal input
sequence. A file that is absent is an empty registry.
"""

from __future__ import annotations

import dataclasses
import pathlib
import re
import tomllib

__all__ = ["SHOWN", "FILES", "KEYS", "Equivalent", "portable_command", "mutation_key",
           "parse_registry", "load_registry", "entry_toml"]

#: The ways a mutant is shown equivalent.
SHOWN = ("proven", "argued")

#: Each design's file (:data:`dptbd.sim.mutation.netlist.DESIGN_TOPS`).
FILES = {"segmenter": "segmenter.toml", "axi": "axi.toml", "dp": "dp.toml",
         "dp2": "dp2.toml", "dp4": "dp4.toml"}

#: The keys of a ``[[mutant]]`` table, every one required.
KEYS = ("mutation", "shown", "source", "why")

_HERE = pathlib.Path(__file__).resolve().parent
_REPO = _HERE.parents[2]
#: The repository's top folders of Amaranth sources (``hw/``; ``dptbd/``, ``sim/``,
#: ``model/`` for completeness): a ``-src`` path from another checkout is cut before the
#: last of them.
_TOP_FOLDER = re.compile(r"^.*/(?=(?:hw|sim|model|dptbd)/[^/]*)")
_SRC = re.compile(r"(?<=-src )(\S+)")
#: A ``-src`` location's line part: ``:12`` or ``:12.5-14.9``.
_LINE = re.compile(r":[0-9]+(?:\.[0-9]+)?(?:-[0-9]+(?:\.[0-9]+)?)?$")


@dataclasses.dataclass(frozen=True)
class Equivalent:
    """One entry: the mutation (its :func:`portable_command`), ``proven`` or ``argued``, the
    Amaranth source line and why no output can differ."""

    mutation: str
    shown: str
    source: str
    why: str


def _portable(path: str) -> str:
    """A ``-src`` location without the checkout: relative to this repository, else the part
    after ``site-packages/``, else from the last top folder of the repository's layout."""
    file, sep, line = path.rpartition(":")
    file = file if sep else path
    try:
        rel = pathlib.Path(file).relative_to(_REPO).as_posix()
        if not rel.startswith(".venv/") and "/site-packages/" not in f"/{rel}":
            file = rel
    except ValueError:
        pass
    if "/site-packages/" in file:
        file = file.rsplit("/site-packages/", 1)[1]
    elif file.startswith("/"):
        file = _TOP_FOLDER.sub("", file)
    return f"{file}{sep}{line}" if sep else file


def portable_command(command: str) -> str:
    """``command`` (a ``mutate`` line) with every ``-src`` path made independent of the
    checkout: the string an entry stores."""
    return _SRC.sub(lambda m: _portable(m.group(1)), command.strip())


def mutation_key(command: str) -> str:
    """:func:`portable_command` of ``command`` without the ``-src`` line numbers (the file
    kept): the string the registry matches, the same after an edit that moves source lines
    but leaves the netlist unchanged."""
    return _SRC.sub(lambda m: _LINE.sub("", _portable(m.group(1))), command.strip())


def parse_registry(text: str, name: str = "registry") -> tuple[Equivalent, ...]:
    """The entries of a registry file's ``text`` (``name``: the file, for the messages).

    Raises
    ------
    ValueError
        Not TOML, a table other than ``[[mutant]]``, a key missing, empty or unknown, a
        ``shown`` other than ``proven`` / ``argued``, or a mutation listed twice.
    """
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{name}: not TOML: {exc}") from None
    unknown = sorted(set(data) - {"mutant"})
    if unknown:
        raise ValueError(f"{name}: unknown table(s) {', '.join(unknown)}; the file holds "
                         f"[[mutant]] tables only")
    if not isinstance(data.get("mutant", []), list):
        raise ValueError(f"{name}: mutant is not an array of tables; write [[mutant]]")
    out: list[Equivalent] = []
    seen: dict[str, int] = {}
    for i, item in enumerate(data.get("mutant", []), 1):
        where = f"{name}: mutant {i}"
        extra = sorted(set(item) - set(KEYS))
        if extra:
            raise ValueError(f"{where}: unknown key(s) {', '.join(extra)}; keys are "
                             f"{', '.join(KEYS)}")
        missing = [k for k in KEYS if not isinstance(item.get(k), str) or not item[k].strip()]
        if missing:
            raise ValueError(f"{where}: {', '.join(missing)} missing or not a non-empty "
                             f"string; every entry has {', '.join(KEYS)}")
        if item["shown"] not in SHOWN:
            raise ValueError(f"{where}: shown {item['shown']!r} is not one of "
                             f"{', '.join(SHOWN)}")
        if not item["mutation"].startswith("mutate -mode "):
            raise ValueError(f"{where}: mutation {item['mutation'][:60]!r} is not a "
                             f"'mutate -mode ...' line of Yosys' mutate -list")
        key = mutation_key(item["mutation"])
        if key in seen:
            raise ValueError(f"{where}: the mutation of mutant {seen[key]} again; each "
                             f"mutation is listed once")
        seen[key] = i
        out.append(Equivalent(portable_command(item["mutation"]), item["shown"], item["source"].strip(),
                              " ".join(item["why"].split())))
    return tuple(out)


def load_registry(design: str, folder: str | pathlib.Path | None = None
                  ) -> dict[str, Equivalent]:
    """``design``'s registry (its file in ``folder``, default this package's), keyed by
    :func:`mutation_key`; empty if the file is absent."""
    if design not in FILES:
        raise ValueError(f"design must be one of {', '.join(FILES)}, got {design!r}")
    path = pathlib.Path(folder or _HERE) / FILES[design]
    if not path.is_file():
        return {}
    return {mutation_key(e.mutation): e for e in parse_registry(path.read_text(), path.name)}


def entry_toml(entry: Equivalent) -> str:
    """``entry`` as a ``[[mutant]]`` table (the mutation a literal string: cell names hold
    backslashes), which :func:`parse_registry` reads back as ``entry``."""
    import textwrap

    def basic(text: str) -> str:
        return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'

    if "'" in entry.mutation or "\n" in entry.mutation:
        raise ValueError(f"mutation {entry.mutation[:60]!r} holds a quote or a line break; "
                         f"a mutate line has neither")
    why = textwrap.wrap(entry.why, 88)
    why_text = (basic(entry.why) if len(why) == 1 else
                '"""\n' + "\n".join(w.replace("\\", "\\\\").replace('"', '\\"') for w in why)
                + '"""')
    return (f"[[mutant]]\nmutation = '{entry.mutation}'\nshown = {basic(entry.shown)}\n"
            f"source = {basic(entry.source)}\nwhy = {why_text}\n")
