"""The Verilator toolchain: the tools a build needs, its flags, the harness sources, a
compile step, and Verilator's runtime library kept beside the builds.

:func:`check_tools` finds Verilator, a C++ compiler and make (:class:`ToolMissingError`
names what is missing); their version lines go into every build key
(:mod:`dptbd.sim.verilator.cache`). :func:`runtime_dir`, :func:`restore_runtime` and
:func:`save_runtime` keep Verilator's runtime library (``verilated*.o``): the same for every
design, compiled by the first build of a toolchain and copied into later ones (it is most
of a build's compile time).
"""

from __future__ import annotations

import functools
import hashlib
import json
import os
import pathlib
import shutil
import subprocess
import tempfile
from typing import Sequence

__all__ = [
    "VERILATOR_FLAGS",
    "CXX_FLAGS",
    "COVERAGE_FLAGS",
    "HARNESS",
    "HARNESSES",
    "COMPILERS",
    "ToolMissingError",
    "check_tools",
    "compiler",
    "compiler_make_args",
    "harness_sources",
    "store_defines",
    "step",
    "compile_executable",
    "runtime_dir",
    "restore_runtime",
    "save_runtime",
]

#: Verilator flags. ``-O3 --x-assign fast --x-initial fast --noassert`` measured fastest
#: here; ``--threads`` is far slower on this design and is not used. ``-Wno-WIDTH``: Yosys'
#: ``write_verilog`` relies on implicit extension (``hw/flow/verilog.py``, lint waivers).
VERILATOR_FLAGS = ("--cc", "--exe", "-O3", "--x-assign", "fast", "--x-initial", "fast",
                   "--noassert", "-Wno-fatal", "-Wno-WIDTH", "--prefix", "Vdut")
#: C++ optimisation of the harness, the verilated model (``OPT_FAST``) and Verilator's runtime
#: library (``OPT_GLOBAL``; compiled once per toolchain, below): -O3 rather than
#: Verilator's default -Os, for simulation speed.
CXX_FLAGS = ("-O3",)
#: The C++ compiler of every build (the verilated model, the harness, Verilator's runtime
#: library), passed to Verilator's makefile, which otherwise names g++ whatever ``$CXX``
#: says: ``$CXX`` when set, else the first of these found. clang++ first: with Verilator
#: 5.006 a build takes 0.6–0.8 of g++'s time and its simulation runs as fast or faster
#: (``python benchmarks/bench_verilator.py --compilers``; ``docs/simulation.md``).
COMPILERS = ("clang++", "g++", "c++")
#: Verilator flags of the coverage build (added to :data:`VERILATOR_FLAGS`): a point per
#: branch of every ``if`` / ``case`` (line) and per bit of every signal (toggle).
COVERAGE_FLAGS = ("--coverage-line", "--coverage-toggle")

HARNESS = pathlib.Path(__file__).resolve().parents[1] / "harness" / "dptbd_harness.cpp"
#: Designs with a harness of their own (flat AXI ports, register operations):
#: ``dptbd.sim.verilator.axi`` runs it.
HARNESSES = {"axi": HARNESS.with_name("dptbd_axi_harness.cpp")}

class ToolMissingError(RuntimeError):
    """Verilator or a C++ compiler is not installed."""


def _first_line(cmd: Sequence[str]) -> str:
    out = subprocess.run(cmd, capture_output=True, text=True, check=False)
    return (out.stdout or out.stderr).strip().splitlines()[0] if (out.stdout or out.stderr) \
        else ""


def compiler() -> str | None:
    """Path of the C++ compiler builds use: ``$CXX`` when set (None if it is not found),
    else the first of :data:`COMPILERS` on PATH, else None."""
    if os.environ.get("CXX"):
        return shutil.which(os.environ["CXX"])
    return next(filter(None, map(shutil.which, COMPILERS)), None)


def compiler_make_args() -> list[str]:
    """Verilator makefile variables that make :func:`compiler` compile and link."""
    cxx = compiler()
    return [f"CXX={cxx}", f"LINK={cxx}"]


