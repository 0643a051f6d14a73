"""The cocotb bench's steps (:mod:`dptbd.sim.benches.axi`: register ``writes``,
``lut_codes``, ``soft_reset``, ``check`` and ``stop``, and the keys only the Verilator runs
take) as operations of the AXI harness with what each is to answer
(:func:`step_operations`), and the frame monitor's fault pulses they imply
(:func:`fault_pulse_array`).
"""

from __future__ import annotations

import numpy as np

from dptbd.hw.register_map import FAULTS, constants_namespace, register_map
from dptbd.sim.axi.stimulus import Beats, fault_pulses, stream_pieces

__all__ = ["OKAY", "SLVERR", "DECERR", "CUT_COUNTERS", "BUS_LATE_BIT", "step_operations",
           "no_sof_mask", "fault_pulse_array"]

OKAY, SLVERR, DECERR = 0, 2, 3

#: The counters of the core's events, which a reset with words in flight leaves at a count
#: that depends on timing: read right after every ``soft_reset: "now"`` (the base of their
#: check at the end) and LISTS checked there against the lists delivered.
CUT_COUNTERS = ("FRAMES", "SEGMENTS", "LISTS", "SATURATED")

#: The bit of an ``m`` operation's data that makes the write's W late (``"w-late"``).
BUS_LATE_BIT = 36


def step_operations(cfg, steps: list[dict], settle: int, final_reads: list[str],
                    store=None) -> tuple[list[tuple], list[tuple]]:
    """The harness operations of the bench's ``steps`` and, per w/r operation, what to
    check: ``("write", name, expected response)`` or ``("read", name, expected value or
    None)``. Each step waits ``settle`` cycles before its ``check`` reads or soft reset (as
    :mod:`dptbd.sim.benches.axi` does), then writes; ``final_reads`` are read after the last beat
    and ``settle`` idle cycles.

    ``soft_reset`` may be ``"now"``: no settle before it (``soft_reset_wait`` idle cycles
    if given), then a wait until ``STATUS.soft_reset_busy`` reads 0 (check
    ``("wait", "STATUS", beat)``), then reads of :data:`CUT_COUNTERS` (checks ``("cut",
    name, beat)``). ``aresetn`` (cycles) holds ``aresetn`` low after the settle and the
    check reads; with ``aresetn_wait`` (idle cycles, may be 0) instead of the settle, with
    words in flight, and then a read of STATUS (``("mark", "STATUS", beat)``: the cycle
    of the cut).
    Besides the bench's keys a step may hold ``clear_counters`` (a ``CONTROL.clear_counters``
    pulse after the settle and the check reads, before a soft reset), ``lut_writes``
    (``[p, m, code, wstrb]``: single LUT entries, after ``lut_codes``; refused unless
    ``wstrb`` = 0xF and the code is in [0, 2**F]) and ``bus`` (raw accesses, last:
    ``["w", address, data, wstrb, response]`` or ``["r", address, response, value or
    None]``; what is to be checked is given; ``"w-late"`` offers W only from the cycle
    after the AW handshake and changes ``awaddr`` then, ``"r-probe"`` changes ``araddr``
    after the AR handshake, offers AR while the read is pending (``"r-probe-all"`` AW and
    W too; none may be taken: the harness counts ``axil_violations``) and holds ``rready``
    low for 3 cycles of ``rvalid``). ``store``: the build's state store, whose
    registers a ``check`` may then read."""
    regs, regmap = constants_namespace(cfg, store), register_map(cfg, store)
    ops, checks, start = [], [], 0

    def read(at, name, want=None):
        ops.append((at, "r", getattr(regs, f"REG_{name}"), 0))
        checks.append(("read", name, want))

    def write(at, address, value, want, name):
        ops.append((at, "w", address, int(value)))
        checks.append(("write", name, want))

    unity = 1 << cfg.weight_frac_bits
    for step in steps:
        if (step.get("check") or step.get("soft_reset") is True or step.get("clear_counters")
                or (step.get("aresetn") and "aresetn_wait" not in step)):
            ops.append((start, "i", settle, 0))
        for name, want in (step.get("check") or {}).items():
            read(start, name, want)
        if step.get("aresetn"):
            if step.get("aresetn_wait"):
                ops.append((start, "i", int(step["aresetn_wait"]), 0))
            ops.append((start, "a", int(step["aresetn"]), 0))
        if step.get("aresetn") and "aresetn_wait" in step:   # the cycle of the cut
            ops.append((start, "b", regs.REG_STATUS, 0))
            checks.append(("mark", "STATUS", start))
        if step.get("clear_counters"):
            write(start, regs.REG_CONTROL, regs.CONTROL_CLEAR_COUNTERS_MASK, OKAY, "CONTROL")
        if step.get("soft_reset") == "now" and step.get("soft_reset_wait"):
            ops.append((start, "i", int(step["soft_reset_wait"]), 0))
        if step.get("soft_reset"):
            write(start, regs.REG_CONTROL, regs.CONTROL_SOFT_RESET_MASK, OKAY, "CONTROL")
        if step.get("soft_reset") == "now":
            ops.append((start, "b", regs.REG_STATUS, 0))
            checks.append(("wait", "STATUS", start))
            for name in CUT_COUNTERS:           # what the cut left: the base of the end check
                ops.append((start, "r", getattr(regs, f"REG_{name}"), 0))
                checks.append(("cut", name, start))
        for name, value in step.get("writes", []):
            reg = regmap[name]
            limits = reg.fields[0].limits if reg.kind == "setting" else (0, 2**32 - 1)
            taken = reg.access != "ro" and limits[0] <= value <= limits[1]
            write(start, getattr(regs, f"REG_{name}"), value, OKAY if taken else SLVERR, name)
        if step.get("lut_codes") is not None:
            for p, row in enumerate(step["lut_codes"]):
                for m, code in enumerate(row):
                    write(start, regs.LUT_BASE + 4 * cfg.lut_address(p, m), code, OKAY, "LUT")
        for p, m, code, strobe in step.get("lut_writes", []):
            taken = strobe == 0xF and 0 <= code <= unity
            ops.append((start, "m", regs.LUT_BASE + 4 * cfg.lut_address(p, m),
                        int(code) | int(strobe) << 32))
            checks.append(("write", f"LUT[{p}, {m}]", OKAY if taken else SLVERR))
        for kind, address, *rest in step.get("bus", []):
            if kind in ("w", "w-late"):
                data, strobe, want = rest
                late = (kind == "w-late") << BUS_LATE_BIT
                ops.append((start, "m", int(address), int(data) | int(strobe) << 32 | late))
                checks.append(("write", f"{int(address):#05x}", want))
            else:
                probe = {"r-probe": 1, "r-probe-all": 3}.get(kind, 0)
                ops.append((start, "r", int(address), probe))
                checks.append(("bus-read", f"{int(address):#05x}", tuple(rest)))
        start = step["stop"]
    ops.append((start, "i", settle, 0))
    for name in final_reads:
        read(start, name)
    return ops, checks


