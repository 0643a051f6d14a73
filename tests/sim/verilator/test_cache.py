"""The Verilator build cache (:mod:`dptbd.sim.verilator.cache`): reuse, stale stamps,
interrupted builds, the build root, and every bad design refused before anything is built
(missing tools: ``test_toolchain.py``).

Builds are cached under ``~/.cache/dptbd/verilator``; the cache tests use a fresh root in
``tmp_path`` seeded with the Verilator runtime library of the default root when it has one.
"""

from __future__ import annotations

import json
import pathlib
import shutil

import pytest

from dptbd.sim.verilator import cache as V
from dptbd.sim.verilator import toolchain as T
from dptbd.sim.rtl.check import check_frames
from dptbd.sim.icarus import config_name
from dptbd.sim.scenarios import make_frames

from helpers.verilator_harness import SEG, make_config  # noqa: E402
from helpers.refusals import whole  # noqa: E402

pytestmark = pytest.mark.skipif(shutil.which("verilator") is None, reason="needs Verilator")

BASE = make_config(**SEG)

def fresh_root(path: pathlib.Path) -> pathlib.Path:
    """An empty build root with the default root's runtime library (compiling it costs
    most of a first build); without one the first build compiles it."""
    path.mkdir(parents=True, exist_ok=True)
    src = T.runtime_dir(V.default_build_root(), T.check_tools(), False)
    if (src / "complete").exists():
        shutil.copytree(src, path / src.name)
    return path


CACHE_CFG = make_config(width=13, height=7, segment_frames=2)


@pytest.fixture(scope="module")
def pristine_root(tmp_path_factory):
    return fresh_root(tmp_path_factory.mktemp("pristine") / "builds")


@pytest.fixture
def pristine(pristine_root):
    """(root, build) of CACHE_CFG, built once per module — again if the key changed
    meanwhile (the gateware or the harness edited while the tests run)."""
    sim = V.build(CACHE_CFG, "dp", root=pristine_root)
    return pristine_root, sim


@pytest.fixture
def cache(pristine, tmp_path):
    """A copy of the pristine root: (root, directory of the build)."""
    root = tmp_path / "builds"
    shutil.copytree(pristine[0], root)
    return root, root / pristine[1].directory.name


def no_compiling(monkeypatch):
    def refuse(*a, **k):
        raise AssertionError("compiled although the cache should have been used")
    monkeypatch.setattr(T, "step", refuse)
    monkeypatch.setattr(V, "_generate", refuse)


def assert_works(sim):
    frames = make_frames("noise", sim.cfg, 2, seed=1)
    result = check_frames(sim, frames)
    assert result.passed, result.report


def test_second_build_is_cached_and_does_not_recompile(cache, monkeypatch):
    root, directory = cache
    exe = directory / V.EXECUTABLE
    before = (exe.stat().st_mtime_ns, exe.read_bytes())
    no_compiling(monkeypatch)
    sim = V.build(CACHE_CFG, "dp", root=root)
    assert sim.cached and sim.directory == directory.resolve()
    assert (exe.stat().st_mtime_ns, exe.read_bytes()) == before
    assert sim.latency == 14
    assert sorted(p.name for p in root.iterdir() if p.name.startswith(config_name(CACHE_CFG))) \
        == [directory.name]
    assert_works(sim)


def test_build_directory_name_and_key(pristine):
    root, sim = pristine
    assert sim.directory.name == f"{config_name(CACHE_CFG)}-dp-{sim.key[:12]}"
    assert sim.directory.parent == root.resolve()
    other = V._build_key(CACHE_CFG, "core", "auto", False)
    assert other != sim.key and V._build_key(CACHE_CFG, "dp", "auto", False) == sim.key
    assert V._build_key(CACHE_CFG.replace(segment_frames=3), "dp", "auto", False) != sim.key


def _missing(directory):
    (directory / V.STAMP).unlink()


def _garbage(directory):
    (directory / V.STAMP).write_text("{not json")


def _json_list(directory):
    (directory / V.STAMP).write_text("[1, 2]\n")


def _json_null(directory):
    (directory / V.STAMP).write_text("null\n")


def _foreign_key(directory):
    stamp = json.loads((directory / V.STAMP).read_text())
    stamp["key"] = "f" * 64
    (directory / V.STAMP).write_text(json.dumps(stamp))


def _no_manifest(directory):
    stamp = json.loads((directory / V.STAMP).read_text())
    del stamp["manifest"]
    (directory / V.STAMP).write_text(json.dumps(stamp))


def _altered_executable(directory):
    with open(directory / V.EXECUTABLE, "ab") as fh:
        fh.write(b"\0")


def _missing_executable(directory):
    (directory / V.EXECUTABLE).unlink()


def _empty_directory(directory):
    shutil.rmtree(directory)
    directory.mkdir()


DAMAGES = [_missing, _garbage, _json_list, _json_null, _foreign_key, _no_manifest,
           _altered_executable, _missing_executable, _empty_directory]


class _Compiled(Exception):
    """Raised by a stand-in for the compiler: the build was about to compile."""


@pytest.mark.parametrize("damage", DAMAGES)
def test_a_damaged_build_is_never_reused(cache, damage, monkeypatch):
    """Every damage sends the build to the compiler (here a stand-in, so no compile);
    the rebuild itself: the test below."""
    root, directory = cache

    def compile_(*args, **kwargs):
        raise _Compiled

    monkeypatch.setattr(V, "_compile", compile_)
    damage(directory)
    with pytest.raises(_Compiled):
        V.build(CACHE_CFG, "dp", root=root)


# one damage rebuilt in the default suite (a compile each), every one with -m slow
@pytest.mark.parametrize("damage", [
    pytest.param(d, marks=() if d is _altered_executable else pytest.mark.slow)
    for d in DAMAGES])