@functools.lru_cache(maxsize=None)
def check_tools() -> dict[str, str]:
    """``{"verilator": version line, "c++": version line}``, the second :func:`compiler`'s;
    raises :class:`ToolMissingError` naming what is missing and the Icarus fallback."""
    missing = []
    verilator = shutil.which("verilator")
    if verilator is None:
        missing.append("verilator (Debian package 'verilator')")
    cxx = compiler()
    if cxx is None:
        missing.append("a C++ compiler (Debian package 'g++')")
    make = shutil.which("make")
    if make is None:
        missing.append("make (Debian package 'make')")
    if missing:
        raise ToolMissingError(
            "compiled RTL simulation needs " + " and ".join(missing) + "; install it "
            "(bash scripts/setup.sh setup) or use the Icarus simulator instead "
            "(dptbd sim --simulator icarus)")
    return {"verilator": _first_line([verilator, "--version"]),
            "c++": _first_line([cxx, "--version"])}


def harness_sources(design: str) -> list[pathlib.Path]:
    """The harness source of ``design``, the header every harness shares and, for ``axi``,
    the AXI4 memory model it includes with the state store in external memory."""
    source = HARNESSES.get(design, HARNESS)
    return [source, source.with_name("harness_io.h"),
            *([source.with_name("axi4_memory.h")] if design == "axi" else [])]


def store_defines(store) -> list[str]:
    """The harness defines of a build with the state in external memory (``axi4_memory.h``)."""
    return ["-DDPTBD_AXI_STORE", f"-DDPTBD_AXI_DATA_BITS={store.data_bits}",
            f"-DDPTBD_AXI_OUTSTANDING={store.outstanding}",
            f"-DDPTBD_FRAME_BYTES={store.frame_bytes}ULL"]


def step(cmd: list[str], cwd: pathlib.Path, verbose: bool, what: str) -> None:
    out = subprocess.run(cmd, cwd=cwd, capture_output=not verbose, text=True, check=False)
    if out.returncode != 0:
        log = ((out.stdout or "") + (out.stderr or ""))[-4000:]
        raise RuntimeError(f"{what} failed (exit {out.returncode}):\n{log}")


def runtime_dir(root: pathlib.Path, tools: dict, waves: bool, coverage: bool = False
                 ) -> pathlib.Path:
    extra = {"coverage": COVERAGE_FLAGS} if coverage else {}    # VM_COVERAGE: other objects
    key = hashlib.sha256(json.dumps({**extra, "tools": tools, "waves": waves,
                                     "flags": VERILATOR_FLAGS, "cxx": CXX_FLAGS},
                                    sort_keys=True).encode())
    return root / f"runtime-{key.hexdigest()[:12]}"


def compile_executable(work: pathlib.Path, executable: str, runtime: pathlib.Path,
                       verbose: bool, what: str) -> None:
    """``make`` Verilator's output in ``work/obj`` (``Vdut.mk``) into ``work/executable``
    with :func:`compiler` and :data:`CXX_FLAGS`: Verilator's runtime library copied from
    ``runtime`` when kept there (:func:`runtime_dir`), else compiled and kept; ``obj``
    removed after."""
    obj = work / "obj"
    reused = restore_runtime(runtime, obj)
    step(["make", "-C", "obj", "-f", "Vdut.mk", f"-j{min(2, os.cpu_count() or 1)}",
          f"OPT_FAST={' '.join(CXX_FLAGS)}", f"OPT_GLOBAL={' '.join(CXX_FLAGS)}",
          *compiler_make_args()], work, verbose, what)
    if not reused:
        save_runtime(runtime, obj)
    shutil.move(str(obj / executable), str(work / executable))
    shutil.rmtree(obj)


def restore_runtime(runtime: pathlib.Path, obj: pathlib.Path) -> bool:
    objects = sorted(runtime.glob("verilated*.o")) if (runtime / "complete").exists() else []
    for path in objects:
        target = obj / path.name
        shutil.copyfile(path, target)          # a fresh mtime: newer than its source
    return bool(objects)


def save_runtime(runtime: pathlib.Path, obj: pathlib.Path) -> None:
    objects = sorted(obj.glob("verilated*.o"))
    if not objects or (runtime / "complete").exists():
        return
    tmp = pathlib.Path(tempfile.mkdtemp(prefix=runtime.name + ".", dir=runtime.parent))
    for path in objects:
        shutil.copyfile(path, tmp / path.name)
    (tmp / "complete").write_text("\n".join(p.name for p in objects) + "\n")
    try:
        os.replace(tmp, runtime)
    except OSError:                            # another build saved it first
        shutil.rmtree(tmp, ignore_errors=True)
