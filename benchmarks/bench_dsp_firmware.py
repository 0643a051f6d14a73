"""Memory and worst-case work per segment of the DSP firmware (``dptbd/dsp/firmware``).

    python benchmarks/bench_dsp_firmware.py                 # the tables of docs/dsp_firmware.md §7 and docs/throughput.md
    python benchmarks/bench_dsp_firmware.py --sets 64x128 16x66 --steps 400 --json out.json

For each build-time capacity set ``CxNxPxA`` (``capacity`` C track records,
``max_candidates`` N, ``max_points`` P, ``output_capacity`` A; P and A default 64) the
firmware is built
(:func:`dptbd.dsp.firmware.build_shared_library`) and measured:

* **static memory**: ``dptbd_track_context_bytes()``, the whole state (``sizeof`` the
  context struct; nothing else is allocated);
* **work per segment** on two worst-case streams (:data:`STREAMS`), both with N candidates
  on a grid 3 px apart (no cluster suppression: every candidate tests every other one),
  energies rising with the index (each new-track insertion moves to the front), every
  record in use with ids falling with the record index (each track insertion moves to the
  front: C(C-1)/2 compares), thresholds that never delete: ``in_gates`` (every candidate in
  every gate: each cost evaluation runs the heading cost and its integer square root, every
  track is extended, then tested for duplicates) and ``outside_gates`` (no candidate in any
  gate: C x N cost evaluations, all N candidates left over for new tracks). The firmware's
  own counters (``dptbd_work``) give the loop iterations of a segment, printed next to the
  bound of ``docs/dsp_firmware.md``;
* **time per segment** of ``dptbd_track_step`` called through ctypes (a call costs well under
  a microsecond), minimum and median over ``--steps`` steady-state segments, and the same
  in cycles of the time-stamp counter (``cpu MHz`` of ``/proc/cpuinfo``; on a shared machine
  the minimum is the figure to quote); and the Python model's time per segment on the same
  stream for comparison (fewer steps).

This script only reports; it asserts nothing.
"""

from __future__ import annotations

import argparse
import ctypes
import json
import statistics
import sys
import time

import numpy as np

from dptbd.dsp.association import CANDIDATE_DTYPE, AssociationConfig, Tracker
from dptbd.dsp.c_tracker import CTracker, _Candidate, _numpy_dtype

DEFAULT_SETS = ("16x66x16x16", "32x66x32x16", "64x66", "64x128", "128x128", "256x256")


def cpu_mhz() -> float | None:
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("cpu MHz"):
                    return float(line.split(":")[1])
    except OSError:
        pass
    return None


