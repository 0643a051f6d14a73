"""The campaign's runs of ``dptbd_dp`` built with ``--state-store axi`` (design ``"dp_axi"``:
:class:`~dptbd.hw.axi_store.pipeline.DPPipelineAxi`, its state in an AXI4 memory model).

A run draws from its seed only (:func:`draw_store_run`) a hostile scene
(:func:`~dptbd.sim.campaign.draw.hostile_frames`), input gaps and output back-pressure, a
read latency class (0; 1 … 99; 100 … 499; 500 … 700 cycles, in turn: seed mod 4; an error
run 0 or 1 … 99, in turn every fourth seed) with a range inside it and a write-response
range of its own, the memory's ready (AR, AW, W) and valid (R, B) probabilities (1, or
uniform in [0.3, 1)) and the state's base address (a multiple of the burst size, so the
frame's bursts end at 4 KB boundaries at varying offsets), and:

* without faults, runs on Verilator (:mod:`dptbd.sim.verilator.dp_axi`, the C++ memory model
  that checks every AXI4 rule it sees): every output word equal to the golden model's bit for
  bit (the first mismatch reported by frame, row, column and field), no AXI4 rule broken, no
  error flagged, and as many write bursts ending at a 4 KB boundary as the layout gives
  (:func:`boundary_bursts`), as many read bursts or up to a frame's more (the read-ahead);
  the ``store`` bins count what the memory model observed (stalled cycles of each channel,
  bursts ending at a 4 KB boundary: :data:`~dptbd.sim.coverage.bins.store.OBSERVED`);
* with the faults ``"read_error"`` / ``"write_error"``
  (:data:`~dptbd.sim.campaign.store.cases.STORE_FAULTS`), runs on the Amaranth simulator with :class:`~dptbd.sim.axi4_memory.Axi4Memory` (its errors are tied to
  a slot's address; the C++ model's to a window of cycles), which answers the first read
  beat and / or the first write burst touching a random slot (a second error: the slot half
  a frame further) from the first pixel of a random frame t on with SLVERR or DECERR (seed
  mod 4 picks one of the four (code, direction) pairs, the other direction fails too in
  about half the runs); the promise of ``docs/integration.md`` ("State store in external
  memory") is checked: each error pulses ``read_error`` / ``write_error`` exactly once,
  every pixel still comes out (the core never waits on a failed transfer), the frames before
  t and every frame from the segment after t + 1's on are bit-exact (the failed transfers
  are frame t - 1's or t's write, t's or t + 1's read).
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np

from dptbd.sim.campaign.store.cases import LATENCY_DRAW, STORE_FAULTS, store_config

__all__ = ["StorePlan", "draw_store_run", "boundary_bursts", "build_store", "check_store_run"]


@dataclasses.dataclass(frozen=True)
class StorePlan:
    """What run ``seed`` of a ``"dp_axi"`` case drew."""

    frames: np.ndarray = dataclasses.field(repr=False, compare=False)
    latency: tuple[int, int]
    write_latency: tuple[int, int]
    axi_ready: float
    axi_valid: float
    valid_gap: float
    ready_pause: float
    base: int
    #: ((code "SLVERR" / "DECERR", direction "read" / "write"), …) injected at ``slot``
    errors: tuple = ()
    slot: int = 0
    #: the frame from whose first pixel on the slot's next read / write fails
    target: int = 0

    def slots(self, pixels: int) -> tuple[int, ...]:
        """The slot of each error: :attr:`slot`, and half a frame further for a second."""
        return tuple((self.slot + i * (pixels // 2)) % pixels for i in range(len(self.errors)))

    @property
    def notes(self) -> tuple[str, ...]:
        out = [f"gaps {self.valid_gap:.2f}, back-pressure {self.ready_pause:.2f}",
               f"read latency {self.latency[0]} … {self.latency[1]}, write response "
               f"{self.write_latency[0]} … {self.write_latency[1]}",
               f"AXI ready {self.axi_ready:.2f}, valid {self.axi_valid:.2f}, base {self.base:#x}"]
        pixels = self.frames.shape[1] * self.frames.shape[2]
        out += [f"{code} on the first {direction} of slot {slot} from frame {self.target}"
                for (code, direction), slot in zip(self.errors, self.slots(pixels))]
        return tuple(out)


def draw_store_run(case, seed: int) -> StorePlan:
    """Run ``seed`` of ``case`` (see the module doc), from the seed only."""
    from dptbd.sim.campaign.draw import MAX_STALL, hostile_frames

    cfg, store = case.cfg, store_config(case)
    rng = np.random.default_rng([seed, 0xA715])
    frames = hostile_frames(cfg, case.frames, rng)
    faults = [f for f in case.faults if f in STORE_FAULTS]
    # consecutive seeds: each class in turn (error runs, on the Amaranth simulator: 0 or
    # 1 … 99 cycles, in turn every fourth seed)
    lo_c, hi_c = LATENCY_DRAW[seed // 4 % 2] if faults else LATENCY_DRAW[seed % 4]
    lo, hi = sorted(int(v) for v in rng.integers(lo_c, hi_c + 1, size=2))
    wl = tuple(sorted(int(v) for v in rng.integers(0, max(hi, 1) + 1, size=2)))
    axi_ready, axi_valid = (1.0 if rng.random() < 0.3 else float(rng.uniform(0.3, 1.0))
                            for _ in range(2))
    gap, pause = (0.0 if rng.random() < 0.3 else float(rng.uniform(0.0, MAX_STALL))
                  for _ in range(2))
    pages = max(1, (1 << min(store.address_bits, 24)) - store.frame_bytes) // store.burst_bytes
    base = int(rng.integers(0, min(pages, 4 * 4096 // store.burst_bytes))) * store.burst_bytes
    errors, slot, target = (), 0, 0
    if faults:
        # consecutive seeds: each (code, direction) in turn, about half with the other
        # direction failing too (its code drawn)
        codes = ("SLVERR", "DECERR")
        fault = faults[seed // 2 % len(faults)]
        errors = ((codes[seed % 2], fault.split("_")[0]),)
        for other in faults:
            if other != fault and rng.random() < 0.5:
                errors += ((codes[int(rng.integers(0, 2))], other.split("_")[0]),)
        slot = int(rng.integers(0, cfg.width * cfg.height))
        target = int(rng.integers(1, max(2, case.frames - 1)))
    return StorePlan(frames, (lo, hi), wl, axi_ready, axi_valid, gap, pause, base, errors,
                     slot, target)


def boundary_bursts(store, base: int, frames: int) -> int:
    """The bursts of one direction ending at a 4 KB boundary in ``frames`` frames: the
    port reads and writes every slot of the region once a frame in bursts aligned to the
    burst size, so one burst ends at each multiple of 4096 in (base, base + frame_bytes]."""
    top = base + store.frame_bytes
    return frames * (top // 4096 - base // 4096)


def build_store(case, root=None):
    """The Verilator build of ``case`` (none for an error case: Amaranth simulator)."""
    if any(f in STORE_FAULTS for f in case.faults):
        return None
    from dptbd.sim.verilator import dp_axi
    return dp_axi.build(store_config(case), root=root, family=case.family)


def check_store_run(case, seed: int, root=None):
    """Draw, run and check run ``seed`` of ``case`` (see the module doc); the
    :class:`~dptbd.sim.campaign.results.RunOutcome` with its bins."""
    from dptbd.sim.campaign.results import RunOutcome
    from dptbd.sim.coverage.bins.store import store_bins

    start = time.perf_counter()
    plan = draw_store_run(case, seed)
    if plan.errors:
        passed, report, words, cycles, sim_seconds, observed = _check_errors(case, plan, seed)
    else:
        passed, report, words, cycles, sim_seconds, observed = _check_verilator(
            case, plan, seed, root)
    bins = store_bins(plan, passed=passed, observed=observed)
    return RunOutcome(case.name, seed, passed, report, words, words, cycles, sim_seconds,
                      time.perf_counter() - start, plan.notes, bins)


def _mismatch(cfg, outputs: np.ndarray, expected: np.ndarray, skip=()) -> str:
    """The first word of ``outputs`` differing from ``expected`` outside the frames ``skip``,
    by frame, row, column and field; "" if none (and as many words)."""
    from dptbd.sim.scoreboard import compare_word

    size = cfg.width * cfg.height
    n = min(len(outputs), len(expected))
    keep = np.ones(n, dtype=bool)
    for f in skip:
        keep[f * size:(f + 1) * size] = False
    diff = np.flatnonzero((outputs[:n] != expected[:n]) & keep)
    if len(diff):
        i = int(diff[0])
        return str(compare_word(cfg, i, int(outputs[i]), int(expected[i])))
    if len(outputs) != len(expected):
        return f"{len(outputs)} output words, expected {len(expected)}"
    return ""


def _check_verilator(case, plan: StorePlan, seed: int, root):
    from dptbd.sim.coverage.bins.store import OBSERVED
    from dptbd.sim.scoreboard import expected_words
    from dptbd.sim.verilator import dp_axi

    cfg, store = case.cfg, store_config(case)
    sim = dp_axi.build(store, root=root, family=case.family)
    if plan.base != store.base_address:
        sim = dataclasses.replace(sim, store=dataclasses.replace(store, base_address=plan.base))
    run = dp_axi.run(sim, plan.frames, latency=plan.latency, write_latency=plan.write_latency,
                     axi_ready=plan.axi_ready, axi_valid=plan.axi_valid,
                     valid_gap=plan.valid_gap, ready_pause=plan.ready_pause, seed=seed)
    r = run.result
    expected = np.asarray(expected_words(cfg, plan.frames), dtype=np.uint64).reshape(-1)
    report = _mismatch(cfg, run.outputs, expected)
    if r["status"] != "done":
        report = report or f"status {r['status']} after {int(r['cycles'])} cycles"
    elif int(r["violations"]):
        report = f"{int(r['violations'])} AXI4 rule violations, the first: {r['first_violation']}"
    elif int(r["read_errors"]) or int(r["write_errors"]):
        report = (f"read_error {int(r['read_errors'])}, write_error {int(r['write_errors'])} "
                  f"cycles with an OKAY memory")
    observed = {name: int(r[name]) for name in OBSERVED}
    want = boundary_bursts(sim.store, plan.base, case.frames)
    # the read-ahead may also fetch the start of a frame after the last (less than a frame)
    ahead = boundary_bursts(sim.store, plan.base, 1)
    for direction, most in (("read", want + ahead), ("write", want)):
        seen = observed[f"{direction}_boundary_bursts"]
        if not report and not want <= seen <= most:
            report = (f"{seen} {direction} bursts ended at a 4 KB boundary, the layout "
                      f"gives {want if most == want else f'{want} … {most}'}")
    return (not report, report, len(run.outputs), int(r["cycles"]), float(r["seconds"]),
            observed)


def _check_errors(case, plan: StorePlan, seed: int):
    """The error run on the Amaranth simulator (see the module doc)."""
    import random

    from amaranth.sim import Simulator

    from dptbd.hw.axi_store.bus import RESP_DECERR, RESP_SLVERR
    from dptbd.hw.axi_store.pipeline import DPPipelineAxi
    from dptbd.sim.axi4_memory import Axi4Memory
    from dptbd.sim.scoreboard import expected_words
    from dptbd.sim.stimulus import pixel_words

    cfg = case.cfg
    store = dataclasses.replace(store_config(case), base_address=plan.base)
    dut = DPPipelineAxi(store)
    code = {"SLVERR": RESP_SLVERR, "DECERR": RESP_DECERR}
    by_direction = {direction: code[c] for c, direction in plan.errors}
    memory = Axi4Memory(dut, store, seed=seed, latency=plan.latency,
                        write_latency=plan.write_latency, ready=plan.axi_ready,
                        valid=plan.axi_valid, once=True)
    words = [int(w) for w in pixel_words(cfg, plan.frames)]
    size = cfg.width * cfg.height
    armed = {}                                # byte address: code, one slot per direction
    for (name, direction), slot in zip(plan.errors, plan.slots(size)):
        address = plan.base + slot * store.frame.state_slot_bits // 8
        armed[address] = code[name]
        memory.used.add((address, "write" if direction == "read" else "read"))
    limit = len(words) * (8 + plan.latency[1] + plan.write_latency[1]) + 10_000
    state = dict(outputs=[], cycles=0, pulses={"read": [], "write": []}, timeout=False)
    rng = random.Random(seed)

    async def bench(ctx):
        payload_in = dut.pixels.payload.as_value()
        payload_out = dut.states.payload.as_value()
        accepted, offering = 0, False
        while len(state["outputs"]) < len(words):
            if accepted == plan.target * size and not memory.errors:
                memory.errors.update(armed)                           # from here on
            if state["cycles"] >= limit:
                state["timeout"] = True
                return
            if not offering and accepted < len(words):
                offering = rng.random() >= plan.valid_gap
                if offering:
                    ctx.set(payload_in, words[accepted])
            taking = rng.random() >= plan.ready_pause
            ctx.set(dut.pixels.valid, offering)
            ctx.set(dut.states.ready, taking)
            for direction in ("read", "write"):
                if ctx.get(getattr(dut, f"{direction}_error")):
                    state["pulses"][direction].append(accepted)
            took = offering and ctx.get(dut.pixels.ready)
            if taking and ctx.get(dut.states.valid):
                state["outputs"].append(int(ctx.get(payload_out)))
            await ctx.tick()
            state["cycles"] += 1
            if took:
                accepted += 1
                offering = False

    sim = Simulator(dut)
    sim.add_clock(1e-8)
    sim.add_testbench(bench)
    sim.add_testbench(memory.process(), background=True)
    t0 = time.perf_counter()
    sim.run()
    seconds = time.perf_counter() - t0
    outputs = np.array(state["outputs"], dtype=np.uint64)
    expected = np.asarray(expected_words(cfg, plan.frames), dtype=np.uint64).reshape(-1)
    pulses = state["pulses"]
    report = ""
    if state["timeout"]:
        report = f"timeout after {state['cycles']} cycles: {len(outputs)} of {len(words)} out"
    for direction in ("read", "write"):
        want = int(direction in by_direction)
        if not report and len(pulses[direction]) != want:
            report = (f"{direction}_error pulsed {len(pulses[direction])} times, expected "
                      f"{want}")
    if not report:
        # the failed transfers are frame target - 1's write or target's, frame target's read
        # or target + 1's: frames target … the end of target + 1's segment may differ
        k, t = cfg.segment_frames, plan.target
        report = _mismatch(cfg, outputs, expected, skip=range(t, ((t + 1) // k + 1) * k))
    mem_stats = memory.stats
    # the Amaranth model counts bursts only: these runs fill no stall or boundary bin
    return (not report, report, len(outputs), state["cycles"], seconds,
            {"read_bursts": int(mem_stats["read_bursts"]),
             "write_bursts": int(mem_stats["write_bursts"])})

