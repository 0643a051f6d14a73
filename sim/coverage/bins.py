"""Functional coverage of the verification campaign: every bin, defined here and only here.

A bin is a named count of something a run exercised. The counts of one run come from the
stimulus it offered (the input words, the stall densities, the cycle each word was accepted
and each output left, the resets, LUT and settings writes, the injected faults) and from the
golden model's outputs, which the RTL matched bit for bit: a run that failed fills no bin.
:func:`stream_bins` reads a compiled run of ``dp``, ``core`` or ``segmenter``
(:func:`dptbd.sim.campaign.check_run`), :func:`axi_bins` a run of ``dptbd_axi``
(:func:`dptbd.sim.axi_runs.check_run`): the inputs of
:func:`dptbd.sim.verilator_axi.check_axi` (the ``Beats``, the ``steps`` and the stall
densities) and the cycle each beat was accepted and each register operation done.

The bins are plain ``{name: hits}`` dicts: a run declares every bin its design and its
case's faults can fill (with 0 hits), so merging runs is addition (:func:`merge`) and a bin
still at 0 after the campaign is empty (:func:`empty_bins`); bins of a design that is not in
the campaign are never declared, never empty.

Why a module of our own rather than cocotb-coverage: cocotb-coverage samples transactions
one by one into a process-global database (``coverage_db``) and merges the databases of
several processes through exported XML/YAML files; the campaign's runs are scored in
worker processes and the bins here are computed array-wise from whole runs, so a dict of
counts that pickles and adds is all that is needed.

The bin groups and what a hit is (``docs/gateware.md``, "Verification campaign"):

* ``stall`` (also ``axi``, the positions by the model's counters of each piece between
  resets): input words accepted at a position of the frame (first / last row, first /
  last column, interior, a segment-boundary frame: the first or the last frame of a
  segment, by the model's counters) in runs whose input gap density (``valid_gap``) and
  output back-pressure density (``ready_pause``) fall in a band each: none (0), light
  (0 < p < 0.35), heavy (p >= 0.35).
* ``reset``: resets whose rise found k words in the pipeline, k = 0 … L (L the DP
  pipeline's latency of the run's build), or more than L (words waiting in the output
  FIFO under back-pressure). ``dp`` / ``core``: the words accepted since the previous reset
  minus the outputs transferred since then, before the reset's cycle (every accepted word
  leaves as one output). ``segmenter`` (one output per list, not per word): the words
  accepted in the L cycles before the reset (the DP pipeline never stalls on a list).
* ``soft reset`` (``axi``): soft resets (CONTROL.soft_reset) that found k words in flight,
  k = 0 … L (L the AXI top's latency, the build's ``latency``: from a beat accepted on
  ``s_axis_video`` to its state word, the DP pipeline's and the video input's): the beats
  accepted in the L cycles before the cycle the soft reset's AXI4-Lite
  write began (the harness offers no beat while an operation is under way; the register
  block answers a write in its :data:`AXIL_WRITE_CYCLES`-th cycle, so the write began
  that many cycles before its recorded response, less one). A soft reset after the step's
  settle (``soft_reset: True``) finds 0; ``soft_reset: "now"`` is measured this way.
* ``aresetn`` (``axi``): ``aresetn`` pulses with 0 words in flight, from the plan: those
  ``check_axi`` holds low after the step's settle (more than L idle cycles; those with
  words in flight, ``aresetn_wait``, are not counted here).
* ``fault``: injected faults of each class (:data:`dptbd.sim.campaign.FAULTS`,
  :data:`dptbd.sim.axi_stimulus.FAULT_KINDS`) followed by a clean segment: a whole segment
  (K complete frames from the counters' frame 0) that starts at or after the fault, with no
  fault, LUT or settings write inside it, all of whose outputs matched (the run passed).
* ``LUT``: whole-table writes by the stage of the frame they come before (between frames:
  before a frame's first word or after the stream; in the first row; a middle row; the last
  row), and written entries holding code 0, 2**F - 1 and 2**F (the largest code, weight 1).
* ``saturation``: model state words at E = 2**B_E - 1.
* ``lists`` (``segmenter``, ``axi``): candidate lists (all of whose words came out) with 0
  records, exactly n records (0 < n < C, n the list's run-time candidate count), C records,
  and with the overflow flag (more than C pixels reached the threshold).
* ``ties``: lists whose scored frame has two or more pixels in the list's threshold bin T
  (T < 2**b): a tie at the threshold, every one of them selected.
* ``register`` (``axi``): AXI4-Lite accesses refused (SLVERR) for each reason of
  ``docs/registers.md``: a value out of range per setting register and for the LUT window,
  a LUT write without wstrb = 1111, a LUT read, a write to a constant, counter or status
  register, unaligned and unmapped reads and writes. ``check_axi``'s ``steps`` express the
  range refusals of the setting registers, ``lut_writes`` and ``bus`` the LUT's and the
  raw accesses (``bus`` of :func:`axi_bins` adds more); a write of a setting with some
  strobes refuses the value it would make (the strobed bytes of the data over the
  register's value held then).
"""

