"""``dptbd.hw.flow.tools``: a missing tool names the Debian package that provides it."""

import pytest

from dptbd.hw.flow.tools import ToolNotFoundError, require_tool


def test_missing_tool_names_the_debian_package():
    with pytest.raises(ToolNotFoundError, match=(
            r"^'/nonexistent/bin/nextpnr-ice40' not found on PATH: it is needed for iCE40 "
            r"synthesis; install the Debian package 'nextpnr-ice40' \(apt-get install "
            r"nextpnr-ice40\)$")):
        require_tool("/nonexistent/bin/nextpnr-ice40")
