"""A hash of the gateware's source, for caches of anything built from it."""

from __future__ import annotations

import hashlib
import pathlib

__all__ = ["gateware_hash"]


def gateware_hash() -> str:
    """SHA-256 (24 hex digits) of the gateware's source: every ``.py`` file of ``dptbd.hw``.

    A synthesis result (:mod:`dptbd.evaluation.sweep`) or a compiled simulation
    (:mod:`dptbd.sim.verilator.cache`) cached under a key that includes it is rebuilt whenever
    the gateware changes.
    """
    root = pathlib.Path(__file__).resolve().parents[1]  # hw/, the components and their flow
    h = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        h.update(path.relative_to(root).as_posix().encode() + b"\0" + path.read_bytes() + b"\0")
    return h.hexdigest()[:24]