from __future__ import annotations

import dataclasses
import re
from typing import Iterable, Mapping

import numpy as np

__all__ = ["BANDS", "POSITIONS", "Group", "GROUPS", "band", "declared_stream", "declared_axi",
           "stream_bins", "axi_bins", "bus_operations", "soft_reset_bin", "list_ends", "merge",
           "empty_bins", "table", "empty_message", "ARESETN", "AXIL_WRITE_CYCLES"]

STREAM = ("dp", "core", "segmenter")
AXI = ("axi",)

#: Stall density bands: (name, lowest density, highest density excluded).
BANDS = (("none", 0.0, 0.0), ("light", 0.0, 0.35), ("heavy", 0.35, 1.0))

POSITIONS = ("first row", "last row", "first column", "last column", "interior",
             "segment boundary frame")

LIST_LABELS = ("0 records (empty)", "exactly n records (0 < n < C)", "C records (at capacity)",
               "overflowing (more than C)")

LUT_STAGES = ("written between frames", "written in the first row",
              "written in a middle row", "written in the last row")
LUT_CODES = ("code 0", "code 2**F - 1", "code 2**F (the largest)")


@dataclasses.dataclass(frozen=True)
class Group:
    """A family of bins: its name (the prefix of its bins' names) and the designs whose
    runs fill it."""

    name: str
    designs: tuple[str, ...]


GROUPS = (Group("stall", STREAM + AXI), Group("reset", STREAM), Group("soft reset", AXI),
          Group("aresetn", AXI), Group("fault", STREAM + AXI), Group("LUT", STREAM + AXI),
          Group("saturation", STREAM + AXI), Group("lists", ("segmenter",) + AXI),
          Group("ties", ("segmenter",) + AXI), Group("register", AXI))

SATURATION = "saturation: a state word at E = 2**B_E - 1"
TIES = "ties: two or more pixels in the threshold bin"
ARESETN = "aresetn: 0 words in flight"
#: Cycles of an AXI4-Lite write in the AXI harness, from AW and W offered to the response
#: taken (the register block's; ``tests/sim/test_axi_runs.py`` measures it).
AXIL_WRITE_CYCLES = 3
FIFO = "more than L words (output FIFO)"
RANGE = " value out of range"
BUS_REASONS = ("LUT write without wstrb = 1111", "LUT read", "write to a constant register",
               "write to a counter", "write to the status register", "unaligned write",
               "unaligned read", "unmapped write", "unmapped read")


def band(p: float) -> str:
    """The band of a stall density."""
    return "none" if p == 0 else ("light" if p < BANDS[1][2] else "heavy")


def _key(group: str, label: str) -> str:
    return f"{group}: {label}"


def _words(k: int) -> str:
    return f"{k} word{'' if k == 1 else 's'} in flight"


