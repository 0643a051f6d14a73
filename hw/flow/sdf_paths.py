"""The worst register-to-register paths of a routed design, from nextpnr's SDF.

nextpnr's ``--report`` gives one critical path per clock. For the next ones, ``nextpnr
--sdf FILE --write placed.json`` writes the routed delays (each cell's ``IOPATH`` and
``SETUPHOLD``, each net arc's ``INTERCONNECT``) and the placement (each cell's
``NEXTPNR_BEL``, ``X<x>/Y<y>/…``); :func:`worst_paths` finds, for every timing endpoint,
its longest path (a longest-path pass over the delay graph, the worst of min:typ:max and
of rise / fall), and returns the ``n`` worst endpoints with their start, logic and routing
delay, the placement distance (tiles, ``|dx| + |dy|``) from start to end and the span
(the same summed from cell to cell along the path). It times one
clock and no clock skew, so its delays are nextpnr's path delays without the clock's
arrival difference (the critical path agrees with nextpnr's report to the picosecond or
differs by that skew). ::

    python -m dptbd.hw.flow.sdf_paths build/synth/ecp5/axi128/routed.sdf \\
        build/synth/ecp5/axi128/placed.json -n 10
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import pathlib
import re
from typing import Iterator, Mapping, Sequence

__all__ = ["DelayGraph", "TimedPath", "parse_sdf", "placement", "signal", "worst_paths", "main"]

_TOKEN = re.compile(r'\(|\)|"(?:[^"\\]|\\.)*"|(?:[^\s()"\\]|\\.)+')


def _tokens(text: str) -> Iterator[str]:
    for m in _TOKEN.finditer(text):
        yield m.group(0)


def _tree(text: str) -> list:
    """The SDF's s-expressions as nested lists of atoms (escapes kept)."""
    stack: list[list] = [[]]
    for tok in _tokens(text):
        if tok == "(":
            stack.append([])
        elif tok == ")":
            if len(stack) == 1:
                raise ValueError("SDF: unbalanced ')'")
            done = stack.pop()
            stack[-1].append(done)
        else:
            stack[-1].append(tok)
    if len(stack) != 1:
        raise ValueError("SDF: unbalanced '('")
    return stack[0]


def _unescape(name: str) -> str:
    return re.sub(r"\\(.)", r"\1", name)


def _delay(values: Sequence) -> float:
    """The worst of ``(min:typ:max)`` triples (rise, fall), in the SDF's unit."""
    worst = 0.0
    for v in values:
        if isinstance(v, list) and v:
            worst = max([worst] + [float(x) for x in v[0].split(":") if x])
    return worst


@dataclasses.dataclass
class DelayGraph:
    """An SDF's delays in ns: ``arcs`` maps a node ``cell/port`` to its ``(next node, delay,
    kind)``, kind ``"logic"`` (a cell's IOPATH) or ``"routing"`` (an INTERCONNECT);
    ``launch`` a register output to its clock to out, ``setup`` a register input to its
    setup time."""

    arcs: dict[str, list[tuple[str, float, str]]]
    launch: dict[str, float]
    setup: dict[str, float]


def parse_sdf(text: str) -> DelayGraph:
    """The :class:`DelayGraph` of an SDF's text (``ValueError`` if its parentheses do not
    balance)."""
    root = _tree(text)
    top = root[0] if root and isinstance(root[0], list) else root
    divider = "."
    scale = 1.0
    graph = DelayGraph({}, {}, {})
    for item in top:
        if not isinstance(item, list) or not item:
            continue
        if item[0] == "DIVIDER" and len(item) > 1:
            divider = item[1]
        elif item[0] == "TIMESCALE":
            unit = "".join(item[1:])
            scale = {"1ps": 1e-3, "1ns": 1.0, "10ps": 1e-2, "100ps": 1e-1}.get(unit, 1.0)
        elif item[0] == "CELL":
            _cell(item, graph, divider, scale)
    return graph


def _port(term) -> str:
    """``D`` or ``(posedge CLK)``'s ``CLK``."""
    return term[-1] if isinstance(term, list) else term


