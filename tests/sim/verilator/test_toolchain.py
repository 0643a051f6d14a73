"""The Verilator toolchain (:mod:`dptbd.sim.verilator.toolchain`): every missing tool named,
before anything is built, and the versions that go into the build key."""

from __future__ import annotations

import shutil

import pytest

from dptbd.sim.verilator import cache as V
from dptbd.sim.verilator import toolchain as T

from helpers.verilator_harness import SEG, make_config  # noqa: E402
from helpers.refusals import whole

pytestmark = pytest.mark.skipif(shutil.which("verilator") is None, reason="needs Verilator")

BASE = make_config(**SEG)


@pytest.fixture
def clear_tools():
    T.check_tools.cache_clear()
    yield
    T.check_tools.cache_clear()


INSTALL = ("; install it (bash scripts/setup.sh setup) or use the Icarus simulator instead "
           "(dptbd sim --simulator icarus)")


@pytest.mark.parametrize("missing,named", [
    ({"verilator"}, "verilator (Debian package 'verilator')"),
    ({"make"}, "make (Debian package 'make')"),
    ({"g++", "c++"}, "a C++ compiler (Debian package 'g++')"),
    ({"verilator", "g++", "c++", "make"}, "verilator (Debian package 'verilator') and a C++ "
     "compiler (Debian package 'g++') and make (Debian package 'make')"),
])
def test_missing_tools_are_named(tmp_path, monkeypatch, clear_tools, missing, named):
    real = shutil.which
    monkeypatch.delenv("CXX", raising=False)
    monkeypatch.setattr(shutil, "which", lambda name, *a, **k: None if name in missing
                        else real(name, *a, **k))
    message = whole("compiled RTL simulation needs " + named + INSTALL)
    with pytest.raises(T.ToolMissingError, match=message):
        T.check_tools()
    with pytest.raises(T.ToolMissingError, match=message):
        V.build(BASE, "dp", root=tmp_path / "builds")
    assert not (tmp_path / "builds").exists()


def test_check_tools_names_the_versions():
    tools = T.check_tools()
    assert set(tools) == {"verilator", "c++"}
    assert tools["verilator"].startswith("Verilator ")
