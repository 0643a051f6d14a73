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
* with the faults ``"read_error"`` / ``"write_error"`` (:data:`STORE_FAULTS`), runs on the
  Amaranth simulator with :class:`~dptbd.sim.axi4_memory.Axi4Memory` (its errors are tied to
  a slot's address; the C++ model's to a window of cycles), which answers the first read
  beat and / or the first write burst touching a random slot (a second error: the slot half
  a frame further) from the first pixel of a random frame t on with SLVERR or DECERR (seed
  mod 4 picks one of the four (code, direction) pairs, the other direction fails too in
  about half the runs); the promise of ``docs/integration.md`` ("State store in external
  memory") is checked: each error pulses ``read_error`` / ``write_error`` exactly once,
  every pixel still comes out (the core never waits on a failed transfer), the frames before
  t and every frame from the segment after t + 1's on are bit-exact (the failed transfers
  are frame t - 1's or t's write, t's or t + 1's read).

The ``"axi_store"`` cases (:func:`axi_store_cases`) run the drop-in core ``dptbd_axi``
built with ``--state-store axi`` on Verilator (``dptbd.sim.verilator.build(cfg, "axi",
state_store=...)``, the harness's C++ memory model on its state port, which forgets every
burst in flight while ``aresetn`` is low, as AXI4 lets a reset abandon them): each run is an
``"axi"`` case's run of :func:`dptbd.sim.axi.runs.draw_run` — frame-sync faults, soft resets
(after the pipeline drained and with words in flight), ``aresetn`` pulses after the pipeline
drained and with words and bursts in flight at a beat drawn anywhere in a frame, run-time
settings, LUT writes, counter clears — with the memory of :func:`draw_memory` (a read
latency class in turn, write-response latency, random AXI ready / valid) and
:func:`dptbd.sim.verilator.axi.check_axi` scores every candidate word, flag, response and
counter, with no AXI4 rule broken and no burst left in flight at the end; their ``store``
bins are the memory model's observations; the refused bus accesses (``"bus"``) are drawn
on the store build's register map (:class:`~dptbd.sim.axi.actions.Drawer`: its registers
not unmapped, read by the checks, and refused ``STATE_BASE`` writes, unaligned or out of
range). An ``"axi_store"`` case with the faults ``"read_error"`` / ``"write_error"``
draws error runs instead (:func:`draw_error_window`): a clean hostile stream with input gaps
and back-pressure, the memory above, and every burst whose address handshake falls in a
window of cycles answered SLVERR or DECERR (reads, writes or both in turn by seed mod 3, the
response in turn by seed mod 2; the window spans 1 … 6 bursts from the first of its
direction after a drawn fraction of the run, found in a first run without errors:
:func:`window_cycles`); the run passes when the stream never stops (every beat taken, every
list sent), no AXI4 rule broke, ``STATE_READ_ERRORS`` / ``STATE_WRITE_ERRORS`` count what
the memory sent (at least one error), the ``ERROR`` bits are set exactly for the directions
that failed, ``LISTS`` counts every list, and every list of a segment that neither it nor
the segment before came near the window (its pixels accepted more than :func:`error_margin`
pixels away from those accepted in it) is the model's, the last segment's among them
(``docs/integration.md``, "State store in external memory").
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np

__all__ = ["STORE_FAULTS", "StorePlan", "draw_store_run", "check_store_run", "store_cases",
           "boundary_bursts", "MemoryPlan", "draw_memory", "axi_store_cases",
           "check_axi_store_run", "ErrorWindow", "draw_error_window", "window_cycles",
           "error_margin"]

#: Fault classes of a ``"dp_axi"`` case.
STORE_FAULTS = ("read_error", "write_error")

#: Read latency ranges of the classes (:data:`dptbd.sim.coverage.bins.store.LATENCY_CLASSES`)
#: a run draws from.
_LATENCY_DRAW = ((0, 0), (1, 99), (100, 499), (500, 700))


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


def _store(case):
    return case.cfg.axi_store(**dict(case.store or {}))


