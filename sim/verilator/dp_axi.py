"""Compiled RTL simulation of ``dptbd_dp`` built with ``--state-store axi``
(:class:`~dptbd.hw.axi_store.pipeline.DPPipelineAxi`) on Verilator, its state in the C++ AXI4
memory model ``sim/harness/axi4_memory.h`` (random latency per burst, random ready /
valid, every AXI4 rule it sees checked, writes applied with their response).

:func:`build` verilates the Verilog of an :class:`~dptbd.config.AxiStoreConfig` with that
harness into a cached executable (key: the Verilog text, the harness sources, the flags);
:func:`run` streams frames through it and scores the outputs against the golden model
(:func:`dptbd.sim.scoreboard.expected_words`). The C++ model takes data widths of 32, 64 and
128 bits; it answers the bursts whose address handshake falls in ``error_cycles`` with
``error_response`` (SLVERR or DECERR) with probability ``read_error`` / ``write_error``, and
``result`` then holds the error beats / responses it sent (``read_error_beats``,
``write_error_bursts``; of them with DECERR on the port: ``read_decerrs``,
``write_decerrs``) and the cycles the design's ``read_error`` / ``write_error`` pulsed
(``read_errors``, ``write_errors``).
At P = 2 or 4 pixels per clock (``DPCoreWide`` inside, store words of P states)
the input is beats of P pixels and the outputs, beats of P states, are scored per pixel
(:func:`dptbd.sim.rtl.check.beat_state_words`).
"""

from __future__ import annotations

import dataclasses
import hashlib
import os
import pathlib
import shutil
import subprocess
import tempfile

import numpy as np

from dptbd.config import AxiStoreConfig
from dptbd.sim.verilator.cache import (CXX_FLAGS, VERILATOR_FLAGS, check_tools, default_build_root,
                                       family_options)
from dptbd.sim.verilator import toolchain

__all__ = ["HARNESS", "AxiStoreBuild", "AxiStoreRun", "build", "run"]

HARNESS = pathlib.Path(__file__).resolve().parents[1] / "harness" / "dptbd_dp_axi_harness.cpp"
EXECUTABLE = "dptbd_sim"


@dataclasses.dataclass(frozen=True)
class AxiStoreBuild:
    """A compiled executable of one :class:`AxiStoreConfig`."""

    store: AxiStoreConfig
    directory: pathlib.Path
    executable: pathlib.Path
    manifest: dict


@dataclasses.dataclass
class AxiStoreRun:
    """What one run reported: ``result`` (``result.txt``), the outputs (one packed state
    per pixel, as a P = 1 design gives them), the acceptance cycles (one per input beat: per
    pixel at P = 1), and whether the outputs equal the golden model's."""

    result: dict
    outputs: np.ndarray
    accept_cycles: np.ndarray
    bit_exact: bool
    first_mismatch: int | None
    pixels_per_clock: int = 1

    @property
    def cycles_per_pixel(self) -> float:
        """Cycles from the first to the last accepted beat, over the pixels (1 / P when a
        beat of P pixels enters every cycle)."""
        a = self.accept_cycles
        return float(a[-1] - a[0] + 1) / (len(a) * self.pixels_per_clock)


def build(store: AxiStoreConfig, *, root: str | os.PathLike | None = None,
          family: str | None = None) -> AxiStoreBuild:
    """Verilate ``store``'s ``dptbd_dp`` with the AXI4 memory harness, or reuse the build;
    with ``family``, the DP core and the store with that FPGA family's options, its vendor
    cells verilated from their models (as :func:`~dptbd.sim.verilator.cache.build`)."""
    from dptbd.hw.flow.verilog import MODULE_NAME, generate_verilog
    from dptbd.hw.schedule import check_supported
    from dptbd.hw.wide import check_wide
    from dptbd.sim.cell_models import model_sources

    (check_supported if store.frame.pixels_per_clock == 1 else check_wide)(store.frame)
    options = None if family is None else family_options(store.frame, family)
    tools = check_tools()
    text, manifest = generate_verilog(store.frame, state_store=store, core_options=options)
    models = model_sources(text)
    defines = {"DPTBD_AXI_DATA_BITS": store.data_bits,
               "DPTBD_AXI_OUTSTANDING": store.outstanding,
               "DPTBD_FRAME_BYTES": store.frame_bytes}
    sources = [HARNESS, HARNESS.with_name("harness_io.h"), HARNESS.with_name("axi4_memory.h"),
               *models]
    key = hashlib.sha256(repr((text, [p.read_bytes() for p in sources], defines,
                               VERILATOR_FLAGS, CXX_FLAGS, tools)).encode()).hexdigest()[:16]
    root = pathlib.Path(root) if root is not None else default_build_root()
    directory = root / f"dp-axi-store{'' if family is None else '-' + family}-{key}"
    executable = directory / EXECUTABLE
    if not executable.exists():
        root.mkdir(parents=True, exist_ok=True)
        tmp = pathlib.Path(tempfile.mkdtemp(dir=root, prefix=".dp-axi-store-"))
        try:
            (tmp / f"{MODULE_NAME}.v").write_text(text)
            cflags = " ".join([*(f"-D{k}={v}" for k, v in defines.items()),
                               f"-I{HARNESS.parent}"])
            toolchain.step(["verilator", *VERILATOR_FLAGS, "--top-module", MODULE_NAME,
                            "-CFLAGS", cflags, "-o", EXECUTABLE, "--Mdir", "obj",
                            f"{MODULE_NAME}.v", *map(str, models), str(HARNESS)],
                           tmp, False, f"verilator ({MODULE_NAME}, AXI4 store)")
            toolchain.compile_executable(tmp, EXECUTABLE,
                                         toolchain.runtime_dir(root, tools, waves=False),
                                         False, f"C++ build ({MODULE_NAME}, AXI4 store)")
            if directory.exists():
                shutil.rmtree(directory)
            tmp.rename(directory)
        except BaseException:
            shutil.rmtree(tmp, ignore_errors=True)
            raise
    return AxiStoreBuild(store, directory, executable, manifest)