def grid(n: int, side: int, offset: int = 0) -> np.ndarray:
    """N candidates on a grid 3 px apart (offset px down), energies rising with the index."""
    per_row = side // 3
    idx = np.arange(n)
    rows, cols = 3 * (idx // per_row) + 1 + offset, 3 * (idx % per_row) + 1
    out = np.zeros(n, dtype=CANDIDATE_DTYPE)
    out["row"], out["col"], out["energy"] = rows, cols, 1000 + idx
    out["direction"], out["row0"], out["col0"], out["path"] = 4, rows, cols, 1
    return out


#: The two worst-case streams (module docstring).
STREAMS = {
    # every candidate in every gate: each cost evaluation runs the heading cost (a path one
    # pixel long gives every candidate a heading), every track is extended
    "in_gates": dict(gate=1000.0, gate_miss=1.0, path_rows=1, offset=0),
    # no candidate in any gate (gates 0, tracks standing still, candidates 1 px away): every
    # track evaluates every candidate, every candidate is left over for a new track
    "outside_gates": dict(gate=0.0, gate_miss=0.0, path_rows=0, offset=1),
}


def stream_setup(kind: str, capacity: int, max_candidates: int, max_points: int = 64,
                 output_capacity: int = 64):
    spec = STREAMS[kind]
    side = 3 * int(np.ceil(np.sqrt(max_candidates))) + 3
    kw = dict(segment_frames=6, segment_stride=6, height=side, width=side, radius=1)
    assoc = AssociationConfig(capacity=capacity, max_candidates=max_candidates,
                              max_points=max_points, output_capacity=output_capacity,
                              seed_gate=spec["gate"], gate_base=spec["gate"],
                              gate_max=spec["gate"], gate_miss=spec["gate_miss"],
                              delete_ratio=0.0, predict_ratio=0.0, confirm_ratio=0.0,
                              max_misses=255)
    first = grid(max_candidates, side)
    first["row0"] -= spec["path_rows"]
    later = grid(max_candidates, side, spec["offset"])
    later["row0"] -= spec["path_rows"]
    return kw, assoc, first, later


def bounds(c: int, n: int) -> dict[str, int]:
    """The worst-case loop iterations of docs/dsp_firmware.md."""
    m = min(c, n)
    return {"suppression_tests": n * (n - 1), "sort_compares": c * (c - 1) // 2 + n * (n - 1) // 2,
            "cost_evaluations": c * n, "duplicate_tests": m * (m - 1) // 2,
            "free_probes": n + c}


def measure(kind: str, capacity: int, max_candidates: int, max_points: int, output_capacity: int,
            steps: int, py_steps: int) -> dict:
    """One stream on one build: work counters, C and Python time per segment."""
    kw, assoc, first, later = stream_setup(kind, capacity, max_candidates, max_points,
                                           output_capacity)
    c = CTracker(assoc, **kw)
    lib, ctx = c._lib, ctypes.byref(c._ctx)

    def c_list(cands):
        buf = np.zeros(max_candidates, dtype=_numpy_dtype(_Candidate))
        for name in CANDIDATE_DTYPE.names:
            buf[name] = cands[name]
        return buf, buf.ctypes.data_as(ctypes.POINTER(_Candidate))

    (buf0, ptr0), (buf1, ptr1) = c_list(first), c_list(later)
    work = type(c._work)()
    lib.dptbd_track_step(ctx, ptr0, max_candidates, ctypes.byref(work))   # fills the table
    lib.dptbd_track_step(ctx, ptr1, max_candidates, ctypes.byref(work))
    for i in range(capacity):          # ids falling with the index: every sort insertion
        c._ctx.tracks[i].id = capacity - i   # goes to the front (C(C-1)/2 compares)
    times, works = [], []
    for _ in range(steps):
        t0 = time.perf_counter_ns()
        lib.dptbd_track_step(ctx, ptr1, max_candidates, ctypes.byref(work))
        times.append(time.perf_counter_ns() - t0)
        works.append(tuple(getattr(work, f) for f, _ in work._fields_))
    names = [f for f, _ in work._fields_]
    w = dict(zip(names, works[-1]))
    py = Tracker(assoc, **kw)
    py.step(first)
    py.step(later)
    py_times = []
    for _ in range(py_steps):
        t0 = time.perf_counter_ns()
        py.step(later)
        py_times.append(time.perf_counter_ns() - t0)
    mhz = cpu_mhz()
    best, med = min(times), statistics.median(times)
    return {"stream": kind, "capacity": capacity, "max_candidates": max_candidates,
            "max_points": max_points, "output_capacity": output_capacity,
            "context_bytes": int(lib.dptbd_track_context_bytes()),
            "active": int(lib.dptbd_track_active(ctx)), "work": w,
            "iterations": sum(w.values()), "bounds": bounds(capacity, max_candidates),
            "bound_iterations": sum(bounds(capacity, max_candidates).values()),
            "c_us_min": best / 1e3, "c_us_median": med / 1e3,
            "c_cycles_min": None if mhz is None else round(best * mhz / 1e3),
            "python_ms_median": statistics.median(py_times) / 1e6 if py_times else None}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sets", nargs="+", default=list(DEFAULT_SETS),
                    help="capacity sets CxN[xPxA] (capacity x max_candidates [x max_points x "
                         "output_capacity], P and A default 64)")
    ap.add_argument("--steps", type=int, default=200, help="timed C steps per set")
    ap.add_argument("--python-steps", type=int, default=5, help="timed Python steps per set")
    ap.add_argument("--json", help="write the results here")
    args = ap.parse_args(argv)
    rows = []
    print(f"cpu MHz (time-stamp counter): {cpu_mhz()}")
    print("| C x N x P x A | stream | context bytes | suppression | sort | costs | duplicates | probes | "
          "iterations (bound) | C us/segment min (median) | cycles min | Python ms/segment |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for spec in args.sets:
        c, n, p, a = ([int(v) for v in spec.lower().split("x")] + [64, 64])[:4]
        for kind in STREAMS:
            r = measure(kind, c, n, p, a, args.steps, args.python_steps)
            rows.append(r)
            w = r["work"]
            print(f"| {c} x {n} x {p} x {a} | {kind} | {r['context_bytes']:,} | {w['suppression_tests']:,} | "
                  f"{w['sort_compares']:,} | {w['cost_evaluations']:,} | "
                  f"{w['duplicate_tests']:,} | {w['free_probes']:,} | {r['iterations']:,} "
                  f"({r['bound_iterations']:,}) | {r['c_us_min']:.1f} ({r['c_us_median']:.1f}) | "
                  f"{r['c_cycles_min']:,} | {r['python_ms_median']:.1f} |", flush=True)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
