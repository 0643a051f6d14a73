"""One run of the AXI harness (``sim/harness/dptbd_axi_harness.cpp``) on a ``design="axi"``
build: the input beats as the harness's words (:func:`beat_words`, at P = 2 or 4
:func:`wide_beat_words`), the job file with its operations, stalls and AXI4 memory model
settings (:data:`MEMORY_KEYS`), and what the run reported (:class:`AxiRun`).
"""

from __future__ import annotations

import dataclasses
import pathlib
import subprocess
import tempfile

import numpy as np

from dptbd.sim.axi.stimulus import Beats
from dptbd.sim.verilator import _check_probability, cycle_budget
from dptbd.sim.verilator.cache import VerilatorBuild

__all__ = ["ERROR_RESPONSES", "MEMORY_KEYS", "AxiRun", "beat_words", "wide_beat_words",
           "settle_cycles", "run_axi"]

#: The responses the memory model's errors can carry (its ``error_response``).
ERROR_RESPONSES = ("SLVERR", "DECERR")

#: The AXI4 memory model's settings (``sim/harness/axi4_memory.h``) ``run_axi`` takes in
#: ``memory``: two-number ranges (latency, write_latency: cycles; error_cycles: [from, to)),
#: probabilities (axi_ready, axi_valid, read_error, write_error), the base address, the span
#: and the errors' response (error_response: one of :data:`ERROR_RESPONSES`).
MEMORY_KEYS = {"latency": 2, "write_latency": 2, "error_cycles": 2, "axi_ready": 1,
               "axi_valid": 1, "read_error": 1, "write_error": 1, "base": 1, "span": 1,
               "error_response": 1}


@dataclasses.dataclass(frozen=True)
class AxiRun:
    """What one run of the AXI harness reported."""

    status: str                  # "done" or "timeout"
    cycles: int
    out_words: np.ndarray        # uint64 m_axis_cand tdata of every transfer
    out_flags: np.ndarray        # uint64 tuser[0] | tlast << 1
    out_cycles: np.ndarray
    accept_cycles: np.ndarray    # uint64 cycle each beat was accepted (2**64-1: never)
    op_data: np.ndarray          # int64 per w/r operation: read data (0 for writes)
    op_resp: np.ndarray          # int64 per w/r operation: BRESP / RRESP
    counters: dict               # accepted, outputs, stalled_input_cycles, irq_rises, …
    sim_seconds: float
    op_cycles: np.ndarray = None  # int64 per w/r/m/b operation: the cycle it completed
    irq_cycles: np.ndarray = None  # uint64 cycle of every change of irq: rises, falls in turn
    first_violation: str | None = None  # the memory model's first AXI4 rule broken (store builds)
    bursts: np.ndarray = None    # store builds: (n, 3) int64 cycle, is_write, address per burst

    @property
    def cycles_per_second(self) -> float:
        return self.cycles / self.sim_seconds if self.sim_seconds > 0 else float("nan")


def beat_words(beats: Beats) -> np.ndarray:
    """The harness's input words: ``tdata | tuser[0] << 32 | tlast << 33``."""
    return (np.asarray(beats.pixel, dtype=np.uint64)
            | np.asarray(beats.first, dtype=np.uint64) << np.uint64(32)
            | np.asarray(beats.last, dtype=np.uint64) << np.uint64(33))


def wide_beat_words(cfg, beats: Beats) -> np.ndarray:
    """The harness's input words at P = 2 or 4 pixels per clock: every P consecutive pixels
    of ``beats`` (one pixel each, as at P = 1) in one ``s_axis_video`` beat, pixel k in
    byte lane k of ``tdata`` (:func:`~dptbd.hw.wide.axis_video.lane_bits`), ``tuser[0]``
    of its first pixel, ``tlast`` of its last. Refused: a pixel count that is not a
    multiple of P, or ``tuser[0]`` / ``tlast`` inside a beat."""
    from dptbd.hw.wide.axis_video import lane_bits

    p = cfg.pixels_per_clock
    if len(beats) % p:
        raise ValueError(f"{len(beats)} pixels do not fill beats of pixels_per_clock={p}")
    pixel = np.asarray(beats.pixel, dtype=np.uint64).reshape(-1, p)
    first = np.asarray(beats.first, dtype=bool).reshape(-1, p)
    last = np.asarray(beats.last, dtype=bool).reshape(-1, p)
    if first[:, 1:].any() or last[:, :-1].any():
        raise ValueError(f"at pixels_per_clock={p} tuser[0] (start of frame) may be set on "
                         f"the first pixel of a beat of {p} and tlast (end of line) on its "
                         f"last only")
    lane = lane_bits(cfg)
    tdata = np.zeros(len(pixel), dtype=np.uint64)
    for k in range(p):
        tdata |= pixel[:, k] << np.uint64(lane * k)
    return beat_words(Beats(tdata, first[:, 0], last[:, -1]))


