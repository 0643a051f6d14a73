"""Compiled RTL simulation: a whole input stream run through a Verilator build in one call.

:func:`run` writes the input words and the stimulus (seeded valid gaps and ready
back-pressure, resets at given cycles, LUT writes before given words, DPCore's external
store at power-up) into a job directory, runs the executable once, and returns every
output transfer with its cycle and the cycle each input word was accepted (:class:`RawRun`).
Nothing runs in Python per cycle.

The executables come from the build cache :mod:`dptbd.sim.verilator.cache`; its public
names (:func:`build`, :func:`check_tools`, :class:`ToolMissingError`, :class:`VerilatorBuild`,
:data:`DESIGNS`, …) are re-exported here, so ``from dptbd.sim import verilator;
verilator.build(...)`` keeps working.

Use Debian's ``verilator`` (5.006; ``scripts/setup.sh`` installs it). X-propagation is not
modelled (Verilator is 2-state): the 4-state checks stay on Icarus (``docs/gateware.md``,
"Which simulator checks what").
"""

from __future__ import annotations

import dataclasses
import os
import pathlib
import subprocess
import tempfile
import time
from typing import Iterable

import numpy as np

from dptbd.sim.verilator.cache import (
    CXX_FLAGS,
    DESIGNS,
    EXECUTABLE,
    HARNESS,
    STAMP,
    VERILATOR_FLAGS,
    ToolMissingError,
    VerilatorBuild,
    build,
    check_tools,
    default_build_root,
)

__all__ = [
    "DESIGNS",
    "VERILATOR_FLAGS",
    "CXX_FLAGS",
    "HARNESS",
    "EXECUTABLE",
    "STAMP",
    "ToolMissingError",
    "VerilatorBuild",
    "RawRun",
    "default_build_root",
    "check_tools",
    "build",
    "cycle_budget",
    "payload_words",
    "beat_words",
    "beat_values",
    "run",
]


@dataclasses.dataclass(frozen=True)
class RawRun:
    """What one run of the executable reported."""

    status: str                 # "done" or "timeout"
    cycles: int                 # cycles simulated
    out_words: np.ndarray       # uint64 payload of every output transfer
    out_cycles: np.ndarray      # uint64 cycle of each output transfer
    accept_cycles: np.ndarray   # uint64 cycle each input word was accepted (2**64-1: never)
    counters: dict              # lut_writes, stalled_input_cycles, paused_output_cycles, ...
    sim_seconds: float          # the harness's cycle loop
    wall_seconds: float         # the whole process, file I/O included

    @property
    def cycles_per_second(self) -> float:
        return self.cycles / self.sim_seconds if self.sim_seconds > 0 else float("nan")


def _check_probability(name: str, value: float) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) \
            or not 0.0 <= float(value) < 1.0:
        raise ValueError(f"{name} must be a probability in [0, 1), got {value!r}")
    return float(value)