def declared_stream(design: str, faults: Iterable[str], lut: bool, latency: int
                    ) -> dict[str, int]:
    """Every bin (0 hits) a run of ``design`` can fill: its case's ``faults``, ``lut``
    whether its case writes the LUT, ``latency`` the DP pipeline's L."""
    faults = tuple(faults)
    out = {_key("stall", f"gaps {g}, back-pressure {b}, {p}"): 0
           for g, *_ in BANDS for b, *_ in BANDS for p in POSITIONS}
    if "reset" in faults:
        out.update({_key("reset", _words(k)): 0 for k in range(latency + 1)})
        if design != "segmenter":
            out[_key("reset", FIFO)] = 0
    out.update({_key("fault", f"{f} recovered"): 0 for f in faults})
    if lut:
        out.update({_key("LUT", label): 0 for label in LUT_STAGES + LUT_CODES})
    out[SATURATION] = 0
    if design == "segmenter":
        out.update({_key("lists", label): 0 for label in LIST_LABELS})
        out[TIES] = 0
    return out


def soft_reset_bin(k: int) -> str:
    """The bin of a soft reset that found ``k`` words in flight."""
    return _key("soft reset", _words(k))


def declared_axi(cfg, latency: int) -> dict[str, int]:
    """Every bin (0 hits) a run of ``dptbd_axi`` fills; ``latency`` the DP pipeline's L of
    the build."""
    from dptbd.sim.axi_stimulus import FAULT_KINDS

    out = {_key("stall", f"gaps {g}, back-pressure {b}, {p}"): 0
           for g, *_ in BANDS for b, *_ in BANDS for p in POSITIONS}
    out.update({soft_reset_bin(k): 0 for k in range(latency + 1)})
    out[ARESETN] = 0
    out.update({_key("fault", f"{f} recovered"): 0 for f in FAULT_KINDS})
    out.update({_key("LUT", label): 0 for label in LUT_STAGES + LUT_CODES})
    out[SATURATION] = 0
    out.update({_key("lists", label): 0 for label in LIST_LABELS})
    out[TIES] = 0
    out.update({_key("register", name + RANGE): 0 for name in _ranged(cfg)})
    out.update({_key("register", reason): 0 for reason in BUS_REASONS})
    return out


def _ranged(cfg) -> list[str]:
    """The registers (and the LUT window) that refuse a value out of range."""
    from dptbd.hw.register_map import register_map

    regs = register_map(cfg)
    return [r.name for r in regs.registers if r.kind == "setting"] + \
        [w.name for w in regs.windows]


# ---- the model's view of a whole run --------------------------------------------------------

@dataclasses.dataclass
class _View:
    """The model's outputs of a run, concatenated over its epochs (resets, soft resets)."""

    row: np.ndarray
    col: np.ndarray
    frame_end: np.ndarray
    energy: np.ndarray
    boundary: np.ndarray           # the word is in a segment's first or last frame
    segments: list                 # (start, stop) of whole segments, stream indices
    lists: list                    # (CandidateList, n) of every list that came out whole


def _view(cfg, pieces) -> _View:
    """``pieces``: (index of the first word, StreamExpectation, lists or None, words of
    the lists that came out or None)."""
    from dptbd.sim.candidate_scoreboard import list_words

    rows, cols, ends, energy, boundary, segments, lists = [], [], [], [], [], [], []
    for start, exp, got_lists, received in pieces:
        rows.append(exp.positions[:, 1])
        cols.append(exp.positions[:, 2])
        ends.append(exp.fields[:, 3])
        energy.append(exp.fields[:, 0])
        edge = np.zeros(len(exp.fields), dtype=bool)
        runs = list(exp.runs)
        for run in runs:
            if run.frame == 0 or run.frame == run.segment_frames - 1:
                edge[run.start:run.stop] = True
        boundary.append(edge)
        for i, run in enumerate(runs):
            k = run.segment_frames
            whole = runs[i:i + k]
            if run.frame == 0 and len(whole) == k and all(
                    r.complete and r.frame == j for j, r in enumerate(whole)):
                segments.append((start + run.start, start + whole[-1].stop))
        if got_lists is None:
            continue
        ends_at = list_ends(cfg, exp.fields, exp.settings)
        real = got_lists[:len(ends_at)]
        sizes = np.cumsum([len(w) for w in list_words(cfg, real)])
        whole_out = int(np.searchsorted(sizes, received, side="right")) \
            if received is not None else len(real)
        lists += [(lst, n) for lst, (_, n) in zip(real[:whole_out], ends_at)]
    cat = (lambda parts, dtype: np.concatenate(parts).astype(dtype) if parts
           else np.zeros(0, dtype=dtype))
    return _View(cat(rows, np.int64), cat(cols, np.int64), cat(ends, bool),
                 cat(energy, np.int64), cat(boundary, bool), segments, lists)