def _cell(item: list, graph: DelayGraph, divider: str, scale: float) -> None:
    inst = ""
    clocks = set()      # the cell's clock inputs: an IOPATH from one is a clock to out
    for part in item[1:]:
        if isinstance(part, list) and part and part[0] == "INSTANCE":
            inst = _unescape(part[1]) if len(part) > 1 else ""
        if isinstance(part, list) and part and part[0] == "TIMINGCHECK":
            clocks.update(_port(check[2]) for check in part[1:]
                          if isinstance(check, list) and len(check) > 2)
    for part in item[1:]:
        if not (isinstance(part, list) and part):
            continue
        if part[0] == "DELAY":
            for block in part[1:]:
                for entry in block[1:]:
                    if not isinstance(entry, list) or not entry:
                        continue
                    if entry[0] == "IOPATH":
                        src, dst = entry[1], entry[2]
                        d = _delay(entry[3:]) * scale
                        if isinstance(src, list) or src in clocks:     # clock to out
                            dst = _port(dst)
                            node = f"{inst}/{dst}"
                            graph.launch[node] = max(graph.launch.get(node, 0.0), d)
                        else:
                            graph.arcs.setdefault(f"{inst}/{src}", []).append(
                                (f"{inst}/{dst}", d, "logic"))
                    elif entry[0] == "INTERCONNECT":
                        a, b = (_pin(x, divider) for x in entry[1:3])
                        graph.arcs.setdefault(a, []).append(
                            (b, _delay(entry[3:]) * scale, "routing"))
        elif part[0] == "TIMINGCHECK":
            for check in part[1:]:
                if isinstance(check, list) and check and check[0] in ("SETUPHOLD", "SETUP"):
                    node = f"{inst}/{_port(check[1])}"
                    graph.setup[node] = max(graph.setup.get(node, 0.0),
                                            _delay(check[3:4]) * scale)


def _pin(text: str, divider: str) -> str:
    """``cell.port`` (the SDF's divider, the last unescaped one) as ``cell/port``."""
    idx = max(i for i, c in enumerate(text)
              if c == divider and (i == 0 or text[i - 1] != "\\"))
    return f"{_unescape(text[:idx])}/{text[idx + 1:]}"


def placement(netlist: Mapping) -> dict[str, tuple[int, int]]:
    """Each placed cell's tile ``(x, y)`` from a ``nextpnr --write`` JSON's ``NEXTPNR_BEL``."""
    tiles = {}
    for module in netlist.get("modules", {}).values():
        for name, cell in module.get("cells", {}).items():
            bel = cell.get("attributes", {}).get("NEXTPNR_BEL", "")
            m = re.match(r"X(\d+)/Y(\d+)/", bel)
            if m:
                tiles[name] = (int(m.group(1)), int(m.group(2)))
    return tiles


@dataclasses.dataclass(frozen=True)
class TimedPath:
    """The longest path into one endpoint: ``start`` / ``end`` cells, ``logic_ns`` (clock
    to out, cells, setup), ``routing_ns``, ``cells`` on the way (start and end included),
    ``distance`` (tiles from start to end, ``None`` without a placement), ``span`` (tiles
    from cell to cell along the path, ``None`` without a placement), ``bits``: the endpoints
    of the same start and end signal (bits of one bus, the worst shown); ``nets``: the
    routed connections on the way (those of nonzero delay)."""

    start: str
    end: str
    logic_ns: float
    routing_ns: float
    cells: int
    distance: int | None
    span: int | None = None
    bits: int = 1
    nets: int = 0

    @property
    def total_ns(self) -> float:
        return self.logic_ns + self.routing_ns


def signal(cell: str) -> str:
    """A flip-flop's signal: its cell name without nextpnr-ecp5's ``_TRELLIS_FF_Q_<bit>``."""
    return re.sub(r"_TRELLIS_FF_Q(_\d+)?$", "", cell)