def no_sof_mask(beats: Beats, steps: list[dict]) -> np.ndarray:
    """Per beat: ``VIDEO_INPUT.no_sof`` is 1 when the beat is accepted (the steps' taken
    ``writes`` of ``VIDEO_INPUT``, from the step's first beat on)."""
    mask = np.zeros(len(beats), dtype=bool)
    start, value = 0, False
    for step in steps:
        value = value and not step.get("aresetn")
        for name, written in step.get("writes", []):
            if name == "VIDEO_INPUT" and written in (0, 1):
                value = bool(written)
        mask[start:step["stop"]] = value
        start = step["stop"]
    mask[start:] = value
    return mask


def fault_pulse_array(cfg, beats: Beats, steps: list[dict]) -> np.ndarray:
    """The frame monitor's fault pulses, ``(beats, len(FAULTS))``: the monitor restarts at
    every soft reset (:func:`~dptbd.sim.axi.stimulus.stream_pieces`) and raises no
    ``frame_long`` while ``no_sof`` is 1 (:func:`no_sof_mask`)."""
    out = np.zeros((len(beats), len(FAULTS)), dtype=np.int64)
    for piece in stream_pieces(cfg, steps):
        a, b = piece.start, min(piece.stop, len(beats))
        pulses = fault_pulses(cfg, beats.first[a:b], beats.last[a:b])
        if pulses:
            out[a:b] = [[p[k] for k in FAULTS] for p in pulses]
    out[no_sof_mask(beats, steps), FAULTS.index("frame_long")] = 0
    return out