def run(sim: AxiStoreBuild, frames: np.ndarray, *, latency=(0, 0), write_latency=None,
        axi_ready: float = 1.0, axi_valid: float = 1.0, valid_gap: float = 0.0,
        ready_pause: float = 0.0, seed: int = 1, max_cycles: int | None = None,
        job_dir: str | os.PathLike | None = None, read_error: float = 0.0,
        write_error: float = 0.0, error_cycles: tuple[int, int] | None = None,
        error_response: str = "SLVERR") -> AxiStoreRun:
    """Stream ``frames`` (``(T, H, W)``) through ``sim``; score against the golden model.
    ``read_error`` / ``write_error``: the probability that a read / write burst whose address
    handshake falls in ``error_cycles`` (``[from, to)``; None: every cycle) is answered with
    ``error_response`` (one of :data:`~dptbd.sim.verilator.axi.ERROR_RESPONSES`)."""
    from dptbd.sim.scoreboard import expected_words
    from dptbd.sim.verilator.axi import ERROR_RESPONSES

    if error_response not in ERROR_RESPONSES:
        raise ValueError(f"error_response {error_response!r}: the responses are "
                         f"{', '.join(ERROR_RESPONSES)}")

    cfg = sim.store.frame
    words = _input_words(sim, frames)
    if max_cycles is None:
        slow = (1 + max(latency[1], (write_latency or latency)[1]) / 8) \
            / max(0.05, (1 - valid_gap) * (1 - ready_pause) * axi_ready * axi_valid)
        max_cycles = int(len(words) * 4 * slow) + 100_000
    with tempfile.TemporaryDirectory() as tmp:
        folder = pathlib.Path(job_dir or tmp)
        folder.mkdir(parents=True, exist_ok=True)
        words.astype("<u8").tofile(folder / "in.bin")      # (beats, words per beat) at P > 1
        wl = write_latency or latency
        (folder / "job.txt").write_text(
            f"words {len(words)}\nseed {seed}\nmax_cycles {max_cycles}\ndrain 64\n"
            f"valid_gap {valid_gap}\nready_pause {ready_pause}\n"
            f"latency {latency[0]} {latency[1]}\nwrite_latency {wl[0]} {wl[1]}\n"
            f"axi_ready {axi_ready}\naxi_valid {axi_valid}\nbase {sim.store.base_address}\n"
            f"segment_frames {cfg.segment_frames}\n"
            f"read_error {float(read_error)!r}\nwrite_error {float(write_error)!r}\n"
            f"error_response {error_response}\n"
            + ("" if error_cycles is None else
               f"error_cycles {int(error_cycles[0])} {int(error_cycles[1])}\n"))
        subprocess.run([str(sim.executable), str(folder)], check=True)
        result = {}
        for line in (folder / "result.txt").read_text().splitlines():
            key, _, value = line.partition(" ")
            result[key] = value if key in ("status", "first_violation") else float(value)
        outputs = _pixel_states(sim, np.fromfile(folder / "out.bin", dtype="<u8"))
        accepted = np.fromfile(folder / "accept_cycles.bin", dtype="<u8")
    expected = np.asarray(expected_words(cfg, frames), dtype=np.uint64).reshape(-1)
    n = min(len(outputs), len(expected))
    diff = np.flatnonzero(outputs[:n] != expected[:n])
    first = int(diff[0]) if len(diff) else (None if len(outputs) == len(expected) else n)
    return AxiStoreRun(result, outputs, accepted, first is None, first, cfg.pixels_per_clock)


def _payload_words(sim: AxiStoreBuild, stream: str) -> int:
    """uint64 words per ``stream`` payload in the harness's files (1 up to 64 bits)."""
    widths = {port["name"]: port["width"] for port in sim.manifest["ports"]}
    return max(1, -(-widths[f"{stream}__payload"] // 64))


def _input_words(sim: AxiStoreBuild, frames: np.ndarray) -> np.ndarray:
    """The ``pixels`` payloads of ``frames``: one uint64 per pixel at P = 1, rows of
    uint64 words per beat of P pixels at P > 1."""
    from dptbd.sim.stimulus import pack_pixels

    cfg = sim.store.frame
    p = cfg.pixels_per_clock
    if p == 1:
        return np.asarray(pack_pixels(cfg, frames), dtype=np.uint64)
    from dptbd.hw.wide import pack_beat
    from dptbd.sim.verilator import beat_words

    flat = np.asarray(frames).reshape(len(frames), -1)
    values = [pack_beat(cfg, frame[i:i + p], i == 0) for frame in flat
              for i in range(0, frame.size, p)]
    return beat_words(values, _payload_words(sim, "pixels"))


def _pixel_states(sim: AxiStoreBuild, words: np.ndarray) -> np.ndarray:
    """out.bin's words as one packed state per pixel (beats split at P > 1)."""
    cfg = sim.store.frame
    if cfg.pixels_per_clock == 1:
        return words
    from dptbd.sim.rtl.check import beat_state_words

    per_beat = _payload_words(sim, "states")
    rows = words.reshape(-1, per_beat) if per_beat > 1 else words
    return np.asarray(beat_state_words(cfg, rows), dtype=np.uint64).reshape(-1)