def list_ends(cfg, fields: np.ndarray, settings: np.ndarray | None) -> list[tuple[int, int]]:
    """(index of the list's last word, the list's n) of every list that
    :func:`~dptbd.model.segmentation.segment_stream` makes of ``fields`` with ``settings``,
    in order: the same control flow (a segment's K and n taken at its first word, a list
    ending at its scored frame's last pixel or at an ``end_of_segment`` inside the scored
    frame, counters realigned on every ``end_of_segment``), one step per segment."""
    size = cfg.width * cfg.height
    eos = np.flatnonzero(np.asarray(fields)[:, 4])
    n_words = len(fields)
    out, a = [], 0
    while a < n_words:
        k, n = ((int(settings[a][0]), int(settings[a][1])) if settings is not None
                else (cfg.segment_frames, cfg.n_candidates))
        last = a + k * size - 1
        i = int(np.searchsorted(eos, a))
        e = int(eos[i]) if i < len(eos) else None
        if e is not None and e < last:
            if e >= last - size + 1:
                out.append((e, n))
            a = e + 1
        else:
            if last < n_words:
                out.append((last, n))
            a = last + 1
    return out


# ---- the bins of one run --------------------------------------------------------------------

def _positions(view: _View, cfg, counts: dict, prefix: str) -> None:
    first, last = view.row == 0, view.row == cfg.height - 1
    left, right = view.col == 0, view.col == cfg.width - 1
    masks = {"first row": first, "last row": last, "first column": left, "last column": right,
             "interior": ~(first | last | left | right), "segment boundary frame": view.boundary}
    for name in POSITIONS:
        counts[_key("stall", f"{prefix}, {name}")] += int(np.count_nonzero(masks[name]))


def _recovered(view: _View, events: list[tuple[str, int]], counts: dict,
               writes: Iterable[int] = ()) -> None:
    """A fault is recovered when a clean segment (no fault and no write in ``writes``
    inside it) starts at or after it."""
    at = np.array([i for _, i in events] + list(writes), dtype=np.int64)
    clean = [s for s, t in view.segments
             if not np.any((at > s) & (at < t))]
    latest = max(clean, default=-1)
    for fault, i in events:
        if i <= latest:
            counts[_key("fault", f"{fault} recovered")] += 1


def _lut_stage(view: _View, cfg, index: int) -> str:
    n = len(view.row)
    if index >= n:
        if n == 0 or view.frame_end[n - 1]:
            return LUT_STAGES[0]
        index = n - 1
    elif view.row[index] == 0 and view.col[index] == 0:
        return LUT_STAGES[0]
    row = int(view.row[index])
    return LUT_STAGES[1] if row == 0 else (LUT_STAGES[3] if row == cfg.height - 1
                                           else LUT_STAGES[2])


def _lut(view: _View, cfg, writes, counts: dict) -> None:
    unity = 1 << cfg.weight_frac_bits
    for index, codes in writes:
        counts[_key("LUT", _lut_stage(view, cfg, int(index)))] += 1
        codes = np.asarray(codes)
        for label, code in zip(LUT_CODES, (0, unity - 1, unity)):
            counts[_key("LUT", label)] += int(np.count_nonzero(codes == code))


def _lists(view: _View, cfg, counts: dict) -> None:
    capacity = cfg.record_capacity
    for lst, n in view.lists:
        hit = {LIST_LABELS[0]: lst.count == 0,
               LIST_LABELS[1]: 0 < n < capacity and lst.count == n,
               LIST_LABELS[2]: lst.count == capacity, LIST_LABELS[3]: bool(lst.overflow)}
        for label, yes in hit.items():
            counts[_key("lists", label)] += int(yes)
        t = int(lst.threshold)
        counts[TIES] += int(t < cfg.n_bins and int(lst.histogram[t]) >= 2)


