"""Code coverage of the RTL: Verilator's coverage data read, mapped to the Amaranth source.

A coverage build (``build(cfg, design, coverage=True)``, :mod:`dptbd.sim.verilator.cache`)
is verilated with ``--coverage-line --coverage-toggle`` on the text of
:mod:`dptbd.sim.coverage.source_text`, where every ``if`` / ``casez`` and every case item
carries the ``src`` (``file.py:line``) of its ``m.If`` / ``m.Elif`` / ``m.Else`` /
``m.Switch`` / ``m.Case`` / ``m.FSM`` state, and every signal the ``src`` of its
declaration. Each run writes a ``VerilatedCov`` file; ``verilator_coverage --write`` merges
them per build (:func:`merge`), and this module reads the merged text
(:func:`parse_dat`: one ``C '<key>' <count>`` line per point, the key's fields ``f`` file,
``l`` line, ``n`` column, ``page`` ``v_line/<module>`` | ``v_branch/<module>`` |
``v_toggle/<module>``, ``o`` what — ``block``, ``if``, ``elsif``, ``else``, ``case`` or the
signal bit — ``S`` line span, ``h`` hierarchy, separated by the bytes 0x01 and 0x02).

Verilator 5.006 writes three kinds of points, reported as

* **line** (``v_line``): a block of statements — each branch of an ``if`` / ``else if`` /
  ``else`` chain, each case item, each clocked ``always`` and each initialised ``reg``;
* **branch** (``v_branch``): both outcomes (``if`` and ``else``) of each two-way ``if``;
* **toggle** (``v_toggle``): each bit of each signal; covered when it changed at least once
  (so it was seen at 0 and at 1). The report counts the bits of registers only
  (:func:`registers`): the other signals are functions of registers and inputs.

:func:`source_map` gives each Verilog line the Amaranth ``file:line`` of its statement (the
``src`` attributes directly above it; the k-th branch of an ``if`` / ``else if`` chain the
k-th entry of the chain's ``dptbd_cases`` attribute), :func:`locate` a point's. Points on
Yosys' time-0 trigger (``if (\\$auto$verilog_backend…) begin end``, an artefact of the text,
not of the gateware) are dropped.
"""

from __future__ import annotations

import dataclasses
import os
import pathlib
import re
import shutil
import subprocess
from typing import Iterable, Sequence

from dptbd.sim.cell_models import CELL_MODELS

__all__ = ["KINDS", "Point", "CoverageToolMissing", "find_verilator_coverage", "parse_dat",
           "read_dat", "merge", "annotate", "source_map", "locate", "relative_src",
           "SOURCE_FOLDERS", "registers",
           "unescape", "usable"]

#: Verilator's page kinds and the names reported.
KINDS = {"v_line": "line", "v_branch": "branch", "v_toggle": "toggle"}

ARTEFACT = "$auto$verilog_backend"

_REPO = pathlib.Path(__file__).resolve().parents[2]


class CoverageToolMissing(FileNotFoundError):
    """``verilator_coverage`` is not on PATH."""


def find_verilator_coverage() -> str:
    """The path of ``verilator_coverage``; :class:`CoverageToolMissing` if it is not on PATH."""
    tool = shutil.which("verilator_coverage")
    if tool is None:
        raise CoverageToolMissing(
            "--coverage needs verilator_coverage (Debian package 'verilator', which installs "
            "it with verilator), and it is not on PATH")
    return tool


@dataclasses.dataclass(frozen=True)
class Point:
    """One coverage point of one build."""

    kind: str        # "line", "branch" or "toggle"
    module: str      # Verilog module: the Amaranth hierarchy, dotted (``dptbd_seg.dp.core``)
    file: str        # the Verilog file
    line: int        # its line
    column: int
    what: str        # Verilator's ``o``: block, if, elsif, else, case; the signal bit (toggle)
    span: str        # Verilator's ``S`` (line span), or ""
    count: int
    key: str         # the whole key, as in the file

    @property
    def covered(self) -> bool:
        return self.count > 0


_FIELDS = {"f": "file", "l": "line", "n": "column", "page": "page", "o": "what", "S": "span"}


