"""Build the DSP firmware (``dptbd/dsp/firmware/``) with the system C compiler.

The association firmware (``dptbd_track.c``, ``docs/dsp_firmware.md``) is compiled on first
use into a shared library that :mod:`dptbd.dsp.c_tracker` loads with :mod:`ctypes`:

* **compiler**: ``compiler=`` if given, else ``$CC``, else ``cc``; a missing one is refused
  naming it and how to install one;
* **flags**: :data:`WARNING_FLAGS` (``-std=c99 -Wall -Wextra -Werror -pedantic``: a warning
  is a build failure) plus :data:`OPT_FLAGS`, ``-fPIC -shared``, the capacities as ``-D``
  (:func:`capacity_defines`: they are compile-time constants of the firmware) and any
  ``extra_flags``;
* **cache**: ``$DPTBD_FIRMWARE_CACHE``, else ``$XDG_CACHE_HOME/dptbd/firmware``, else
  ``~/.cache/dptbd/firmware``; one file per key, the SHA-256 of the sources and headers,
  the compiler's ``--version`` text and every flag. A library is compiled into a temporary
  file in the cache folder and renamed into place (:func:`os.replace`, atomic), so two
  processes building the same key at once both end with a whole library.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import tempfile
from pathlib import Path
from typing import Sequence

__all__ = ["FIRMWARE_DIR", "SOURCES", "HEADERS", "WARNING_FLAGS", "OPT_FLAGS",
           "FirmwareBuildError", "find_compiler", "compiler_version", "capacity_defines",
           "cache_dir", "build_key", "compile_command", "build_shared_library",
           "build_executable"]

#: The firmware's sources.
FIRMWARE_DIR = Path(__file__).resolve().parent
#: The firmware's C files.
SOURCES = ("dptbd_track.c", "dptbd_backtrack.c", "dptbd_trim.c")
HEADERS = ("dptbd_track.h", "dptbd_candidate_record.h")
#: Every build: C99, every warning an error.
WARNING_FLAGS = ("-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic")
#: Optimisation, every build.
OPT_FLAGS = ("-O2",)


class FirmwareBuildError(RuntimeError):
    """The firmware could not be built: no compiler, or the compiler failed (message has
    the command and the compiler's output)."""


def find_compiler(compiler: str | None = None) -> str:
    """Path of the C compiler: ``compiler``, else ``$CC``, else ``cc``."""
    name = compiler or os.environ.get("CC") or "cc"
    path = shutil.which(name)
    if path is None:
        source = "compiler=" if compiler else ("$CC" if os.environ.get("CC") else "the default")
        raise FirmwareBuildError(
            f"no C compiler: {name!r} ({source}) is not on PATH; the DSP firmware needs one "
            f"(Debian: apt-get install gcc, or clang; or set CC to a compiler)")
    return path


def compiler_version(compiler: str) -> str:
    """The compiler's ``--version`` text (part of the cache key)."""
    try:
        out = subprocess.run([compiler, "--version"], capture_output=True, text=True, check=True)
    except (OSError, subprocess.CalledProcessError) as exc:
        raise FirmwareBuildError(f"C compiler {compiler!r} does not run: {exc}") from None
    return out.stdout.strip()


def capacity_defines(capacity: int = 64, max_candidates: int = 128, max_points: int = 64,
                     output_capacity: int = 64) -> tuple[str, ...]:
    """``-D`` flags of the firmware's compile-time capacities (AssociationConfig's names)."""
    return (f"-DDPTBD_CAPACITY={int(capacity)}", f"-DDPTBD_MAX_CANDIDATES={int(max_candidates)}",
            f"-DDPTBD_MAX_POINTS={int(max_points)}",
            f"-DDPTBD_OUTPUT_CAPACITY={int(output_capacity)}")


def cache_dir() -> Path:
    """Folder of built libraries (module docstring)."""
    env = os.environ.get("DPTBD_FIRMWARE_CACHE")
    if env:
        return Path(env)
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "dptbd" / "firmware"


def build_key(compiler: str, flags: Sequence[str],
              sources: Sequence[str | Path] = ()) -> str:
    """SHA-256 of the firmware's sources and headers, any other ``sources``, the compiler's
    version and the flags."""
    h = hashlib.sha256()
    for path in [FIRMWARE_DIR / name for name in SOURCES + HEADERS] + [Path(p) for p in sources]:
        h.update(path.name.encode() + b"\0" + path.read_bytes() + b"\0")
    h.update(compiler_version(compiler).encode() + b"\0")
    h.update("\0".join(flags).encode())
    return h.hexdigest()


def compile_command(compiler: str, sources: Sequence[str | Path], out: str | Path,
                    flags: Sequence[str]) -> list[str]:
    """The compiler's argument list: flags, ``-I`` the firmware folder, sources, ``-o out``."""
    return [compiler, *flags, f"-I{FIRMWARE_DIR}", *map(str, sources), "-o", str(out)]


def _run(cmd: list[str]) -> None:
    res = subprocess.run(cmd, capture_output=True, text=True)
    if res.returncode != 0:
        raise FirmwareBuildError(f"firmware build failed ({' '.join(cmd)}):\n"
                                 f"{res.stdout}{res.stderr}".rstrip())


def build_shared_library(defines: Sequence[str] = (), *, compiler: str | None = None,
                         extra_flags: Sequence[str] = (), cache: str | Path | None = None,
                         sources: Sequence[str | Path] | None = None) -> Path:
    """The firmware as a shared library, from the cache or compiled now.

    Parameters
    ----------
    defines : sequence of str
        ``-D`` flags (:func:`capacity_defines`).
    compiler : str, optional
        Compiler name or path (default ``$CC``, else ``cc``).
    extra_flags : sequence of str
        Appended to the flags (and to the key).
    cache : path, optional
        Cache folder (default :func:`cache_dir`).
    sources : sequence of path, optional
        Compile these instead of the firmware's :data:`SOURCES` (a test harness that
        ``#include``-s ``dptbd_track.c``); part of the key.

    Returns
    -------
    pathlib.Path
        ``<cache>/libdptbd_track-<key>.so``.
    """
    cc = find_compiler(compiler)
    flags = [*WARNING_FLAGS, *OPT_FLAGS, "-fPIC", "-shared", *defines, *extra_flags]
    folder = Path(cache) if cache is not None else cache_dir()
    own = [FIRMWARE_DIR / s for s in SOURCES] if sources is None else [Path(p) for p in sources]
    out = folder / f"libdptbd_track-{build_key(cc, flags, own if sources else ())[:32]}.so"
    if out.is_file():
        return out
    folder.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=".build-", suffix=".so", dir=folder)
    os.close(fd)
    try:
        _run(compile_command(cc, own, tmp, flags))
        os.replace(tmp, out)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
    return out


def build_executable(sources: Sequence[str | Path], out: str | Path, *,
                     defines: Sequence[str] = (), compiler: str | None = None,
                     extra_flags: Sequence[str] = ()) -> Path:
    """Compile ``sources`` together with the firmware into the program ``out`` (not cached),
    with :data:`WARNING_FLAGS`, :data:`OPT_FLAGS`, ``defines`` and ``extra_flags``
    (e.g. ``-fsanitize=address,undefined``)."""
    cc = find_compiler(compiler)
    flags = [*WARNING_FLAGS, *OPT_FLAGS, *defines, *extra_flags]
    _run(compile_command(cc, [*sources, *(FIRMWARE_DIR / s for s in SOURCES)], out, flags))
    return Path(out)
