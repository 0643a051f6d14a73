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
    ({"clang++", "g++", "c++"}, "a C++ compiler (Debian package 'g++')"),
    ({"verilator", "clang++", "g++", "c++", "make"},
     "verilator (Debian package 'verilator') and a C++ "
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


@pytest.mark.parametrize("found, cxx, chosen", [
    ({"clang++", "g++", "c++"}, None, "clang++"),    # clang++ first (COMPILERS)
    ({"g++", "c++"}, None, "g++"),
    ({"c++"}, None, "c++"),
    ({"clang++", "g++"}, "g++", "g++"),              # $CXX when set
    ({"clang++"}, "g++", None),                      # ... and only $CXX
    (set(), None, None),
])
def test_the_compiler_is_cxx_else_the_first_found(monkeypatch, found, cxx, chosen):
    monkeypatch.setattr(shutil, "which", lambda name, *a, **k: f"/bin/{name}" if name in found
                        else None)
    if cxx is None:
        monkeypatch.delenv("CXX", raising=False)
    else:
        monkeypatch.setenv("CXX", cxx)
    assert T.compiler() == (None if chosen is None else f"/bin/{chosen}")
    if chosen is not None:
        assert T.compiler_make_args() == [f"CXX=/bin/{chosen}", f"LINK=/bin/{chosen}"]


def test_the_build_compiles_and_links_with_the_compiler_it_names(tmp_path, monkeypatch):
    """Verilator's makefile names g++ whatever ``$CXX`` says: the build passes the compiler
    whose version line is in its key."""
    commands = []
    real_step = T.step

    def step(cmd, cwd, verbose, what):
        commands.append(cmd)
        return real_step(cmd, cwd, verbose, what)

    monkeypatch.setattr(T, "step", step)
    V.build(BASE, "dp", root=tmp_path / "builds")
    make = [cmd for cmd in commands if cmd[0] == "make"]
    assert len(make) == 1 and make[0][-2:] == T.compiler_make_args()
    assert T.check_tools()["c++"] == T._first_line([T.compiler(), "--version"])