def _reset_occupancy(design: str, resets, accept: np.ndarray, out_cycles: np.ndarray,
                     latency: int) -> list[int]:
    """Words in the pipeline at each reset's first cycle (see the module doc)."""
    occupancy, prev_in, prev_out = [], 0, 0
    for cycle in sorted(c for c, _ in resets):
        n_in = int(np.searchsorted(accept, cycle))
        n_out = int(np.searchsorted(out_cycles, cycle))
        if design == "segmenter":
            occupancy.append(n_in - max(prev_in, int(np.searchsorted(accept, cycle - latency))))
        else:
            occupancy.append((n_in - prev_in) - (n_out - prev_out))
        prev_in, prev_out = n_in, n_out
    return occupancy


def stream_bins(case, stimulus, result, events: Iterable[tuple[str, int]] = (),
                latency: int = 0) -> dict[str, int]:
    """The bins of one compiled run of a ``dp``, ``core`` or ``segmenter`` case.

    Parameters
    ----------
    case : dptbd.sim.campaign.Case
    stimulus : dptbd.sim.rtl_check.Stimulus
    result : dptbd.sim.rtl_check.CheckResult
    events : iterable of (fault, word index)
        The framing faults injected (``misaligned_first``, ``short_frame``,
        ``long_frame``) and the first word they touch; resets, LUT and settings writes and
        the store's garbage are read from ``stimulus``.
    latency : int
        The DP pipeline's L of the build.
    """
    cfg = case.cfg
    lut = "lut" in case.faults or case.random_lut
    counts = declared_stream(case.design, case.faults, lut, latency)
    if not result.passed:
        return counts
    pieces = [(a, exp, board.lists if case.design == "segmenter" else None, board.count)
              for a, exp, board in result.scored]
    view = _view(cfg, pieces)
    _positions(view, cfg, counts, f"gaps {band(stimulus.valid_gap)}, "
                                  f"back-pressure {band(stimulus.ready_pause)}")
    raw = result.raw
    accept = raw.accept_cycles[:result.words_in].astype(np.int64)
    if "reset" in case.faults:
        for k in _reset_occupancy(case.design, stimulus.resets, accept,
                                  raw.out_cycles.astype(np.int64), latency):
            counts[_key("reset", _words(k) if k <= latency else FIFO)] += 1
    found = list(events)
    found += [("reset", int(np.searchsorted(accept, c))) for c, _ in stimulus.resets]
    found += [("lut", int(i)) for i, _ in stimulus.lut_changes if int(i) > 0]
    found += [("settings", int(i)) for i, _ in stimulus.settings_changes]
    if stimulus.store_init == "random":
        found.append(("store_garbage", 0))
    _recovered(view, [e for e in found if e[0] in case.faults], counts)
    if lut:
        _lut(view, cfg, stimulus.lut_changes, counts)
    counts[SATURATION] += int(np.count_nonzero(view.energy == cfg.e_max))
    _lists(view, cfg, counts)
    return counts


def _bus_reason(regs, kind: str, address: int, data: int, wstrb: int,
                held: Mapping[int, int]) -> str | None:
    """Why the register block refuses a raw access (``docs/registers.md``), or None;
    ``held``: the value each setting register (by address) holds before the access."""
    verb = "write" if kind == "w" else "read"
    if address % 4:
        return f"unaligned {verb}"
    for window in regs.windows:
        if window.base <= address < window.end:
            if kind == "r":
                return f"{window.name} read"
            if wstrb != 0xF:
                return f"{window.name} write without wstrb = 1111"
            lo, hi = window.field.limits
            return None if lo <= data <= hi else window.name + RANGE
    for reg in regs.registers:
        if reg.address == address:
            if kind == "r":
                return None
            if reg.kind in ("constant", "counter", "status"):
                return {"constant": "write to a constant register",
                        "counter": "write to a counter",
                        "status": "write to the status register"}[reg.kind]
            lo, hi = reg.fields[0].limits or (None, None)
            return None if lo is None or lo <= _merged(data, wstrb, held[address]) <= hi \
                else reg.name + RANGE
    return f"unmapped {verb}"


def _merged(data: int, wstrb: int, held: int) -> int:
    """The word a write with strobes ``wstrb`` makes of a register holding ``held``."""
    mask = sum(0xFF << 8 * lane for lane in range(4) if wstrb >> lane & 1)
    return (data & mask) | (held & ~mask & 0xFFFFFFFF)