def worst_paths(graph: DelayGraph, tiles: Mapping[str, tuple[int, int]] | None = None,
                n: int = 10) -> list[TimedPath]:
    """The ``n`` worst endpoints' longest paths, worst first (one path per endpoint; the
    endpoints of one bus from one start signal as one, ``TimedPath.bits``)."""
    # longest arrival from any launch, by a depth-first topological order
    order: list[str] = []
    seen: set[str] = set()
    for root in graph.launch:
        if root in seen:
            continue
        seen.add(root)
        stack = [(root, iter(graph.arcs.get(root, ())))]
        while stack:
            node, it = stack[-1]
            for nxt, _, _ in it:
                if nxt not in seen and nxt not in graph.launch:
                    seen.add(nxt)
                    stack.append((nxt, iter(graph.arcs.get(nxt, ()))))
                    break
            else:
                stack.pop()
                order.append(node)
    # node -> (total, logic, routing, routed nets)
    arrival: dict[str, tuple[float, float, float, int]] = {}
    before: dict[str, str | None] = {}
    for node in graph.launch:
        arrival[node] = (graph.launch[node], graph.launch[node], 0.0, 0)
        before[node] = None
    for node in reversed(order):
        if node not in arrival:
            continue
        total, logic, routing, nets = arrival[node]
        for nxt, d, kind in graph.arcs.get(node, ()):
            if nxt in graph.launch:
                continue
            wire = kind == "routing"
            cand = (total + d, logic + d * (not wire), routing + d * wire,
                    nets + (wire and d > 0))
            if nxt not in arrival or cand[0] > arrival[nxt][0]:
                arrival[nxt] = cand
                before[nxt] = node
    ends = []
    for node, setup in graph.setup.items():
        if node in arrival:
            total, logic, routing, nets = arrival[node]
            ends.append((total + setup, logic + setup, routing, nets, node))
    ends.sort(reverse=True)
    found: dict[tuple[str, str], TimedPath] = {}
    for _, logic, routing, nets, node in ends:
        cells, walk = [], node
        while walk is not None:
            cell = walk.rsplit("/", 1)[0]
            if not cells or cells[-1] != cell:
                cells.append(cell)
            walk = before[walk]
        cells.reverse()
        key = (signal(cells[0]), signal(cells[-1]))
        if key in found:
            found[key] = dataclasses.replace(found[key], bits=found[key].bits + 1)
            continue
        if len(found) == n:
            continue
        distance = span = None
        if tiles and all(c in tiles for c in cells):
            def far(a, b):
                return abs(tiles[a][0] - tiles[b][0]) + abs(tiles[a][1] - tiles[b][1])
            distance = far(cells[0], cells[-1])
            span = sum(far(a, b) for a, b in zip(cells, cells[1:]))
        elif tiles and cells[0] in tiles and cells[-1] in tiles:
            distance = (abs(tiles[cells[0]][0] - tiles[cells[-1]][0])
                        + abs(tiles[cells[0]][1] - tiles[cells[-1]][1]))
        found[key] = TimedPath(start=cells[0], end=cells[-1], logic_ns=logic,
                               routing_ns=routing, cells=len(cells), distance=distance,
                               span=span, nets=nets)
    return list(found.values())


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("sdf", type=pathlib.Path, help="nextpnr --sdf output")
    parser.add_argument("placed", type=pathlib.Path, nargs="?",
                        help="nextpnr --write output (for the placement distance)")
    parser.add_argument("-n", type=int, default=10, help="endpoints to list (default 10)")
    args = parser.parse_args(argv)
    graph = parse_sdf(args.sdf.read_text())
    tiles = placement(json.loads(args.placed.read_text())) if args.placed else None
    print("| # | start | end | bits | total (ns) | logic (ns) | routing (ns) | nets | cells | "
          "distance (tiles) | span (tiles) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for i, p in enumerate(worst_paths(graph, tiles, args.n), 1):
        dist, span = ("—" if v is None else str(v) for v in (p.distance, p.span))
        print(f"| {i} | `{signal(p.start)}` | `{signal(p.end)}` | {p.bits} | "
              f"{p.total_ns:.2f} | {p.logic_ns:.2f} | {p.routing_ns:.2f} | {p.nets} | {p.cells} | "
              f"{dist} | {span} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
