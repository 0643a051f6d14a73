"""The gateware's source hash: the cache key of everything built from ``dptbd.hw``."""

import hashlib
import pathlib
import re

import dptbd.hw
from dptbd.hw.flow.source_hash import gateware_hash


def test_hash_covers_every_python_file_of_the_gateware():
    root = pathlib.Path(dptbd.hw.__file__).resolve().parent
    h = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        h.update(path.relative_to(root).as_posix().encode() + b"\0" + path.read_bytes() + b"\0")
    assert re.fullmatch(r"[0-9a-f]{24}", gateware_hash())
    assert gateware_hash() == h.hexdigest()[:24]
    assert (root / "flow" / "verilog.py") in set(root.rglob("*.py"))