def bus_operations(cfg, steps: list[dict]) -> list[tuple[int, tuple[str, int, int, int]]]:
    """(step index, ``(kind "w" or "r", byte address, data, wstrb)``) of every register
    access the ``steps`` make besides the checked reads, soft resets and counter clears, in
    the order :func:`~dptbd.sim.verilator_axi.step_operations` performs them: ``writes``,
    ``lut_codes``, ``lut_writes``, ``bus``."""
    from dptbd.hw.register_map import register_map

    regs = register_map(cfg)
    lut = regs.window("LUT").base
    out = []
    for j, step in enumerate(steps):
        ops = [("w", regs[name].address, int(value), 0xF)
               for name, value in step.get("writes", [])]
        if step.get("lut_codes") is not None:
            ops += [("w", lut + 4 * cfg.lut_address(p, m), int(code), 0xF)
                    for p, row in enumerate(step["lut_codes"]) for m, code in enumerate(row)]
        ops += [("w", lut + 4 * cfg.lut_address(p, m), int(code), int(strobe))
                for p, m, code, strobe in step.get("lut_writes", [])]
        ops += [("w", int(a), int(rest[0]), int(rest[1])) if k == "w" else ("r", int(a), 0, 0)
                for k, a, *rest in step.get("bus", [])]
        out += [(j, op) for op in ops]
    return out


def _in_flight(cfg, steps: list[dict], run, latency: int) -> list[int]:
    """Words in flight at each ``soft_reset: "now"`` (see the module doc): the beats
    accepted in the ``latency`` cycles before its write began."""
    from dptbd.sim.verilator_axi import step_operations

    _, checks = step_operations(cfg, steps, 0, [])
    accept = np.sort(np.asarray(run.accept_cycles, dtype=np.int64))
    out = []
    for i, (kind, _, _) in enumerate(checks):
        if kind == "wait":                         # follows its soft reset's write
            began = int(run.op_cycles[i - 1]) - (AXIL_WRITE_CYCLES - 1)
            out.append(int(np.searchsorted(accept, began) -
                           np.searchsorted(accept, began - latency)))
    return out


