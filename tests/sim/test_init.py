"""``sim/__init__.py``: its map of modules lists every module of ``dptbd.sim``, one line
each, and nothing that is not one."""

import pathlib
import re

import dptbd.sim


def test_the_module_map_lists_every_module_once():
    folder = pathlib.Path(dptbd.sim.__file__).parent
    modules = sorted(p.stem for p in folder.glob("*.py") if p.stem != "__init__")
    listed = re.findall(r"^- ``(\w+)``: ", dptbd.sim.__doc__, re.M)
    assert sorted(listed) == modules
    assert len(listed) == len(set(listed))


def test_the_sub_packages_paragraph_names_every_sub_package():
    folder = pathlib.Path(dptbd.sim.__file__).parent
    packages = sorted(p.parent.name for p in folder.glob("*/__init__.py"))
    paragraph = dptbd.sim.__doc__.split("Sub-packages: ", 1)[1].split("\n\n", 1)[0]
    named = set(re.findall(r"``(\w+)`` \(", paragraph))
    assert [p for p in packages if p not in named] == []