def payload_words(sim: VerilatorBuild, stream: str) -> int:
    """uint64 words per payload of ``stream`` (``"pixels"``, ``"states"``, …) in the
    harness's files: 1 up to 64 bits; ``ceil(bits / 64)`` for a wider one (a beat of P
    pixels or states, ``docs/gateware.md`` "P pixels per clock"), the low bits first, in
    ``words`` (one row per beat) and ``RawRun.out_words`` (likewise)."""
    if sim.cfg.pixels_per_clock == 1:       # every payload of a P = 1 design fits 64 bits
        return 1
    widths = {port["name"]: port["width"] for port in sim.manifest["ports"]}
    return max(1, -(-widths[f"{stream}__payload"] // 64))


def beat_words(values, per_beat: int) -> np.ndarray:
    """Python integers (payloads of any width) as ``(n, per_beat)`` uint64 words, low first
    (``per_beat`` 1: a 1-D array)."""
    mask = (1 << 64) - 1
    rows = [[(int(v) >> (64 * k)) & mask for k in range(per_beat)] for v in values]
    out = np.array(rows, dtype=np.uint64).reshape(len(rows), per_beat)
    return out[:, 0].copy() if per_beat == 1 else out


def beat_values(words: np.ndarray) -> list[int]:
    """The inverse of :func:`beat_words`: one Python integer per row (or per element of a
    1-D array)."""
    words = np.asarray(words, dtype=np.uint64)
    if words.ndim == 1:
        return [int(w) for w in words]
    return [sum(int(w) << (64 * k) for k, w in enumerate(row)) for row in words]


def cycle_budget(words: int, valid_gap: float, ready_pause: float, extra: int) -> int:
    """A generous cycle limit for ``words`` input words through the given pause densities."""
    return int((words + extra + 1000) / ((1.0 - valid_gap) * (1.0 - ready_pause)) * 3) + 10_000


def run(sim: VerilatorBuild, words: np.ndarray, *, valid_gap: float = 0.0,
        ready_pause: float = 0.0, seed: int = 1,
        resets: Iterable[tuple[int, int]] = (),
        lut_writes: Iterable[tuple[int, int, int]] = (),
        settings: Iterable[tuple[int, int, int, int]] = (),
        store_init: str = "zero", drain: int | None = None, max_cycles: int | None = None,
        trace: str | os.PathLike | None = None,
        coverage: str | os.PathLike | None = None) -> RawRun:
    """Stream ``words`` (packed ``pixels`` payloads) through a build.

    Parameters
    ----------
    sim : VerilatorBuild
    words : array of unsigned integers
        Input payloads in order (:func:`dptbd.sim.stimulus.pixel_words`).
    valid_gap, ready_pause : float
        Probabilities in [0, 1) of an idle input cycle (drawn before a word is offered;
        ``valid`` then stays high until the transfer) and of ``ready`` low on the output.
    seed : int
        Seeds both pause generators and the external store's power-up garbage.
    resets : iterable of (cycle, hold)
        ``rst`` high in cycles ``cycle … cycle + hold - 1`` (cycle ≥ 2: the power-up reset
        holds cycles 0 and 1).
    lut_writes : iterable of (word index, address, code)
        Written through the LUT port, one per cycle, just before that input word is offered.
    settings : iterable of (word index, K, n, s)
        From that input word on, the run-time settings ports carry these values (``n`` and
        ``s`` only exist on ``dptbd_seg``). Before the first, and always from word 0 unless
        given, the build values ``(cfg.segment_frames, cfg.n_candidates, cfg.bin_shift)``.
    store_init : str
        ``"zero"`` or ``"random"``: DPCore's external store at power-up (``design="core"``).
    drain : int, optional
        The run ends once every word is in and the output has been idle this many cycles
        (default: latency + the segmenter's scan + 64, enough to see any extra word).
    max_cycles : int, optional
        Give up after this many cycles (default :func:`cycle_budget`).
    trace : path, optional
        Write an FST waveform (a build with ``waves=True``).
    coverage : path, optional
        Write the run's coverage data there (a build with ``coverage=True``).
    """
    if sim.design == "axi":
        raise ValueError("the 'axi' build has its own harness: use "
                         "dptbd.sim.verilator.axi.run_axi")
    words = np.asarray(words)
    per_beat = payload_words(sim, "pixels")
    if per_beat > 1:        # a beat of P pixels wider than 64 bits: (beats, per_beat) words
        if words.ndim != 2 or words.shape[1] != per_beat \
                or (words.size and words.dtype.kind not in "iu"):
            raise ValueError(f"words must be a (beats, {per_beat}) integer array of uint64 "
                             f"words for this build's {per_beat * 64 - 63}..{per_beat * 64}-bit "
                             f"pixels payloads, got {words.dtype} {words.shape}")
    elif words.ndim != 1 or (words.size and words.dtype.kind not in "iu"):
        raise ValueError(f"words must be a 1-D integer array, got {words.dtype} {words.shape}")
    valid_gap = _check_probability("valid_gap", valid_gap)
    ready_pause = _check_probability("ready_pause", ready_pause)
    if store_init not in ("zero", "random"):
        raise ValueError(f"store_init must be 'zero' or 'random', got {store_init!r}")
    if trace is not None and not sim.waves:
        raise ValueError("trace needs a build made with waves=True")
    if coverage is not None and not sim.coverage:
        raise ValueError("coverage needs a build made with coverage=True")
    resets = sorted((int(c), int(h)) for c, h in resets)
    # stable by word index only: writes before one word keep their order (the last write
    # to an address wins, as lut_changes given for one word in check_stream)
    lut_writes = sorted(((int(i), int(a), int(d)) for i, a, d in lut_writes),
                        key=lambda w: w[0])
    cfg = sim.cfg
    settings = sorted([(0, cfg.segment_frames, cfg.n_candidates, cfg.bin_shift)]
                      + [tuple(int(v) for v in w) for w in settings], key=lambda w: w[0])
    if drain is None:
        scan = int(sim.manifest.get("scan_cycles", 0))
        drain = sim.latency + 2 * scan + 64
    if max_cycles is None:
        max_cycles = cycle_budget(len(words), valid_gap, ready_pause,
                                  drain + len(lut_writes) + sum(h for _, h in resets))
    for cycle, hold in resets:
        if not 2 <= cycle < max_cycles or hold < 1:
            raise ValueError(f"reset at cycle {cycle} for {hold} cycles is outside the run: "
                             f"cycles 2 … {max_cycles - 1}, hold >= 1")
    for index, _, _ in lut_writes:
        if not 0 <= index <= len(words):
            raise ValueError(f"LUT write before word {index}: the stream has {len(words)} words")
    for index, *_ in settings:
        if not 0 <= index <= len(words):
            raise ValueError(f"settings before word {index}: the stream has {len(words)} words")
    # rst is high in the union of the intervals: the harness takes one reset per start
    # cycle (a second reset starting in the same cycle would never fire: a timeout), and a
    # reset starting inside another must not cut that one short
    merged: list[list[int]] = []
    for cycle, hold in resets:
        if merged and cycle <= merged[-1][0] + merged[-1][1]:
            merged[-1][1] = max(merged[-1][1], cycle + hold - merged[-1][0])
        else:
            merged.append([cycle, hold])
    resets = [(c, h) for c, h in merged]
    with tempfile.TemporaryDirectory(prefix="dptbd-verilator-") as job_dir:
        job = pathlib.Path(job_dir)
        np.ascontiguousarray(words, dtype="<u8").tofile(job / "in.bin")
        lines = [f"words {len(words)}", f"valid_gap {valid_gap!r}",
                 f"ready_pause {ready_pause!r}", f"seed {int(seed)}",
                 f"max_cycles {int(max_cycles)}", f"drain {int(drain)}",
                 f"store_init {store_init}"]
        lines += [f"reset {c} {h}" for c, h in resets]
        lines += [f"lut {i} {a} {d}" for i, a, d in lut_writes]
        lines += [f"settings {i} {k} {n} {s}" for i, k, n, s in settings]
        if trace is not None:
            trace = pathlib.Path(trace).resolve()
            trace.parent.mkdir(parents=True, exist_ok=True)
            lines.append(f"trace {trace}")
        if coverage is not None:
            lines.append(f"coverage {pathlib.Path(coverage).resolve()}")
        (job / "job.txt").write_text("\n".join(lines) + "\n")
        start = time.perf_counter()
        out = subprocess.run([str(sim.executable), str(job)], capture_output=True, text=True,
                             check=False)
        wall = time.perf_counter() - start
        if out.returncode != 0:
            raise RuntimeError(f"{sim.executable} failed (exit {out.returncode}): "
                               f"{(out.stderr or out.stdout).strip()[-2000:]}")
        result = {}
        for line in (job / "result.txt").read_text().splitlines():
            k, _, v = line.partition(" ")
            result[k] = v
        out_words = np.fromfile(job / "out.bin", dtype="<u8")
        per_output = payload_words(sim, sim.output)
        if per_output > 1:
            out_words = out_words.reshape(-1, per_output)
        return RawRun(
            status=result.pop("status"), cycles=int(result.pop("cycles")),
            out_words=out_words,
            out_cycles=np.fromfile(job / "out_cycles.bin", dtype="<u8"),
            accept_cycles=np.fromfile(job / "accept_cycles.bin", dtype="<u8"),
            counters={k: float(v) if "." in v else int(v) for k, v in result.items()
                      if k != "seconds"},
            sim_seconds=float(result["seconds"]), wall_seconds=wall)