def test_a_damaged_build_is_rebuilt_never_reused(cache, damage):
    root, directory = cache
    damage(directory)
    sim = V.build(CACHE_CFG, "dp", root=root)
    assert not sim.cached
    assert sim.directory == directory.resolve()
    assert V._stamp_ok(directory, sim.key) == sim.manifest
    assert sorted(p.name for p in root.iterdir() if p.name.startswith(config_name(CACHE_CFG))) \
        == [directory.name]                                 # no temporary left behind
    assert_works(sim)
    assert V.build(CACHE_CFG, "dp", root=root).cached


@pytest.mark.parametrize("exc", [RuntimeError("make failed (exit 2)"), KeyboardInterrupt()])
def test_an_interrupted_build_leaves_nothing_behind(tmp_path, monkeypatch, exc):
    root = fresh_root(tmp_path / "builds")
    real_step = T.step

    def step(cmd, cwd, verbose, what):
        if cmd[0] == "make":
            raise exc
        return real_step(cmd, cwd, verbose, what)

    monkeypatch.setattr(T, "step", step)
    with pytest.raises(type(exc)):
        V.build(CACHE_CFG, "dp", root=root)
    assert [p.name for p in root.iterdir() if p.name.startswith(config_name(CACHE_CFG))] == []
    if isinstance(exc, KeyboardInterrupt):
        return          # the build after an interruption: the same for either (a compile)
    monkeypatch.setattr(T, "step", real_step)
    sim = V.build(CACHE_CFG, "dp", root=root)
    assert not sim.cached
    assert_works(sim)


def test_an_interrupted_rebuild_never_leaves_a_reusable_stale_build(cache, monkeypatch):
    """A stale directory whose rebuild fails is not reused by the next build either."""
    root, directory = cache
    _altered_executable(directory)

    def step(cmd, cwd, verbose, what):
        raise RuntimeError("verilator failed (exit 1)")

    monkeypatch.setattr(T, "step", step)
    with pytest.raises(RuntimeError, match=r"^verilator failed \(exit 1\)$"):
        V.build(CACHE_CFG, "dp", root=root)
    assert [p.name for p in root.iterdir() if p.name.startswith(directory.name + ".")] == []
    monkeypatch.undo()
    sim = V.build(CACHE_CFG, "dp", root=root)
    assert not sim.cached
    assert_works(sim)


def test_build_root_from_the_environment(monkeypatch, tmp_path):
    monkeypatch.setenv("DPTBD_BUILD_DIR", str(tmp_path / "b"))
    assert V.default_build_root() == tmp_path / "b" / "verilator"
    monkeypatch.delenv("DPTBD_BUILD_DIR")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "x"))
    assert V.default_build_root() == tmp_path / "x" / "dptbd" / "verilator"


@pytest.mark.parametrize("design", ["DP", "seg", "", "icarus"])
def test_build_refuses_an_unknown_design(tmp_path, design):
    with pytest.raises(ValueError, match=rf"^design must be one of dp, core, segmenter, axi, "
                                         rf"got {repr(design)}$"):
        V.build(BASE, design, root=tmp_path / "builds")
    assert not (tmp_path / "builds").exists()


def test_a_mutant_build_at_p_above_1_is_of_design_dp_only(tmp_path):
    with pytest.raises(ValueError, match=whole(
            "a mutant build at pixels_per_clock=2 is of design 'dp' (dptbd_dp) only, got "
            "'segmenter'")):
        V.build(make_config(**SEG, pixels_per_clock=2), "segmenter", root=tmp_path / "b",
                mutations=("mutate -mode inv -cell $c -port Y -portbit 0",))
    assert not (tmp_path / "b").exists()


def test_build_refuses_an_unknown_family(tmp_path):
    with pytest.raises(ValueError, match=whole("family must be one of ('ice40', 'ecp5'), "
                                               "got 'xilinx'")):
        V.build(BASE, "dp", root=tmp_path / "builds", family="xilinx")
    assert not (tmp_path / "builds").exists()


def test_a_mutant_build_has_no_family(tmp_path):
    with pytest.raises(ValueError, match=whole(
            "a mutant build has DPCore's default options: family must be None with "
            "mutations, got 'ecp5'")):
        V.build(BASE, "dp", root=tmp_path / "b", family="ecp5",
                mutations=("mutate -mode inv -cell $c -port Y -portbit 0",))
    assert not (tmp_path / "b").exists()


def test_a_family_build_is_the_family_verilog_with_its_cell_models(pristine):
    """``family="ecp5"``: the Verilog ``dptbd verilog --family ecp5`` writes (its on-chip
    store in DP16KDs), verilated with the DP16KD model, in a build of its own; bit-exact."""
    from dptbd.hw.flow.family import get_family
    from dptbd.hw.flow.verilog import generate_verilog
    from dptbd.sim.cell_models import model_path

    root, plain = pristine
    sim = V.build(CACHE_CFG, "dp", root=root, family="ecp5")
    assert sim.family == "ecp5" and plain.family is None and sim.key != plain.key
    assert sim.directory.name == f"{config_name(CACHE_CFG)}-dp-ecp5-{sim.key[:12]}"
    options = dict(get_family("ecp5").options_for(CACHE_CFG))
    assert sim.manifest["core_options"] == options
    text, _ = generate_verilog(CACHE_CFG, core_options=options)
    assert (sim.directory / "dptbd_dp.v").read_text() == text and "\n  DP16KD #(" in text
    command = json.loads((sim.directory / V.STAMP).read_text())["command"]
    assert str(model_path("DP16KD")) in command
    assert str(model_path("DP16KD")) not in json.loads(
        (plain.directory / V.STAMP).read_text())["command"]
    assert_works(sim)
