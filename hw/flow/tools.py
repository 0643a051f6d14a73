"""Running the synthesis tools: finding them, their version, and their errors.

A missing tool raises :class:`ToolNotFoundError` naming the Debian package that provides it;
a tool that runs past its timeout is killed and raises :class:`ToolTimeoutError`; any other
tool failure raises :class:`SynthToolError` with the tail of the tool's log.
"""

from __future__ import annotations

import pathlib
import shutil
import subprocess
import time
from typing import Sequence

__all__ = [
    "DEBIAN_PACKAGES", "SynthToolError", "ToolNotFoundError", "ToolTimeoutError",
    "require_tool", "tool_version",
]

#: Debian package that provides each tool (named in :class:`ToolNotFoundError`).
DEBIAN_PACKAGES = {"yosys": "yosys", "nextpnr-ice40": "nextpnr-ice40"}


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
    """The tool is not on ``PATH``; the message names the Debian package to install."""


class ToolTimeoutError(SynthToolError):
    """The tool ran longer than its timeout and was killed."""


def require_tool(name: str) -> str:
    """Absolute path of the executable ``name`` (a name on ``PATH`` or a path).

    Raises
    ------
    ToolNotFoundError
        Naming the Debian package that provides it (``apt-get install …``).
    """
    path = shutil.which(name)
    if path is None:
        base = pathlib.Path(name).name
        package = DEBIAN_PACKAGES.get(base, base)
        raise ToolNotFoundError(
            f"{name!r} not found on PATH: it is needed for iCE40 synthesis; install the "
            f"Debian package {package!r} (apt-get install {package})", tool=base)
    return path


def tool_version(executable: str, timeout: float = 30) -> str:
    """First non-empty line of ``executable -V`` / ``--version`` output ("" if neither works)."""
    for flag in ("-V", "--version"):
        try:
            proc = subprocess.run([executable, flag], capture_output=True, text=True,
                                  timeout=timeout)
        except (OSError, subprocess.TimeoutExpired):
            continue
        lines = [ln.strip() for ln in (proc.stdout + proc.stderr).splitlines() if ln.strip()]
        if proc.returncode == 0 and lines:
            return lines[0]
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