def draw_store_run(case, seed: int) -> StorePlan:
    """Run ``seed`` of ``case`` (see the module doc), from the seed only."""
    from dptbd.sim.campaign.draw import MAX_STALL, hostile_frames

    cfg, store = case.cfg, _store(case)
    rng = np.random.default_rng([seed, 0xA715])
    frames = hostile_frames(cfg, case.frames, rng)
    faults = [f for f in case.faults if f in STORE_FAULTS]
    # consecutive seeds: each class in turn (error runs, on the Amaranth simulator: 0 or
    # 1 … 99 cycles, in turn every fourth seed)
    lo_c, hi_c = _LATENCY_DRAW[seed // 4 % 2] if faults else _LATENCY_DRAW[seed % 4]
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


def store_cases():
    """The ``"dp_axi"`` cases of the default campaign (``docs/gateware.md``, "Verification
    campaign"): a 64 × 48 frame (6 KB of state: bursts at 4 KB boundaries) on a 32-bit bus
    with 8-beat bursts, a 40 × 24 r = 2 one on a 64-bit bus with 4-beat bursts and one
    burst in flight, and the error case on the Amaranth simulator (16 × 12)."""
    from dptbd.sim.campaign.cases import Case

    return [
        Case("dp-axi-64x48-k4-d32-b8-o4", dict(width=64, height=48, segment_frames=4),
             "dp_axi", 16, 8, store=dict(data_bits=32, burst_beats=8, outstanding=4)),
        Case("dp-axi-40x24-r2-k3-d64-b4-o1", dict(width=40, height=24, segment_frames=3,
                                                  radius=2, weight_frac_bits=6),
             "dp_axi", 20, 8, store=dict(data_bits=64, burst_beats=4, outstanding=1)),
        Case("dp-axi-16x12-k2-errors", dict(width=16, height=12, segment_frames=2),
             "dp_axi", 6, 4, STORE_FAULTS, store=dict(data_bits=64, burst_beats=4,
                                                      outstanding=2)),
    ]


def build_store(case, root=None):
    """The Verilator build of ``case`` (none for an error case: Amaranth simulator)."""
    if any(f in STORE_FAULTS for f in case.faults):
        return None
    from dptbd.sim.verilator import dp_axi
    return dp_axi.build(_store(case), root=root)


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

    cfg, store = case.cfg, _store(case)
    sim = dp_axi.build(store, root=root)
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
    store = dataclasses.replace(_store(case), base_address=plan.base)
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


# ---- dptbd_axi --state-store axi: the AXI cases' runs with resets, on the store build ------

@dataclasses.dataclass(frozen=True)
class MemoryPlan:
    """What run ``seed`` of an ``"axi_store"`` case drew for its memory (no errors)."""

    latency: tuple[int, int]
    write_latency: tuple[int, int]
    axi_ready: float
    axi_valid: float
    errors: tuple = ()

    def memory(self) -> dict:
        """:func:`dptbd.sim.verilator.axi.run_axi`'s ``memory``."""
        return dict(latency=self.latency, write_latency=self.write_latency,
                    axi_ready=self.axi_ready, axi_valid=self.axi_valid)

    @property
    def notes(self) -> tuple[str, ...]:
        return (f"read latency {self.latency[0]} … {self.latency[1]}, write response "
                f"{self.write_latency[0]} … {self.write_latency[1]}",
                f"AXI ready {self.axi_ready:.2f}, valid {self.axi_valid:.2f}")


def draw_memory(seed: int) -> MemoryPlan:
    """The memory of run ``seed``: a read latency class in turn (seed mod 4), a range inside
    it, a write-response range, the AXI ready and valid probabilities (as
    :func:`draw_store_run`)."""
    rng = np.random.default_rng([seed, 0xA716])
    lo_c, hi_c = _LATENCY_DRAW[seed % 4]
    lo, hi = sorted(int(v) for v in rng.integers(lo_c, hi_c + 1, size=2))
    wl = tuple(sorted(int(v) for v in rng.integers(0, max(hi, 1) + 1, size=2)))
    axi_ready, axi_valid = (1.0 if rng.random() < 0.3 else float(rng.uniform(0.3, 1.0))
                            for _ in range(2))
    return MemoryPlan((lo, hi), wl, axi_ready, axi_valid)


def axi_store_cases():
    """The ``"axi_store"`` cases of the default campaign: the small ``"axi"`` case's
    parameter set (24 × 16, K = 2 of K_max 4, F = 0, B_E = 9, n = 3 of C = 6) with its state
    in AXI4 memory on a 32-bit bus, 4-beat bursts, 2 in flight: the AXI runs with resets,
    and (the same build) SLVERR / DECERR windows."""
    from dptbd.sim.axi.runs import AXI_FAULTS
    from dptbd.sim.campaign.cases import Case

    frame = dict(width=24, height=16, segment_frames=2, max_segment_frames=4,
                 weight_frac_bits=0, energy_bits=9, candidate_count=3, candidate_capacity=6,
                 histogram_bits=6, histogram_shift=2)
    store = dict(data_bits=32, burst_beats=4, outstanding=2)
    return [
        Case("axi-store-24x16-f0-k2", dict(frame), "axi_store", 40, 8, AXI_FAULTS,
             store=dict(store)),
        Case("axi-store-24x16-f0-k2-errors", dict(frame), "axi_store", 16, 6, STORE_FAULTS,
             store=dict(store)),
    ]


def build_axi_store(case, root=None):
    """The Verilator build of an ``"axi_store"`` case."""
    from dptbd.sim.verilator import build

    return build(case.cfg, "axi", root=root, state_store=_store(case))


def check_axi_store_run(case, seed: int, root=None):
    """Draw, run and check run ``seed`` of an ``"axi_store"`` case (see the module doc):
    the :class:`~dptbd.sim.campaign.results.RunOutcome` with its ``axi`` and ``store``
    bins."""
    import warnings

    from dptbd.config import EnergyWidthWarning
    from dptbd.sim.axi.runs import draw_run
    from dptbd.sim.campaign.results import RunOutcome
    from dptbd.sim.coverage.bins import axi_bins
    from dptbd.sim.coverage.bins.store import store_bins
    from dptbd.sim.verilator.axi import check_axi

    start = time.perf_counter()
    if any(f in STORE_FAULTS for f in case.faults):
        passed, report, words, cycles, seconds, flagged, counters, notes = _check_error_run(
            case, seed, root)
        memory = dataclasses.replace(draw_memory(seed), errors=flagged)
        return RunOutcome(case.name, seed, passed, f"seed {seed}: {report}" if report else "",
                          case.frames * case.cfg.width * case.cfg.height, words, cycles,
                          seconds, time.perf_counter() - start, notes,
                          store_bins(memory, passed=passed, observed=counters))
    sim = build_axi_store(case, root)
    plan = draw_run(case, seed)
    memory = draw_memory(seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        result = check_axi(sim, plan.beats, plan.steps, valid_gap=plan.valid_gap,
                           ready_pause=plan.ready_pause, seed=seed, pulses=plan.pulses,
                           memory=memory.memory())
        bins = axi_bins(case.cfg, plan.beats, plan.steps, passed=result.passed,
                        latency=sim.latency, valid_gap=plan.valid_gap,
                        ready_pause=plan.ready_pause, run=result.run, store=sim.state_store)
    if "bus" not in case.faults:
        # refusals only the raw accesses reach: not declared (a refused LUT strobe comes
        # from the LUT writes)
        from dptbd.sim.coverage.bins.groups import BUS_REASONS, key

        for reason in BUS_REASONS[1:]:
            bins.pop(key("register", reason), None)
    bins.update(store_bins(memory, passed=result.passed, observed=result.run.counters))
    report = "" if result.passed else f"seed {seed}: {result.report()}"
    return RunOutcome(case.name, seed, result.passed, report, len(plan.beats),
                      len(result.run.out_words) + len(result.run.op_resp), result.run.cycles,
                      result.run.sim_seconds, time.perf_counter() - start,
                      plan.notes + memory.notes, bins)


# ---- dptbd_axi --state-store axi: SLVERR / DECERR windows -------------------------------------

@dataclasses.dataclass(frozen=True)
class ErrorWindow:
    """The error window of an ``"axi_store"`` error run, as drawn: where it falls in the
    run's bursts (:func:`window_cycles`) and the response its bursts get."""

    directions: tuple[str, ...]     # "read", "write" or both
    at: float                       # the window opens at the first burst of a direction
    bursts: int                     # after the pixel at this fraction of the run, and
                                    # closes after this many bursts (any direction)
    valid_gap: float
    ready_pause: float
    response: str = "SLVERR"        # "SLVERR" or "DECERR"


def draw_error_window(case, seed: int) -> ErrorWindow:
    """Run ``seed``'s window: the directions in turn (seed mod 3: read, write, both), the
    response in turn (seed mod 2: SLVERR, DECERR; seeds 0 … 5 give each pair), input
    gaps and back-pressure (each 0 in 30 % of the runs, else uniform in [0, 0.5)), where it
    opens (uniform in [0.2, 0.6) of the run's pixels) and how many bursts it spans (1 … 6)."""
    rng = np.random.default_rng([seed, 0xE770])
    directions = (("read",), ("write",), ("read", "write"))[seed % 3]
    gap, pause = (0.0 if rng.random() < 0.3 else float(rng.uniform(0.0, 0.5))
                  for _ in range(2))
    return ErrorWindow(directions, float(rng.uniform(0.2, 0.6)), int(rng.integers(1, 7)),
                       gap, pause, ("SLVERR", "DECERR")[seed % 2])


def window_cycles(window: ErrorWindow, bursts: np.ndarray, accepted: np.ndarray
                  ) -> tuple[int, int]:
    """``[from, to)`` cycles of ``window`` in a run without errors whose address handshakes
    are ``bursts`` (rows cycle, is_write, address) and pixels were accepted in the cycles
    ``accepted``: from the first burst of one of its directions at or after the pixel at
    ``window.at`` of the run to just after ``window.bursts`` bursts. The memory model's
    errors draw from a generator of their own, so the run with the window is the same run."""
    after = int(accepted[int(window.at * len(accepted))])
    kinds = [d == "write" for d in window.directions]
    rows = np.flatnonzero((bursts[:, 0] >= after) & np.isin(bursts[:, 1], kinds))
    if not len(rows):
        raise ValueError(f"no {' or '.join(window.directions)} burst after cycle {after}")
    first = int(rows[0])
    last = min(first + window.bursts - 1, len(bursts) - 1)
    return int(bursts[first, 0]), int(bursts[last, 0]) + 1


def error_margin(store, latency: int) -> int:
    """Pixels, each side of those accepted in the window, whose states a failed transfer may
    touch: the read-ahead and write-behind (``2 · outstanding`` bursts of ``burst_states``,
    two bursts of packing) and the pipeline's ``latency``."""
    return 2 * (store.outstanding + 2) * store.burst_states + latency


def _check_error_run(case, seed: int, root):
    """An ``"axi_store"`` error run (see the module doc): (passed, report, words, cycles,
    sim seconds, errors flagged ((code, direction), …), memory counters, notes)."""
    from dptbd.hw.flow.register_export import constants_namespace
    from dptbd.sim.axi.stimulus import clean_beats, expected_outputs
    from dptbd.sim.campaign.draw import hostile_frames
    from dptbd.sim.candidate_scoreboard import list_words
    from dptbd.sim.verilator.axi import run_axi

    sim = build_axi_store(case, root)
    cfg, store = sim.cfg, sim.state_store
    regs = constants_namespace(cfg, store)
    frames = hostile_frames(cfg, case.frames, np.random.default_rng([seed, 0xE771]))
    beats = clean_beats(frames)
    window = draw_error_window(case, seed)
    memory = draw_memory(seed)
    reads = ["ERROR", "STATE_READ_ERRORS", "STATE_WRITE_ERRORS", "LISTS"]
    ops = [(len(beats), "i", sim.latency + 64 + memory.latency[1] + memory.write_latency[1],
            0), *[(len(beats), "r", getattr(regs, f"REG_{name}"), 0) for name in reads]]
    stalls = dict(valid_gap=window.valid_gap, ready_pause=window.ready_pause, seed=seed)
    clean = run_axi(sim, beats, ops, memory=memory.memory(), **stalls)
    cycles = window_cycles(window, clean.bursts, clean.accept_cycles)
    setting = dict(memory.memory(), error_cycles=cycles, error_response=window.response,
                   **{f"{d}_error": 1.0 for d in window.directions})
    run = run_axi(sim, beats, ops, memory=setting, **stalls)
    c = run.counters
    got = dict(zip(reads, (int(v) for v in run.op_data)))
    sent = {"read": int(c.get("read_error_beats", 0)),
            "write": int(c.get("write_error_bursts", 0))}
    expected = list_words(cfg, expected_outputs(cfg, beats, [{"stop": len(beats)}]).lists)
    delivered, current = [], []
    for word, flag in zip(run.out_words, run.out_flags):
        current.append(int(word))
        if int(flag) & 2:
            delivered.append(current)
            current = []
    report = ""
    if run.status != "done" or int(c["accepted"]) != len(beats):
        report = f"status {run.status}: {c['accepted']} of {len(beats)} beats accepted"
    elif c.get("violations"):
        report = f"{c['violations']} AXI4 violations, the first: {run.first_violation}"
    elif not c.get("memory_idle"):
        report = "m_axi_state: bursts still in flight at the end"
    elif not any(sent[d] for d in window.directions):
        report = f"no burst in the window {cycles}: no error sent"
    elif (got["STATE_READ_ERRORS"], got["STATE_WRITE_ERRORS"]) != (sent["read"],
                                                                     sent["write"]):
        report = (f"STATE_READ_ERRORS {got['STATE_READ_ERRORS']}, STATE_WRITE_ERRORS "
                  f"{got['STATE_WRITE_ERRORS']}; the memory sent {sent['read']} error beats, "
                  f"{sent['write']} error responses")
    else:
        want_error = sum(getattr(regs, f"ERROR_STATE_{d.upper()}_MASK")
                         for d in ("read", "write") if sent[d])
        if got["ERROR"] != want_error:
            report = f"ERROR = {got['ERROR']:#x}, expected {want_error:#x}"
        elif not len(delivered) == len(expected) == got["LISTS"]:
            report = (f"{len(delivered)} lists delivered, LISTS = {got['LISTS']}, the model "
                      f"gives {len(expected)}")
    if not report:
        accepted = np.asarray(run.accept_cycles, dtype=np.int64)
        inside = np.flatnonzero((accepted >= cycles[0]) & (accepted < cycles[1]))
        lo = int(np.searchsorted(accepted, cycles[0]))
        hi = int(inside[-1]) if len(inside) else lo
        margin = error_margin(store, sim.latency)
        lo, hi = lo - margin, hi + margin
        segment = cfg.segment_frames * cfg.width * cfg.height
        clean = [(s + 1) * segment <= lo or s * segment > hi for s in range(len(expected))]
        exact = [j for j in range(len(expected)) if clean[j] and (j == 0 or clean[j - 1])]
        if not exact or exact[-1] != len(expected) - 1:
            report = (f"the window (pixels {lo} … {hi} with the margin) leaves no clean "
                      f"last segment of {len(expected)}: draw a shorter run")
        for j in exact:
            if not report and delivered[j] != expected[j]:
                report = f"list {j} (a segment clear of the window) differs from the model's"
    flagged = tuple((window.response, d) for d in ("read", "write") if sent[d])
    notes = (f"{window.response} on {' and '.join(window.directions)} bursts taken in cycles "
             f"[{cycles[0]}, {cycles[1]})",
             f"gaps {window.valid_gap:.2f}, back-pressure {window.ready_pause:.2f}",
             *memory.notes)
    return (not report, report, len(run.out_words) + len(run.op_resp), int(run.cycles),
            float(run.sim_seconds), flagged, c, notes)
