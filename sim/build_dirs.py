"""What the Icarus builds (:mod:`dptbd.sim.icarus`) and the Verilator builds
(:mod:`dptbd.sim.verilator.cache`) share: the directory name of a parameter set, a lock
that serialises concurrent builds of one directory (pytest-xdist), and the facts a build
reads from its design table and manifest (:class:`CompiledDesign`).
"""

from __future__ import annotations

import contextlib
import fcntl
import hashlib
import json
import pathlib
from typing import ClassVar, Iterator

from dptbd.config import DPConfig

__all__ = ["config_name", "locked", "CompiledDesign"]


def config_name(cfg: DPConfig) -> str:
    """Readable, unique directory name of a parameter set.

    ``<W>x<H>-k<K>-in<B_in>-e<B_E>-f<F>-r<r>-<rounding>-<hash>``; the hash (8 hex digits of
    SHA-256 over every field, weights included) separates parameter sets that differ only
    in their LUT.
    """
    digest = hashlib.sha256(json.dumps(cfg.to_mapping(), sort_keys=True).encode())
    return (f"{cfg.width}x{cfg.height}-k{cfg.segment_frames}-in{cfg.input_bits}"
            f"-e{cfg.energy_bits}-f{cfg.weight_frac_bits}-r{cfg.radius}-{cfg.rounding}"
            f"-{digest.hexdigest()[:8]}")


@contextlib.contextmanager
def locked(lock_file: pathlib.Path) -> Iterator[None]:
    """Hold an exclusive ``flock`` on ``lock_file`` (created, with its folder)."""
    lock_file.parent.mkdir(parents=True, exist_ok=True)
    with open(lock_file, "w") as fh:
        fcntl.flock(fh, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(fh, fcntl.LOCK_UN)


class CompiledDesign:
    """Mixin of a build dataclass with fields ``design`` (a key of :attr:`designs`) and
    ``manifest`` (the generated Verilog's manifest)."""

    #: design name -> tuple whose first item is the Verilog module name
    designs: ClassVar[dict[str, tuple]] = {}

    @property
    def latency(self) -> int:
        """Cycles from a pixel's acceptance to its result (the manifest's ``latency``)."""
        return int(self.manifest["latency"])

    @property
    def toplevel(self) -> str:
        """The Verilog module name."""
        return self.designs[self.design][0]