def _beat_index(p: int, index: int, kind: str) -> int:
    """The beat before which an operation given before pixel ``index`` is performed."""
    if index % p:
        raise ValueError(f"operation {kind!r} before pixel {index}: at pixels_per_clock={p} "
                         f"operations come between beats, before a pixel index that is a "
                         f"multiple of {p}")
    return index // p


def settle_cycles(sim: VerilatorBuild, ready_pause: float) -> int:
    """Idle cycles after the last beat before reading counters or a soft reset: the latency
    plus two histogram scans, stretched by the output back-pressure."""
    scan = int(sim.manifest.get("scan_cycles", 0))
    return int((sim.latency + 2 * scan + 64) * (1 + 3 * ready_pause))


def run_axi(sim: VerilatorBuild, beats: Beats, ops: list[tuple], *, valid_gap: float = 0.0,
            ready_pause: float = 0.0, seed: int = 1, drain: int | None = None,
            max_cycles: int | None = None, coverage=None, repeat: int = 1,
            memory: dict | None = None) -> AxiRun:
    """Stream ``beats`` through a ``design="axi"`` build with the operations ``ops``
    (``(beat index, "w" | "r" | "i" | "m" | "b", address or idle cycles, data)``, performed
    in order before that beat is offered; ``"m"`` is a write with ``wstrb`` = data >> 32,
    ``"b"`` reads the address until its bit 0 is 0, ``"a"`` holds ``aresetn`` low for the
    given cycles, ``"p"`` loads counter ``address``
    (:func:`~dptbd.sim.mutation.presets.preset_counters`' index) with ``data`` in one cycle,
    in mutant builds only; see the harness's header); ``coverage``: write the run's coverage
    data to that file (a build with ``coverage=True``); ``repeat``: offer ``beats`` that many times
    over (``len(beats) * repeat`` beats; operation indices count them all; long runs:
    ``accept_cycles`` is then empty); ``memory``: the AXI4 memory model's settings
    (:data:`MEMORY_KEYS`; a build with ``state_store`` only, whose base address the model
    takes by default)."""
    if sim.design != "axi":
        raise ValueError(f"run_axi needs a build of design 'axi', got {sim.design!r}")
    if coverage is not None and not sim.coverage:
        raise ValueError("coverage needs a build made with coverage=True")
    valid_gap = _check_probability("valid_gap", valid_gap)
    ready_pause = _check_probability("ready_pause", ready_pause)
    if isinstance(repeat, bool) or not isinstance(repeat, int) or repeat < 1:
        raise ValueError(f"repeat must be an integer of at least 1, got {repeat!r}")
    store = getattr(sim, "state_store", None)
    if memory is not None and store is None:
        raise ValueError("memory applies to a build with state_store only")
    memory = dict(memory or {})
    for key in memory:
        if key not in MEMORY_KEYS:
            raise ValueError(f"memory key {key!r}: the keys are {', '.join(MEMORY_KEYS)}")
    if memory.get("error_response", "SLVERR") not in ERROR_RESPONSES:
        raise ValueError(f"memory error_response {memory['error_response']!r}: the "
                         f"responses are {', '.join(ERROR_RESPONSES)}")
    if store is not None:
        memory.setdefault("base", store.base_address)
    p = sim.cfg.pixels_per_clock
    if p > 1:                           # P pixels per beat: indices of pixels, as at P = 1
        words = wide_beat_words(sim.cfg, beats)
        ops = [(_beat_index(p, index, kind), kind, *rest) for index, kind, *rest in ops]
    else:
        words = beat_words(beats)
    total = len(words) * repeat
    for index, kind, *_ in ops:
        if not 0 <= index <= total or kind not in ("w", "r", "i", "m", "b", "a", "p"):
            raise ValueError(f"operation {kind!r} before beat {index}: kinds are w, r, i, m, "
                             f"b, a, p and beats 0 … {total}")
        if kind == "p" and not sim.mutant:
            raise ValueError("operation 'p' (a counter preset) needs a mutant build")
    slow, rate = 0, 1.0                 # the memory's latency and handshake rate
    if store is not None:
        slow = max(memory.get("latency", (0, 0))[1],
                   memory.get("write_latency", memory.get("latency", (0, 0)))[1])
        rate = max(0.05, float(memory.get("axi_ready", 1.0)) * float(memory.get("axi_valid", 1.0)))
    if drain is None:                   # with a store: its writes answered too
        drain = settle_cycles(sim, 0.0) + (0 if store is None else int(
            store.outstanding * (slow + 2 * store.burst_beats) / rate))
    if max_cycles is None:
        max_cycles = cycle_budget(total, valid_gap, ready_pause,
                                  drain + sum(o[2] if o[1] == "i" else 8 for o in ops))
        max_cycles = int(max_cycles * (1 + slow / 8) / rate)
    with tempfile.TemporaryDirectory(prefix="dptbd-verilator-axi-") as job_dir:
        job = pathlib.Path(job_dir)
        np.ascontiguousarray(words, dtype="<u8").tofile(job / "in.bin")
        lines = [f"words {total}", f"valid_gap {valid_gap!r}",
                 f"ready_pause {ready_pause!r}", f"seed {int(seed)}",
                 f"max_cycles {int(max_cycles)}", f"drain {int(drain)}"]
        lines += [f"op {int(i)} {k} {int(a)} {int(d)}" for i, k, a, d in ops]
        if repeat > 1:
            lines.append(f"period {len(words)}")
        for key, value in memory.items():
            if key == "error_response":
                lines.append(f"{key} {value}")
                continue
            values = value if MEMORY_KEYS[key] == 2 else (value,)
            lines.append(f"{key} " + " ".join(str(int(v) if key in ("latency", "write_latency",
                                                                    "error_cycles", "base",
                                                                    "span")
                                                  else float(v)) for v in values))
        if coverage is not None:
            lines.append(f"coverage {pathlib.Path(coverage).resolve()}")
        (job / "job.txt").write_text("\n".join(lines) + "\n")
        out = subprocess.run([str(sim.executable), str(job)], capture_output=True, text=True,
                             check=False)
        if out.returncode != 0:
            raise RuntimeError(f"{sim.executable} failed (exit {out.returncode}): "
                               f"{(out.stderr or out.stdout).strip()[-2000:]}")
        result = dict(line.partition(" ")[::2]
                      for line in (job / "result.txt").read_text().splitlines())
        violation = result.pop("first_violation", None)
        done = np.fromfile(job / "ops.bin", dtype="<u8")
        accepts = np.fromfile(job / "accept_cycles.bin", dtype="<u8")
        if p > 1:                       # per pixel: a beat's P pixels share its cycle
            accepts = np.repeat(accepts, p)
            result["accepted"] = str(int(result["accepted"]) * p)
        return AxiRun(
            status=result.pop("status"), cycles=int(result.pop("cycles")),
            out_words=np.fromfile(job / "out.bin", dtype="<u8"),
            out_flags=np.fromfile(job / "out_flags.bin", dtype="<u8"),
            out_cycles=np.fromfile(job / "out_cycles.bin", dtype="<u8"),
            accept_cycles=accepts,
            op_data=(done & np.uint64(0xFFFFFFFF)).astype(np.int64),
            op_resp=((done >> np.uint64(32)) & np.uint64(3)).astype(np.int64),
            op_cycles=(done >> np.uint64(34)).astype(np.int64),
            irq_cycles=np.fromfile(job / "irq_cycles.bin", dtype="<u8"),
            counters={k: int(v) for k, v in result.items() if k != "seconds"},
            sim_seconds=float(result["seconds"]),
            first_violation=None if violation in (None, "none") else violation,
            bursts=_bursts(job / "bursts.bin"))


def _bursts(path: pathlib.Path) -> np.ndarray | None:
    """The memory model's log (``bursts.bin``) as ``(n, 3)``: cycle, is_write, address."""
    if not path.exists():
        return None
    raw = np.fromfile(path, dtype="<u8").reshape(-1, 2).astype(np.int64)
    return np.stack([raw[:, 0] >> 1, raw[:, 0] & 1, raw[:, 1]], axis=1)