def axi_bins(cfg, beats, steps: list[dict], *, passed: bool, latency: int,
             valid_gap: float = 0.0, ready_pause: float = 0.0, run=None,
             bus: Iterable[tuple[str, int, int, int]] = ()) -> dict[str, int]:
    """The bins of one run of ``dptbd_axi`` (:func:`dptbd.sim.verilator_axi.check_axi`
    with these ``beats``, ``steps``, ``valid_gap`` and ``ready_pause``; ``passed`` its
    verdict, ``latency`` the build's L, ``VerilatorBuild.latency``). ``run``: the
    :class:`~dptbd.sim.verilator_axi.AxiRun` (its ``accept_cycles`` and ``op_cycles``),
    needed if a soft reset is ``"now"``. ``bus``: raw AXI4-Lite operations the run also
    performed after the steps', ``(kind "w" or "r", byte address, data, wstrb)``.

    :func:`dptbd.sim.axi_runs.check_run` fills an AXI run's bins with it."""
    from dptbd.hw.register_map import FAULTS, register_map
    from dptbd.model.segmentation import segment_stream
    from dptbd.sim.axi_stimulus import stream_pieces
    from dptbd.sim.stream_model import expected_stream
    from dptbd.sim.verilator_axi import fault_pulse_array

    counts = declared_axi(cfg, latency)
    if not passed:
        return counts
    now = sum(step.get("soft_reset") == "now" for step in steps)
    if now and run is None:
        raise ValueError("axi_bins needs the run's cycles (run=) to count the words in "
                         "flight at a soft reset of \"now\"")
    pieces = []
    for piece in stream_pieces(cfg, steps):
        a, b = piece.start, piece.stop
        exp = expected_stream(cfg, beats.pixel[a:b], beats.first[a:b],
                              {i - a: codes for i, codes in piece.lut_changes.items()},
                              {i - a: st for i, st in piece.settings_changes.items()})
        pieces.append((a, exp, segment_stream(exp.fields, cfg, exp.settings), None))
    view = _view(cfg, pieces)
    _positions(view, cfg, counts, f"gaps {band(valid_gap)}, back-pressure {band(ready_pause)}")
    counts[soft_reset_bin(0)] += sum(step.get("soft_reset") is True for step in steps)
    for k in (_in_flight(cfg, steps, run, latency) if now else []):
        counts[soft_reset_bin(k)] += 1
    counts[ARESETN] += sum(bool(step.get("aresetn")) and "aresetn_wait" not in step
                           for step in steps)
    starts = [0] + [step["stop"] for step in steps[:-1]]
    unity = 1 << cfg.weight_frac_bits
    writes = [(s, step["lut_codes"]) for s, step in zip(starts, steps)
              if step.get("lut_codes") is not None]
    entries = [code for step in steps for _, _, code, strobe in step.get("lut_writes", [])
               if strobe == 0xF and 0 <= code <= unity]
    pulses = fault_pulse_array(cfg, beats, steps)
    events = [(kind, int(i)) for j, kind in enumerate(FAULTS)
              for i in np.flatnonzero(pulses[:, j])]
    _recovered(view, events, counts, [s for s, step in zip(starts, steps)
                                      if step.get("writes") or step.get("lut_writes")
                                      or step.get("lut_codes") is not None])
    _lut(view, cfg, writes, counts)
    for label, code in zip(LUT_CODES, (0, unity - 1, unity)):
        counts[_key("LUT", label)] += entries.count(code)
    counts[SATURATION] += int(np.count_nonzero(view.energy == cfg.e_max))
    _lists(view, cfg, counts)
    regs = register_map(cfg)
    settings = {r.address: r.reset for r in regs.registers if r.kind == "setting"}
    held, done = dict(settings), -1
    for j, op in [*bus_operations(cfg, steps), *((len(steps), op) for op in bus)]:
        for step in steps[done + 1:j + 1]:     # aresetn comes before the step's writes
            if step.get("aresetn"):
                held = dict(settings)
        done = max(done, j)
        kind, address, data, wstrb = op
        reason = _bus_reason(regs, kind, int(address), int(data), int(wstrb), held)
        if reason is not None:
            counts[_key("register", reason)] += 1
        elif kind == "w" and int(address) in held:
            held[int(address)] = _merged(int(data), int(wstrb), held[int(address)])
    return counts


# ---- the campaign's bins --------------------------------------------------------------------

def merge(*runs: Mapping[str, int]) -> dict[str, int]:
    """The bins of several runs: every declared bin, hits added."""
    out: dict[str, int] = {}
    for counts in runs:
        for key, hits in counts.items():
            out[key] = out.get(key, 0) + int(hits)
    return out


_BAND_ORDER = {name: i for i, (name, *_) in enumerate(BANDS)}


def _order(key: str):
    """Group order, then the bands and positions in their order, numbers by value."""
    group, _, label = key.partition(": ")
    index = next((i for i, g in enumerate(GROUPS) if g.name == group), len(GROUPS))
    stall = re.fullmatch(r"gaps (\w+), back-pressure (\w+), (.+)", label)
    if stall:
        g, b, p = stall.groups()
        return index, [_BAND_ORDER.get(g, 9), _BAND_ORDER.get(b, 9),
                       POSITIONS.index(p) if p in POSITIONS else 9]
    return index, [(0, int(t), "") if t.isdigit() else (1, 0, t)
                   for t in re.split(r"(\d+)", label)]


def table(counts: Mapping[str, int]) -> list[tuple[str, str, int]]:
    """(bin, the designs whose runs fill it, hits) of every bin, in group order."""
    designs = {g.name: ", ".join(g.designs) for g in GROUPS}
    return [(key, designs.get(key.split(":", 1)[0], "?"), int(counts[key]))
            for key in sorted(counts, key=_order)]


def empty_bins(counts: Mapping[str, int]) -> list[str]:
    """The declared bins no run hit, in group order."""
    return [key for key, _, hits in table(counts) if hits == 0]


def empty_message(empty: list[str]) -> str:
    """The verdict of a campaign that left bins empty."""
    return (f"functional coverage: {len(empty)} empty bin{'' if len(empty) == 1 else 's'}: "
            + "; ".join(empty))
