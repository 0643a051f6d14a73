"""Output folders and files that never overwrite a user's data and are never left half-written.

Every job that writes a folder (``dptbd run``, ``dptbd compare``, ``dptbd detectors``) goes
through :func:`staged_folder`: the files are written into a temporary folder beside the
target, which is renamed into place only when every file is written. An existing folder is
replaced only with ``--force`` and only when it carries the job's own marker file (the JSON
summary the same job writes, whose ``tool`` field names the job): a folder the user made is
never deleted.

Every JSON file a job writes is strict JSON (RFC 8259, which has no NaN or infinity) through
:func:`json_text`: a non-finite number is written as ``null``, whose meaning each job's
document gives per field (no interval, not reached, ...).
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import pathlib
import shutil
import tempfile
from typing import Any, Iterator

import numpy as np

__all__ = ["check_output_folder", "staged_folder", "written_by", "check_output_file",
           "check_new_files", "check_still_new", "write_new_text", "jsonable", "json_text"]


def written_by(path: pathlib.Path, marker: str, tool: str) -> bool:
    """True when ``path/marker`` is JSON whose ``tool`` field is ``tool``."""
    try:
        return json.loads((path / marker).read_text()).get("tool") == tool
    except (OSError, ValueError, AttributeError):
        return False


def check_output_folder(out: pathlib.Path, force: bool, *, marker: str, tool: str,
                        option: str = "--out") -> pathlib.Path:
    """Refuse, before any work, an output folder that cannot or must not be written.

    Parameters
    ----------
    out : pathlib.Path
        The folder to write.
    force : bool
        Whether the user passed ``--force`` (replace an earlier run's folder).
    marker, tool : str
        The job's marker file inside its folder and the ``tool`` it records, e.g.
        ``"summary.json"`` and ``"dptbd run"``.
    option : str
        The option that named the folder, for the messages.

    Returns
    -------
    pathlib.Path
        ``out`` with ``~`` expanded.
    """
    out = out.expanduser()
    resolved = out.resolve()
    job = tool if tool.endswith(" run") else f"{tool} run"  # "dptbd run", "dptbd compare run"
    if not resolved.parent.is_dir():
        raise FileNotFoundError(f"{option} {out}: the folder {out.parent} does not exist")
    cwd = pathlib.Path.cwd().resolve()
    if resolved == cwd or resolved in cwd.parents:
        raise ValueError(f"{option} {out} is the current folder or one of its parents; give a "
                         f"new folder")
    if out.exists() or out.is_symlink():
        if not force:
            raise FileExistsError(f"{option} {out} exists; pass --force to replace it, or "
                                  f"choose another folder")
        if out.is_symlink() or not out.is_dir():
            raise FileExistsError(f"{option} {out} exists and is not a folder; --force replaces "
                                  f"only the folder of an earlier {job}")
        if any(out.iterdir()) and not written_by(out, marker, tool):
            raise FileExistsError(f"{option} {out} is not the folder of an earlier {job} "
                                  f"(no {marker} from it); --force will not replace it")
    return out


@contextlib.contextmanager
def staged_folder(out: pathlib.Path, force: bool, *, marker: str, tool: str,
                  option: str = "--out") -> Iterator[pathlib.Path]:
    """A temporary folder beside ``out``, renamed to ``out`` when the block succeeds.

    The checks of :func:`check_output_folder` run on entry and again just before the rename
    (the folder may have appeared meanwhile). On any error the temporary folder is removed
    and ``out`` is left as it was.
    """
    out = check_output_folder(out, force, marker=marker, tool=tool, option=option)
    tmp = pathlib.Path(tempfile.mkdtemp(prefix=f".{out.name}.partial-",
                                        dir=out.resolve().parent))
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o777 & ~umask)  # mkdtemp makes it private (0700)
    try:
        yield tmp
        check_output_folder(out, force, marker=marker, tool=tool, option=option)
        if out.exists():
            old = out.resolve().parent / f".{out.name}.old-{os.getpid()}"
            os.rename(out, old)
            os.rename(tmp, out)
            shutil.rmtree(old, ignore_errors=True)
        else:
            os.rename(tmp, out)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise


def check_output_file(path: pathlib.Path | None, option: str, force: bool,
                      suffix: str) -> None:
    """Refuse, before any work, an output file with the wrong suffix, in a missing folder,
    or that exists without ``--force``. ``None`` (option not given) passes."""
    if path is None:
        return
    if path.suffix.lower() != suffix:
        raise ValueError(f"{option} {path} must end in {suffix}")
    if path.is_dir():
        raise FileExistsError(f"{option} {path} is a folder")
    if not path.parent.resolve().is_dir():
        raise FileNotFoundError(f"{option} {path}: the folder {path.parent} does not exist")
    if (path.exists() or path.is_symlink()) and not force:
        raise FileExistsError(f"{option} {path} exists; pass --force to overwrite it")


def check_new_files(paths: list[pathlib.Path], force: bool) -> None:
    """Refuse, before any work, a set of files written together (a Verilog file and its
    manifest, a package) when any of them exists and ``force`` is off; the message names
    every one that exists."""
    existing = [str(p) for p in paths if p.exists() or p.is_symlink()]
    if existing and not force:
        names = existing[0] if len(existing) == 1 else \
            f"{', '.join(existing[:-1])} and {existing[-1]}"
        raise FileExistsError(f"{names} {'exists' if len(existing) == 1 else 'exist'}; pass "
                              f"--force to overwrite")


def check_still_new(path: pathlib.Path, option: str, force: bool) -> None:
    """Just before writing a file that :func:`check_output_file` passed: refuse it if it
    appeared during the run and ``force`` is off (for writers that cannot open with ``"x"``,
    such as a figure's)."""
    if (path.exists() or path.is_symlink()) and not force:
        raise FileExistsError(f"{option} {path} appeared during the run; not overwritten")


def write_new_text(path: pathlib.Path, text: str, force: bool) -> None:
    """Write ``text`` to ``path``; without ``force`` never replace a file, even one that
    appeared after the checks (``open(..., "x")``)."""
    with open(path, "w" if force else "x") as fh:
        fh.write(text)


def jsonable(value: Any) -> Any:
    """``value`` as plain JSON data: dicts (keys that JSON cannot key by, e.g. tuples, as
    their ``str``), lists for tuples and arrays, Python numbers for numpy scalars, ``str`` for
    paths, and ``None`` for every non-finite float (NaN, +-inf)."""
    if isinstance(value, dict):
        return {(k if k is None or isinstance(k, (str, int, float, bool)) else str(k)):
                jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return jsonable(value.tolist())
    if isinstance(value, np.generic):
        return jsonable(value.item())
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, pathlib.PurePath):
        return str(value)
    return value


def json_text(value: Any, **dumps: Any) -> str:
    """Strict JSON of ``value`` (:func:`jsonable`: non-finite numbers as ``null``);
    ``dumps`` are :func:`json.dumps`'s options (``indent``, ``sort_keys``, ``default``).
    Written with ``allow_nan=False``: a non-finite number that reaches the encoder anyway
    (from a ``default`` hook) raises ``ValueError`` instead of writing ``NaN``."""
    return json.dumps(jsonable(value), allow_nan=False, **dumps)
