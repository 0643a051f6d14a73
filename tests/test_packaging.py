"""pyproject.toml ships every sub-package of ``dptbd``: a folder with an ``__init__.py`` that
the explicit ``packages`` list misses would be absent from the wheel (an installed ``dptbd``
once failed on every sub-command because ``dptbd.commands`` was missing)."""

from __future__ import annotations

import pathlib
import tomllib

ROOT = pathlib.Path(__file__).resolve().parents[1]


def _declared():
    tool = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    return set(tool["packages"]), tool["package-dir"]


def _folder(package: str, package_dir: dict) -> pathlib.Path:
    """The folder setuptools takes ``package`` from: the longest mapped prefix, then path = name."""
    parts = package.split(".")
    for cut in range(len(parts), 0, -1):
        prefix = ".".join(parts[:cut])
        if prefix in package_dir:
            return ROOT / package_dir[prefix] / pathlib.Path(*parts[cut:])
    return ROOT / pathlib.Path(*parts)


def _found(package_dir: dict) -> set[str]:
    """Every package below the mapped roots: folders holding ``__init__.py``."""
    found = set()
    for name, folder in package_dir.items():
        base = ROOT / folder
        for init in base.rglob("__init__.py"):
            rel = init.parent.relative_to(base)
            if "__pycache__" in rel.parts:
                continue
            found.add(".".join((name, *rel.parts)) if rel.parts else name)
    return found


def test_every_package_on_disk_is_declared():
    declared, package_dir = _declared()
    assert _found(package_dir) - declared == set()


def test_every_declared_package_exists():
    declared, package_dir = _declared()
    # a data-only package (dptbd.sim.harness: the C++ harness) has no __init__.py
    missing = sorted(p for p in declared if not _folder(p, package_dir).is_dir())
    assert missing == []
