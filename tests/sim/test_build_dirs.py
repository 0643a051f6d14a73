"""What the Icarus and Verilator builds share: directory names, the lock, the design facts."""

from __future__ import annotations

import dataclasses
import fcntl
import threading

import pytest

from dptbd.config import DPConfig
from dptbd.weights import plain_weights
from dptbd.sim.build_dirs import CompiledDesign, config_name, locked


def test_build_directory_names_separate_parameter_sets():
    base = DPConfig(width=13, height=7)
    names = {config_name(c) for c in [
        base, base.replace(rounding="half_up"), DPConfig(width=13, height=7, radius=2),
        base.replace(weights=plain_weights(1)), base.replace(segment_frames=5)]}
    assert len(names) == 5
    assert config_name(base).startswith("13x7-k4-in8-e16-f8-r1-truncate-")
    assert config_name(base) == config_name(DPConfig(width=13, height=7))


def test_locked_creates_the_lock_file_and_excludes_a_second_holder(tmp_path):
    lock = tmp_path / "a" / "b.lock"
    with locked(lock):
        assert lock.exists()
        with open(lock) as fh, pytest.raises(BlockingIOError):
            fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)
    got = []
    with locked(lock):
        worker = threading.Thread(target=lambda: got.append(locked(lock).__enter__()))
        worker.start()
        worker.join(0.2)
        assert worker.is_alive() and got == []         # waits for the first holder
    worker.join(5)
    assert not worker.is_alive()


@dataclasses.dataclass(frozen=True)
class _Build(CompiledDesign):
    designs = {"dp": ("dptbd_dp", "states"), "segmenter": ("dptbd_seg", "candidates")}

    design: str
    manifest: dict


def test_compiled_design_reads_the_table_and_the_manifest():
    build = _Build("segmenter", {"latency": "17"})
    assert build.toplevel == "dptbd_seg" and build.latency == 17
