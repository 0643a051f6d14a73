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


@pytest.fixture
def cells():
    """The DP16KDs of a harness's design: instances and behavioural models, by kind."""
    from amaranth.hdl import Instance

    from dptbd.sim.dp16kd_model import DP16KDModel

    def count(harness) -> dict[str, int]:
        found: dict[str, int] = {}

        def walk(fragment):
            kind = ("Instance " + fragment.type if isinstance(fragment, Instance) else
                    "DP16KDModel" if any(isinstance(o, DP16KDModel)
                                         for o in fragment.origins or ()) else None)
            if kind:
                found[kind] = found.get(kind, 0) + 1
            for sub, *_ in fragment.subfragments:
                walk(sub)

        walk(Fragment.get(harness, None))
        return found
    return count