def parse_dat(text: str) -> list[Point]:
    """The points of a ``verilator_coverage`` data text (``# SystemC::Coverage-3``); a key
    given twice adds its counts. Raises ValueError naming the first line it cannot read."""
    counts: dict[str, int] = {}
    for number, line in enumerate(text.splitlines(), 1):
        if not line.strip() or line.startswith("#"):
            continue
        key, sep, count = line[3:].rpartition("' ")
        if not line.startswith("C '") or not sep or not count.strip().isdigit():
            raise ValueError(f"coverage data line {number} is not C '<key>' <count>: "
                             f"{line[:80]!r}")
        counts[key] = counts.get(key, 0) + int(count)
    points = []
    for key, count in counts.items():
        fields = dict(item.split("\x02", 1) for item in key.split("\x01") if "\x02" in item)
        page, _, module = fields.get("page", "").partition("/")
        if page not in KINDS:
            continue
        points.append(Point(KINDS[page], module, fields.get("f", ""), int(fields.get("l", 0)),
                            int(fields.get("n", 0)), fields.get("o", ""), fields.get("S", ""),
                            count, key))
    return points


def read_dat(path: str | os.PathLike) -> list[Point]:
    return parse_dat(pathlib.Path(path).read_text(encoding="utf-8", errors="surrogateescape"))


def merge(paths: Sequence[str | os.PathLike], out: str | os.PathLike) -> pathlib.Path:
    """``verilator_coverage --write out paths…`` (the counts of every run added)."""
    tool = find_verilator_coverage()
    out = pathlib.Path(out)
    result = subprocess.run([tool, "--write", str(out), *map(str, paths)],
                            capture_output=True, text=True, check=False)
    if result.returncode != 0:
        raise RuntimeError(f"verilator_coverage --write failed (exit {result.returncode}): "
                           f"{(result.stderr or result.stdout).strip()[-2000:]}")
    return out


def annotate(dat: str | os.PathLike, verilog_dir: str | os.PathLike,
             out_dir: str | os.PathLike) -> None:
    """``verilator_coverage --annotate out_dir dat`` run where the build's Verilog is."""
    tool = find_verilator_coverage()
    result = subprocess.run([tool, "--annotate", str(pathlib.Path(out_dir).resolve()),
                             str(pathlib.Path(dat).resolve())], cwd=verilog_dir,
                            capture_output=True, text=True, check=False)
    if result.returncode != 0:
        raise RuntimeError(f"verilator_coverage --annotate failed (exit {result.returncode}): "
                           f"{(result.stderr or result.stdout).strip()[-2000:]}")


#: The repository's source folders (``pyproject.toml``'s package-dir): a ``src`` of another
#: checkout is mapped by its path below one of them.
SOURCE_FOLDERS = ("hw", "model", "sim", "dptbd")


def relative_src(src: str) -> str:
    """``file:line`` with the file relative to the repository (``hw/segmenter.py:183``) or,
    for Amaranth's own files, to its package (``amaranth/lib/stream.py:50``).

    A build's text holds the absolute paths of the checkout that generated it, and its build
    key does not name the checkout (the same sources give the same build): a build directory
    shared by two checkouts gives one the other's paths. A path outside this repository is
    therefore mapped by its longest tail that begins with a source folder
    (:data:`SOURCE_FOLDERS`) and names a file of this repository
    (``/elsewhere/hw/segmenter.py`` is ``hw/segmenter.py``)."""
    path, _, line = src.rpartition(":")
    p = pathlib.Path(path)
    try:
        return f"{p.resolve().relative_to(_REPO).as_posix()}:{line}"
    except ValueError:
        parts = p.parts
        for i, part in enumerate(parts):
            tail = pathlib.PurePosixPath(*parts[i:])
            if part in SOURCE_FOLDERS and (_REPO / tail).is_file():
                return f"{tail}:{line}"
        if "amaranth" in parts:
            return f"{pathlib.PurePosixPath(*parts[len(parts) - parts[::-1].index('amaranth') - 1:])}:{line}"
        return src


_ATTR = re.compile(r'^\s*(?:\(\*|/\*)\s*(\S+)\s*=\s*"((?:[^"\\]|\\.)*)"\s*(?:\*\)|\*/)\s*$')
_CHAIN_NEXT = re.compile(r"^(\s*)end else (if \(|begin)")


