"""The bins of a run of the AXI top level ``dptbd_axi`` (:func:`dptbd.sim.axi.runs.check_run`):
what the run fills (:func:`declared_axi`) and what it filled (:func:`axi_bins`), from the
inputs of :func:`dptbd.sim.verilator.axi.check_axi` and the cycle each beat was accepted and
each register operation done; the groups are described in :mod:`dptbd.sim.coverage.bins`."""

from __future__ import annotations

from typing import Iterable

import numpy as np

from dptbd.sim.coverage.bins.groups import (ALIGN, ARESETN, BUS_REASONS, LIST_LABELS,
                                            LUT_CODES, LUT_STAGES, RANGE, SATURATION, TIES,
                                            band, declared_stall, key, words_in_flight)
from dptbd.sim.coverage.bins.registers import (aligned_registers, bus_operations, bus_reason,
                                               merged_write, ranged_registers)
from dptbd.sim.coverage.bins.view import (count_lut, count_outputs, count_positions,
                                          count_recovered, view_of)

__all__ = ["AXIL_WRITE_CYCLES", "soft_reset_bin", "declared_axi", "axi_bins"]

#: Cycles of an AXI4-Lite write in the AXI harness, from AW and W offered to the response
#: taken (the register block's; ``tests/sim/axi/test_runs.py`` measures it).
AXIL_WRITE_CYCLES = 3


def soft_reset_bin(k: int) -> str:
    """The bin of a soft reset that found ``k`` words in flight."""
    return key("soft reset", words_in_flight(k))


def declared_axi(cfg, latency: int, store=None) -> dict[str, int]:
    """Every bin (0 hits) a run of ``dptbd_axi`` fills; ``latency`` the DP pipeline's L of
    the build, ``store`` its state store (``--state-store axi``), if any."""
    from dptbd.sim.axi.stimulus import FAULT_KINDS

    out = declared_stall()
    out.update({soft_reset_bin(k): 0 for k in range(latency + 1)})
    out[ARESETN] = 0
    out.update({key("fault", f"{f} recovered"): 0 for f in FAULT_KINDS})
    out.update({key("LUT", label): 0 for label in LUT_STAGES + LUT_CODES})
    out[SATURATION] = 0
    out.update({key("lists", label): 0 for label in LIST_LABELS})
    out[TIES] = 0
    out.update({key("register", name + RANGE): 0 for name in ranged_registers(cfg, store)})
    out.update({key("register", name + ALIGN): 0 for name in aligned_registers(cfg, store)})
    out.update({key("register", reason): 0 for reason in BUS_REASONS})
    return out


def _in_flight(cfg, steps: list[dict], run, latency: int, store=None) -> list[int]:
    """Words in flight at each ``soft_reset: "now"`` (the ``soft reset`` group of
    :mod:`dptbd.sim.coverage.bins`): the beats accepted in the ``latency`` cycles before its
    write began."""
    from dptbd.sim.verilator.axi import step_operations

    _, checks = step_operations(cfg, steps, 0, [], store=store)
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
             bus: Iterable[tuple[str, int, int, int]] = (), store=None) -> dict[str, int]:
    """The bins of one run of ``dptbd_axi`` (:func:`dptbd.sim.verilator.axi.check_axi`
    with these ``beats``, ``steps``, ``valid_gap`` and ``ready_pause``; ``passed`` its
    verdict, ``latency`` the build's L, ``VerilatorBuild.latency``). ``run``: the
    :class:`~dptbd.sim.verilator.axi.AxiRun` (its ``accept_cycles`` and ``op_cycles``),
    needed if a soft reset is ``"now"``. ``bus``: raw AXI4-Lite operations the run also
    performed after the steps', ``(kind "w" or "r", byte address, data, wstrb)``.
    ``store``: the build's state store (``--state-store axi``), whose register map then
    judges the accesses.

    :func:`dptbd.sim.axi.runs.check_run` fills an AXI run's bins with it."""
    from dptbd.hw.register_map import FAULTS, register_map
    from dptbd.model.segmentation import segment_stream
    from dptbd.sim.axi.stimulus import stream_pieces
    from dptbd.sim.stream_model import expected_stream
    from dptbd.sim.verilator.axi import fault_pulse_array

    counts = declared_axi(cfg, latency, store)
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
    view = view_of(cfg, pieces)
    count_positions(view, cfg, counts,
                    f"gaps {band(valid_gap)}, back-pressure {band(ready_pause)}")
    counts[soft_reset_bin(0)] += sum(step.get("soft_reset") is True for step in steps)
    for k in (_in_flight(cfg, steps, run, latency, store) if now else []):
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
    count_recovered(view, events, counts, [s for s, step in zip(starts, steps)
                                           if step.get("writes") or step.get("lut_writes")
                                           or step.get("lut_codes") is not None])
    count_lut(view, cfg, writes, counts)
    for label, code in zip(LUT_CODES, (0, unity - 1, unity)):
        counts[key("LUT", label)] += entries.count(code)
    count_outputs(view, cfg, counts)
    regs = register_map(cfg, store)
    settings = {r.address: r.reset for r in regs.registers if r.kind == "setting"}
    held, done = dict(settings), -1
    for j, op in [*bus_operations(cfg, steps), *((len(steps), op) for op in bus)]:
        for step in steps[done + 1:j + 1]:     # aresetn comes before the step's writes
            if step.get("aresetn"):
                held = dict(settings)
        done = max(done, j)
        kind, address, data, wstrb = op
        reason = bus_reason(regs, kind, int(address), int(data), int(wstrb), held)
        if reason is not None:
            counts[key("register", reason)] += 1
        elif kind == "w" and int(address) in held:
            held[int(address)] = merged_write(int(data), int(wstrb), held[int(address)])
    return counts
