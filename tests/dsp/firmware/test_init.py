"""Building the DSP firmware: compiler lookup, the cache, warnings under gcc and clang, and the
firmware's bad-input behaviour under -fsanitize=address,undefined (tests/dsp/firmware/selftest.c)."""

import os
import pathlib
import re
import shutil
import subprocess

import pytest

from dptbd.dsp import firmware as fb

HERE = pathlib.Path(__file__).resolve().parent
EXAMPLE = HERE.parents[2] / "examples" / "dsp_tracker" / "main.c"
CAPACITY_SETS = [(), fb.capacity_defines(1, 1, 1, 0), fb.capacity_defines(4, 16, 3, 1),
                 fb.capacity_defines(1000, 2000, 500, 0)]
SANITIZE = ("-g", "-fsanitize=address,undefined", "-fno-sanitize-recover=all")


def test_missing_compiler_is_named(monkeypatch):
    with pytest.raises(fb.FirmwareBuildError, match=(
            r"^no C compiler: 'no-such-cc' \(compiler=\) is not on PATH; the DSP firmware needs "
            r"one \(Debian: apt-get install gcc, or clang; or set CC to a compiler\)$")):
        fb.find_compiler("no-such-cc")
    monkeypatch.setenv("CC", "no-such-cc-either")
    with pytest.raises(fb.FirmwareBuildError, match=r"^no C compiler: 'no-such-cc-either' \(\$CC\) "):
        fb.build_shared_library()


def test_cache_key_reuse_and_atomic_rename(tmp_path, monkeypatch):
    lib = fb.build_shared_library(cache=tmp_path)
    assert re.fullmatch(r"libdptbd_track-[0-9a-f]{32}\.so", lib.name) and lib.parent == tmp_path
    assert sorted(p.name for p in tmp_path.iterdir()) == [lib.name]    # no temporary left

    def no_compile(cmd):
        raise AssertionError("compiled again")
    monkeypatch.setattr(fb, "_run", no_compile)
    assert fb.build_shared_library(cache=tmp_path) == lib                # same key: cached
    monkeypatch.undo()
    other = fb.build_shared_library(fb.capacity_defines(4, 16, 3, 1), cache=tmp_path)
    assert other != lib and other.is_file()                              # flags are in the key
    monkeypatch.setenv("DPTBD_FIRMWARE_CACHE", str(tmp_path / "env"))
    assert fb.cache_dir() == tmp_path / "env"


def test_a_failed_build_names_the_command_and_the_error(tmp_path):
    with pytest.raises(fb.FirmwareBuildError) as info:
        fb.build_shared_library(fb.capacity_defines(0, 1, 1, 1), cache=tmp_path)
    msg = str(info.value)
    assert msg.startswith("firmware build failed (") and "-DDPTBD_CAPACITY=0" in msg
    assert "DPTBD_CAPACITY must be in [1, 65535]" in msg
    assert list(tmp_path.iterdir()) == []


def _compile(compiler, source, defines, opt, tmp_path):
    cmd = [compiler, *fb.WARNING_FLAGS, opt, *defines, f"-I{fb.FIRMWARE_DIR}", "-c", str(source),
           "-o", str(tmp_path / "out.o")]
    res = subprocess.run(cmd, capture_output=True, text=True)
    assert (res.returncode, res.stderr) == (0, ""), " ".join(cmd)


@pytest.mark.parametrize("compiler", ["gcc", "clang"])
def test_warning_free_under_gcc_and_clang(compiler, tmp_path):
    if shutil.which(compiler) is None:
        pytest.skip(f"{compiler} is not installed (bash scripts/setup.sh setup installs it)")
    for defines in CAPACITY_SETS:
        for opt in ("-O0", "-O2", "-O3"):
            for source in fb.SOURCES:
                _compile(compiler, fb.FIRMWARE_DIR / source, defines, opt, tmp_path)
    for source in (EXAMPLE, HERE / "selftest.c", HERE / "probe.c"):
        _compile(compiler, source, (), "-O2", tmp_path)


@pytest.mark.parametrize("defines", CAPACITY_SETS[:3])
def test_bad_input_under_the_sanitizers(defines, tmp_path):
    exe = fb.build_executable([HERE / "selftest.c"], tmp_path / "selftest",
                              defines=defines, extra_flags=SANITIZE)
    res = subprocess.run([str(exe)], capture_output=True, text=True,
                         env={**os.environ, "UBSAN_OPTIONS": "print_stacktrace=1"})
    assert res.returncode == 0, res.stdout + res.stderr
    assert re.fullmatch(r"selftest: all passed \(context \d+ bytes\)\n", res.stdout)
    assert res.stderr == ""