def source_map(verilog: str) -> tuple[dict[int, str], set[int]]:
    """Per Verilog line (1-based) the Amaranth ``file:line`` (repository-relative) of the
    statement or declaration on it, and the lines of Yosys' time-0 trigger (artefacts)."""
    lines = verilog.splitlines()
    out: dict[int, str] = {}
    artefacts: set[int] = set()
    pending: dict[str, str] = {}
    chains: dict[int, list] = {}       # indentation -> [cases, next branch index]
    for number, text in enumerate(lines, 1):
        match = _ATTR.match(text)
        if match:
            pending[match.group(1)] = match.group(2)
            continue
        if ARTEFACT in text:                  # the trigger's declaration and its if
            artefacts.add(number)
        indent = len(text) - len(text.lstrip())
        follow = _CHAIN_NEXT.match(text)
        if follow and indent in chains:
            cases, k = chains[indent]
            if k < len(cases) and cases[k]:
                out[number] = relative_src(cases[k])
            chains[indent][1] = k + 1
        elif "src" in pending:
            out[number] = relative_src(pending["src"])
        if text.lstrip().startswith("if (") and "dptbd_cases" in pending:
            cases = pending["dptbd_cases"].split("|")
            chains[indent] = [cases, 1]
            if cases and cases[0]:
                out[number] = relative_src(cases[0])
        elif not follow and text.strip() == "end" and indent in chains:
            del chains[indent]
        pending = {}
    # Amaranth's internal nets ($N: a register's next value, computed by an always @*
    # block) carry no src: they take the src of the register they feed
    temps: dict[str, str] = {}
    for number, text in enumerate(lines[1:], 2):
        feed = _FEED.match(text)
        if feed and number - 1 in out and _CLOCKED.match(lines[number - 2]):
            temps.setdefault(feed.group(1), out[number - 1])
    for text in lines:
        inline = _INLINE.match(text)
        if inline:
            temps.setdefault(inline.group(1), relative_src(inline.group(2)))
    for number, text in enumerate(lines, 1):
        if number in out:
            continue
        name = None
        if text.strip() == "always @* begin":
            for follow_text in lines[number:number + 3]:
                first = _TEMP_ASSIGN.match(follow_text)
                if first:
                    name = first.group(1)
                    break
        elif text.lstrip().startswith(("reg ", "wire ")) and number - 1 in out \
                and lines[number - 2].lstrip().startswith(("output ", "input ")):
            out[number] = out[number - 1]          # a port's reg: the port's src
        else:
            declared = _TEMP_DECL.match(text)
            name = declared.group(1) if declared else None
        if name in temps:
            out[number] = temps[name]
    # the rest (memory ports and initialisers): the nearest src above, in the same module
    last = None
    for number, text in enumerate(lines, 1):
        if text.startswith("module "):
            last = None
        if number in out:
            last = out[number]
        elif last is not None and text.strip() and not _ATTR.match(text):
            out[number] = last
    return out, artefacts


_CLOCKED = re.compile(r"^\s*always @\(posedge \w+\)\s*$")
_FEED = re.compile(r"^\s*\S+ <= (\\\$\d+) ;\s*$")
_TEMP_ASSIGN = re.compile(r"^\s*(\\\$\d+)\s+= ")
_INLINE = re.compile(r'^\s*assign (\\\$\d+) = .*?\(\* src = "((?:[^"\\]|\\.)*)" \*\)')
_TEMP_DECL = re.compile(r"^\s*(?:reg|wire)\b[^\\]*(\\\$\d+) ;\s*$")


def locate(point: Point, srcmap: dict[int, str]) -> str | None:
    """The Amaranth ``file:line`` of ``point``: of its statement's line, or for an ``else``
    block of a chain (Verilator gives the line of the last ``else if``) the first line of
    its span."""
    if point.kind == "line" and point.what == "else" and point.span:
        first = int(point.span.split("-")[0])
        if first in srcmap:
            return srcmap[first]
    return srcmap.get(point.line)


_MODULE = re.compile(r"^module \\?([^\s(]+)\s*\(")
_REG = re.compile(r"^\s*reg\b(?:\s*\[[^\]]*\])?\s*\\?(\S+)\s*=\s*[^;]+;\s*$")


def registers(verilog: str) -> set[tuple[str, str]]:
    """(module, name) of every register of the text: a ``reg`` with an initial value (Yosys
    writes a flip-flop's reset value there; a process' variable and a memory have none)."""
    out, module = set(), ""
    for text in verilog.splitlines():
        match = _MODULE.match(text)
        if match:
            module = match.group(1)
            continue
        match = _REG.match(text)
        if match:
            out.add((module, match.group(1)))
    return out


def unescape(name: str) -> str:
    """A Verilator name as in the Verilog (``__024`` is ``$``, ``__02e`` is ``.``)."""
    return re.sub(r"__0([0-9a-f]{2})", lambda m: chr(int(m.group(1), 16)), name)


def usable(points: Iterable[Point], artefacts: set[int]) -> list[Point]:
    """The points of the generated Verilog that are not on an artefact line (Yosys' time-0
    trigger): a family build's vendor-cell models (:mod:`dptbd.sim.cell_models`, files of
    their own) are not the gateware, and their lines are not the generated text's."""
    models = set(CELL_MODELS.values())
    return [p for p in points if p.line not in artefacts and ARTEFACT not in unescape(p.what)
            and pathlib.PurePath(p.file).name not in models]
