"""Counter presets of the ``axi`` mutant design: each event counter of the register file
loaded with a chosen value in one cycle, so that a run reaches its high bits without
counting up to them.

A mutation of a counter's high bit that only shows once the counter has passed ``2**k``
(``cnot1``: bit j flipped while bit k is 1) needs ``2**k`` events to be seen; for FRAMES,
``2**25`` frames are 4·10⁹ cycles of the slice's 12 × 10 frames, past any slice. In a
simulator one would deposit the value into the register; the register of a mutated netlist
has no name a harness can rely on (``mutate`` on the register's ``Q`` moves its bits to new
wires), so the deposit is built into the mutant design instead, after the mutations:

- before ``mutate``, each counter's flip-flop (the one ``$dff`` whose ``Q`` drives the wire
  ``regs.<name>``, :data:`COUNTER_PATH`) is tagged with the attribute ``dptbd_preset``;
- after it, :func:`add_presets` puts a ``$mux`` on the tagged flip-flop's ``D``: new input
  ports ``preset_load`` (one bit per counter, in :func:`preset_counters` order) and
  ``preset_value`` (32 bits); with ``preset_load[i]`` high the counter takes
  ``preset_value`` at the clock edge, whatever its event, reset or register write.

The mutations are sampled from, and name cells of, the design without the presets
(:func:`~dptbd.sim.mutation.netlist.mutation_list`); the multiplexers themselves are never
mutated. ``mutsel == 0`` (the original) has the same ports, so a run that presets passes on
the original exactly as on any mutant that does not change the counters. The harness
(``sim/harness/dptbd_axi_harness.cpp``, mutant builds) drives them with its ``p``
operation.
"""

from __future__ import annotations

import re

from dptbd.config import DPConfig

__all__ = ["COUNTER_PATH", "ATTRIBUTE", "preset_counters", "tag_commands", "add_presets"]

#: The register file's counter wire of counter ``name`` in the flattened ``dptbd_axi``.
COUNTER_PATH = "regs.{name}"

#: The attribute that tags a counter's flip-flop (its value: the counter's name).
ATTRIBUTE = "dptbd_preset"

_CELL = re.compile(r'(  attribute \\' + ATTRIBUTE + r' "(?P<name>\w+)"\n'
                   r'(?:  attribute .*\n)*'
                   r'  cell \S+ \S+\n'
                   r'(?P<body>(?:    .*\n)*?))'
                   r'    connect \\D (?P<d>.*)\n')
_WIDTH = re.compile(r"    parameter \\WIDTH (\d+)\n")


def preset_counters(cfg: DPConfig) -> tuple[str, ...]:
    """The counters of ``cfg``'s register map, lower case, in the order of
    ``preset_load``'s bits (the register map's order of its counter fields)."""
    from dptbd.hw.register_map import register_map

    return tuple(reg.name.lower() for reg, _field in register_map(cfg).fields("counter"))


def tag_commands(cfg: DPConfig) -> list[str]:
    """The Yosys commands (after :data:`~dptbd.sim.mutation.netlist.PREPARE`, before the
    ``mutate`` commands) that tag each counter's flip-flop; each asserts that it finds
    exactly one."""
    lines = []
    for name in preset_counters(cfg):
        select = f"w:{COUNTER_PATH.format(name=name)} %ci*:+$dff[Q] t:$dff %i"
        lines += [f"select -assert-count 1 {select}",
                  f'setattr -set {ATTRIBUTE} "{name}" {select}']
    return lines


def add_presets(rtlil: str, module: str, counters: tuple[str, ...]) -> str:
    """``rtlil`` (Yosys' ``write_rtlil`` of the tagged design) with the preset ports and one
    ``$mux`` on each tagged flip-flop's ``D`` in ``module``.

    Raises
    ------
    ValueError
        A counter of ``counters`` has no tagged flip-flop, or ``module`` is not in ``rtlil``.
    """
    start = rtlil.find(f"\nmodule \\{module}\n")
    if start < 0:
        raise ValueError(f"no module {module} in the netlist")
    end = rtlil.index("\nend\n", start)
    body = rtlil[start:end]
    found: dict[str, tuple[str, int]] = {}

    def rewire(match: re.Match) -> str:
        name = match["name"]
        width = int(_WIDTH.search(match["body"])[1])
        found[name] = (match["d"], width)
        return f"{match[1]}    connect \\D \\{ATTRIBUTE}_d_{name}\n"

    body = _CELL.sub(rewire, body)
    missing = [n for n in counters if n not in found]
    if missing:
        raise ValueError(f"no tagged flip-flop for the counter(s) {', '.join(missing)}")
    width = max(w for _d, w in found.values())
    wires = [f"  wire width {len(counters)} input 1000001 \\preset_load",
             f"  wire width {width} input 1000002 \\preset_value"]
    cells = []
    for bit, name in enumerate(counters):
        d, w = found[name]
        wires.append(f"  wire width {w} \\{ATTRIBUTE}_d_{name}")
        cells += [f"  cell $mux \\{ATTRIBUTE}_mux_{name}",
                  f"    parameter \\WIDTH {w}",
                  f"    connect \\A {d}",
                  f"    connect \\B \\preset_value [{w - 1}:0]",
                  f"    connect \\S \\preset_load [{bit}]",
                  f"    connect \\Y \\{ATTRIBUTE}_d_{name}",
                  "  end"]
    head = body.index("\n", 1) + 1                      # after the module line: wires first
    body = body[:head] + "\n".join(wires) + "\n" + body[head:]
    return rtlil[:start] + body + "\n" + "\n".join(cells) + rtlil[end:]
