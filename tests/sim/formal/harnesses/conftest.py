"""The assertion messages of a harness, read from its RTLIL (as the runner reads them)."""

import pytest
from amaranth.back import rtlil
from amaranth.hdl import Fragment

from dptbd.sim.formal.runner import check_messages


@pytest.fixture
def messages():
    def read(harness) -> set[str]:
        il = rtlil.convert(Fragment.get(harness, None), name="top", ports=harness.ports())
        return set(check_messages(il).values()) - {""}
    return read
