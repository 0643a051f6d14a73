"""The ``axi`` slice (``dptbd_axi``): seeded runs of
:func:`dptbd.sim.verilator.axi.check_axi` (every fault class, settings and LUT writes,
refused writes, W1C, soft reset, register reads, gaps and back-pressure), random AXI runs
of the campaign (:func:`dptbd.sim.axi.runs.draw_run`), runs with a random LUT at K_max
(:func:`lut_scenario`), one long run of the counters and the stall cycles
(:func:`counter_plan`) and two runs of exact cycles: ``irq`` after every IRQ_ENABLE and
IRQ_STATUS write (:func:`irq_plan`) and the first beat taken after a soft reset
(:func:`restart_plan`); a sweep of the whole register address space (:func:`decode_steps`) and
a run through many values of n (:func:`n_steps`) and one of 2**21 cycles of output
back-pressure (:func:`stall_plan`); ``noise`` runs under the build's LUT
(:func:`noise_steps`); settings written inside a segment that a resync then ends
(:func:`resync_steps`); the LUT written from its last entry to its first
(:func:`lut_scenario`, ``lut-reverse``); 8 292 one-frame lists read at both clock
parities (:func:`lists_plan`)."""

from __future__ import annotations

from dptbd.config import DPConfig
from dptbd.sim.mutation.slices import BACKPRESSURE, CONFIGS
from dptbd.sim.mutation.verdict import hang_verdict

__all__ = ["RANDOM_AXI_RUNS", "RANDOM_AXI_FRAMES", "LUT_RUNS", "COUNTER_FRAMES",
           "COUNTER_READS", "IRQ_WRITES", "RESTART_DELAY", "RUNS", "axi_scenario",
           "lut_scenario", "counter_plan", "irq_plan", "restart_plan", "N_VALUES",
           "decode_steps", "n_steps", "STALL_CYCLES", "stall_plan", "noise_steps", "resync_steps", "LIST_COUNT", "lists_plan", "run"]

#: Random AXI runs of the ``axi`` slice (:func:`dptbd.sim.axi.runs.draw_run` on the slice's
#: configuration, :data:`RANDOM_AXI_FRAMES` frames each): every refused access class,
#: soft resets with words in flight, aresetn, W1C, clear_counters, LUT and settings writes,
#: every register read with its expected value.
RANDOM_AXI_RUNS, RANDOM_AXI_FRAMES = 32, 24

#: Frames of the ``counters`` run: K = 1 and n = 0 (each frame a segment, each list its
#: trailer), so that FRAMES, SEGMENTS and LISTS pass 2**10 (bit 19 of FRAMES would take
#: 2**19 frames, 63 M cycles: not in the slice); at full speed without back-pressure the
#: input stalls exactly ``scan_cycles`` = 2**b + 4 cycles after each list (the histogram
#: scan, ``docs/gateware.md``, "Timing"), the output never.
COUNTER_FRAMES = 1100

#: ``lut`` runs of the slice (:func:`lut_scenario`): a random LUT read at every energy.
LUT_RUNS = 16

#: The runs of the slice: ``(kind, seed)``, in this order.
RUNS = tuple([("faults", s) for s in range(16)]
             + [("backpressure", s) for s in (1, 4, 7, 14)]
             + [("random", s) for s in range(RANDOM_AXI_RUNS)]
             + [("lut", s) for s in range(LUT_RUNS)]
             + [("counters", 0), ("irq", 0), ("restart", 0), ("decode", 0),
                ("n-values", 0), ("noise", 0), ("noise", 1),
                *(("resync", s) for s in range(6)),
                ("lut-reverse", 0), ("lut-reverse", 1), ("stalls", 0), ("lists", 0)])


def lut_scenario(cfg: DPConfig, seed: int, reverse: bool = False) -> tuple:
    """The beats and steps of ``lut`` run ``seed``: 16 frames of two targets (even seeds) or
    the mixed scene, K = K_max (the largest energies, where a weight's last bit shows in
    the weighted sum), n = C, and a random LUT (codes in [0, 2**F]) from the first beat;
    ``reverse``: its entries written from the last address to the first (a write that
    also reaches a later entry is then not overwritten by that entry's own write)."""
    import numpy as np

    from dptbd.sim.axi.stimulus import clean_beats
    from dptbd.sim.scenarios import make_frames

    rng = np.random.default_rng([seed, 0xA75])
    frames = make_frames("two-targets" if seed % 2 == 0 else "mixed", cfg, 16, seed=seed)
    beats = clean_beats(frames)
    unity = 1 << cfg.weight_frac_bits
    codes = rng.integers(0, unity + 1, size=(cfg.n_moves + 1, cfg.n_moves)).tolist()
    steps = [{"writes": [["SEGMENT_FRAMES", cfg.k_max],
                         ["CANDIDATE_COUNT", cfg.record_capacity]],
              "stop": len(beats)}]
    if reverse:
        steps[0]["lut_writes"] = [[p, m, codes[p][m], 0xF]
                                  for p in reversed(range(cfg.n_moves + 1))
                                  for m in reversed(range(cfg.n_moves))]
    else:
        steps[0]["lut_codes"] = codes
    return beats, steps

#: What the ``counters`` run reads at its end.
COUNTER_READS = ("FRAMES", "SEGMENTS", "LISTS", "SATURATED", "INPUT_STALLS", "OUTPUT_STALLS")

_COUNTER_PLANS: dict = {}


def counter_plan(cfg: DPConfig) -> tuple:
    """The ``counters`` run for ``cfg`` (cached: the model of its :data:`COUNTER_FRAMES`
    frames takes seconds): the beats, the operations (K = 1, n = 0, then after the last
    beat and the settle reads of FRAMES, SEGMENTS, LISTS, SATURATED, INPUT_STALLS and
    OUTPUT_STALLS), the model's words and the values those reads must give."""
    if repr(cfg) not in _COUNTER_PLANS:
        import numpy as np

        from dptbd.hw.flow.register_export import constants_namespace
        from dptbd.hw.segmenter import scan_cycles
        from dptbd.sim.axi.stimulus import clean_beats, expected_outputs
        from dptbd.sim.candidate_scoreboard import list_words
        from dptbd.sim.verilator.axi import CUT_COUNTERS

        regs = constants_namespace(cfg)
        rng = np.random.default_rng([0, 0xA74])
        frames = rng.integers(0, 1 << cfg.input_bits, size=(COUNTER_FRAMES, cfg.height,
                                                             cfg.width))
        beats = clean_beats(frames)
        steps = [{"writes": [["SEGMENT_FRAMES", 1], ["CANDIDATE_COUNT", 0]],
                  "stop": len(beats)}]
        expected = expected_outputs(cfg, beats, steps, cut_lists=True)
        words = [w for lst in list_words(cfg, expected.lists) for w in lst]
        counts = expected.counters()
        ops = [(0, "w", regs.REG_SEGMENT_FRAMES, 1), (0, "w", regs.REG_CANDIDATE_COUNT, 0),
               (len(beats), "i", 64, 0)]
        ops += [(len(beats), "r", getattr(regs, f"REG_{name}"), 0)
                for name in COUNTER_READS]
        want = [*(counts[n] for n in CUT_COUNTERS), (counts["LISTS"] - 1) * scan_cycles(cfg), 0]
        _COUNTER_PLANS[repr(cfg)] = (beats, ops, words, want)
    return _COUNTER_PLANS[repr(cfg)]


def _counters_run(sim) -> tuple[str, str]:
    """The ``counters`` run: every word the model's (each a list's trailer, ``tuser[0]``
    and ``tlast`` set), both writes OKAY, the counters the model's counts."""
    import numpy as np

    from dptbd.sim.verilator.axi import run_axi

    beats, ops, words, counts = counter_plan(sim.cfg)
    run = run_axi(sim, beats, ops)
    problems = []
    if run.status != "done" or int(run.counters.get("accepted", -1)) != len(beats):
        problems.append(f"{run.status}: {run.counters.get('accepted')} of {len(beats)} "
                        "beats accepted")
    got = [int(w) for w in run.out_words]
    if got != words:
        bad = next((i for i, (a, b) in enumerate(zip(got, words)) if a != b),
                   min(len(got), len(words)))
        problems.append(f"{len(got)} words, the model gives {len(words)}; first difference "
                        f"at word {bad}")
    if not np.all(np.asarray(run.out_flags) == 3):
        problems.append("a list's word without tuser[0] and tlast")
    if list(run.op_resp) != [0] * (2 + len(COUNTER_READS)):
        problems.append(f"responses {list(run.op_resp)}")
    reads = [int(v) for v in run.op_data[2:]]
    if reads != counts:
        problems.append(f"{', '.join(COUNTER_READS)} read {reads}, expected {counts}")
    if run.status != "done" and not problems[1:]:
        return "timeout", "; ".join(problems)
    return ("killed" if problems else "survived"), "; ".join(problems) or "passed"


def axi_scenario(cfg: DPConfig, seed: int) -> tuple:
    """The beats, steps and stimulus of AXI run ``seed``: two clean segments and every fault
    class (:func:`dptbd.sim.axi.stimulus.with_fault`), K / n / s writes (one refused), the
    LUT rewritten, ERROR W1C, a soft reset, register checks; gaps and back-pressure from the
    seed."""
    import numpy as np

    from dptbd.hw.flow.register_export import constants_namespace
    from dptbd.hw.register_map import FAULTS, register_map
    from dptbd.sim.axi.stimulus import fault_stretches
    from dptbd.sim.scenarios import make_frames

    rng = np.random.default_rng([seed, 0xA71])
    regs = constants_namespace(cfg)
    frames = make_frames("two-targets" if seed % 2 == 0 else "mixed", cfg,
                         4 + 2 * len(FAULTS), seed=seed)
    beats, starts = fault_stretches(cfg, frames)
    frame = cfg.width * cfg.height
    every = sum(getattr(regs, f"ERROR_{k.upper()}_MASK") for k in FAULTS)
    unity = 1 << cfg.weight_frac_bits
    codes = rng.integers(0, unity + 1, size=(cfg.n_moves + 1, cfg.n_moves)).tolist()
    k1, k2 = (int(v) for v in rng.integers(1, cfg.k_max + 1, size=2))
    n1 = int(rng.integers(1, cfg.record_capacity + 1))
    s2 = int(rng.integers(0, cfg.energy_bits))
    at_reset = {r.name: sum(f.reset << f.lsb for f in r.fields)
                for r in register_map(cfg).registers if r.group != "status" or r.name in
                ("ERROR", "IRQ_STATUS", "STATUS")}
    steps = [{"check": at_reset, "writes": [["IRQ_ENABLE", 3]], "stop": 2 * frame},
             {"writes": [["SEGMENT_FRAMES", k1], ["CANDIDATE_COUNT", n1],
                         ["HISTOGRAM_SHIFT", cfg.energy_bits]], "stop": 4 * frame},
             {"check": {"ERROR": regs.ERROR_WRITE_REFUSED_MASK, "SEGMENT_FRAMES": k1,
                        "CANDIDATE_COUNT": n1, "HISTOGRAM_SHIFT": cfg.bin_shift,
                        "IRQ_ENABLE": 3, "IRQ_STATUS": 3},
              "lut_codes": codes,
              "writes": [["SEGMENT_FRAMES", k2], ["ERROR", regs.ERROR_WRITE_REFUSED_MASK]],
              "stop": starts[2]},
             {"soft_reset": True, "writes": [["HISTOGRAM_SHIFT", s2]], "stop": len(beats)},
             {"check": {"ERROR": every, "SEGMENT_FRAMES": k2, "HISTOGRAM_SHIFT": s2,
                        "STATUS": 0, "INPUT_STALLS": None, "OUTPUT_STALLS": None},
              "writes": [["ERROR", every]], "stop": len(beats)}]
    gap, pause = (float(v) for v in rng.uniform(0.0, 0.5, size=2))
    return beats, steps, gap, pause


def _axi_random_run(sim, seed: int) -> tuple[str, str]:
    from dptbd.sim.axi.runs import AXI_FAULTS, draw_run
    from dptbd.sim.campaign import Case
    from dptbd.sim.verilator.axi import check_axi

    case = Case("mutant-axi-random", CONFIGS["axi"], "axi", RANDOM_AXI_FRAMES, 1, AXI_FAULTS)
    plan = draw_run(case, seed)
    result = check_axi(sim, plan.beats, plan.steps, valid_gap=plan.valid_gap,
                       ready_pause=plan.ready_pause, seed=seed, pulses=plan.pulses)
    if hang_verdict(result.run.status, result.report()):
        return "timeout", (f"cycle budget ({result.run.cycles} cycles) ran out: "
                           f"{result.report()}")
    return ("survived" if result.passed else "killed"), result.report()


#: The writes of the ``irq`` run after its segment, both IRQ_STATUS bits pending:
#: ``(register, value, irq after it)``; ``irq`` is IRQ_STATUS & IRQ_ENABLE, so it changes
#: exactly where the value after a write differs from the value before.
IRQ_WRITES = (("IRQ_ENABLE", 1, 1), ("IRQ_ENABLE", 0, 0), ("IRQ_ENABLE", 2, 1),
              ("IRQ_ENABLE", 0, 0), ("IRQ_ENABLE", 3, 1), ("IRQ_STATUS", 1, 1),
              ("IRQ_STATUS", 2, 0), ("IRQ_ENABLE", 0, 0))


def irq_plan(cfg: DPConfig) -> tuple:
    """The ``irq`` run: a refused write of SEGMENT_FRAMES (0) sets ``ERROR.write_refused``,
    hence ``IRQ_STATUS.fault``; two frames (one segment of K = 2) set
    ``IRQ_STATUS.segment_done``; after the settle, the :data:`IRQ_WRITES`. The beats, the
    operations and, per w/r operation, the response expected."""
    import numpy as np

    from dptbd.hw.flow.register_export import constants_namespace
    from dptbd.sim.axi.stimulus import clean_beats
    from dptbd.sim.verilator.axi import OKAY, SLVERR

    regs = constants_namespace(cfg)
    rng = np.random.default_rng([0, 0xA76])
    beats = clean_beats(rng.integers(0, 1 << cfg.input_bits, size=(2, cfg.height, cfg.width)))
    end = len(beats)
    ops = [(0, "w", regs.REG_SEGMENT_FRAMES, 0), (0, "w", regs.REG_SEGMENT_FRAMES, 2),
           (end, "i", 256, 0), (end, "r", regs.REG_IRQ_STATUS, 0)]
    ops += [(end, "w", getattr(regs, f"REG_{name}"), value) for name, value, _ in IRQ_WRITES]
    responses = [SLVERR, OKAY, OKAY] + [OKAY] * len(IRQ_WRITES)
    return beats, ops, responses


def _irq_run(sim) -> tuple[str, str]:
    """The ``irq`` run: IRQ_STATUS reads 3 after the segment, every response as expected,
    and ``irq`` changes exactly in the cycles of the B responses of the
    :data:`IRQ_WRITES` that change it (the register block updates IRQ_ENABLE and
    IRQ_STATUS at the clock edge that ends the write's strobe cycle, and ``bvalid`` rises
    in the next cycle, where ``irq``, a combinational AND-OR of the two, shows the new
    value) and nowhere else."""
    from dptbd.sim.verilator.axi import run_axi

    beats, ops, responses = irq_plan(sim.cfg)
    run = run_axi(sim, beats, ops)
    problems = []
    if run.status != "done":
        problems.append(f"{run.status} after {run.cycles} cycles")
    if list(run.op_resp) != responses:
        problems.append(f"responses {list(run.op_resp)}, expected {responses}")
    elif int(run.op_data[2]) != 3:
        problems.append(f"IRQ_STATUS read {int(run.op_data[2])} after the segment, expected 3")
    else:
        level, want = 0, []
        for (_name, _value, after), cycle in zip(IRQ_WRITES, run.op_cycles[3:]):
            if after != level:
                want.append(int(cycle))
            level = after
        got = [int(c) for c in run.irq_cycles]
        if got != want:
            problems.append(f"irq changed in cycles {got}, expected {want} (the B responses "
                            "of the writes that change it)")
    return ("killed" if problems else "survived"), "; ".join(problems) or "passed"


#: Cycles from a soft reset's ``restart`` (the cut trailer's transfer, or the cycle of the
#: write's B response when no list is open) to the first beat taken after it: the input is
#: held up to ``restart`` included (``busy``), the harness offers the next beat in the
#: cycle after the write's response, and the core, reset at the end of the ``restart``
#: cycle, takes it one cycle later.
RESTART_DELAY = 2


def restart_plan(cfg: DPConfig) -> tuple:
    """The ``restart`` run: K = 1, n = C (long lists), three frames at full speed and, 10
    beats into the third, a soft reset 40 idle cycles on, while the second frame's list is
    being sent (its cut trailer is the restart); then two more frames, the settle and a
    second soft reset with no list open; one more frame. The beats, the operations, the
    beats before which the two soft resets are written, and the index of the two writes
    among the w/r operations."""
    import numpy as np

    from dptbd.hw.flow.register_export import constants_namespace
    from dptbd.sim.axi.stimulus import clean_beats

    regs = constants_namespace(cfg)
    rng = np.random.default_rng([0, 0xA77])
    beats = clean_beats(rng.integers(0, 1 << cfg.input_bits, size=(6, cfg.height, cfg.width)))
    frame = cfg.width * cfg.height
    cut_at, idle_at = 2 * frame + 10, 5 * frame
    ops = [(0, "w", regs.REG_SEGMENT_FRAMES, 1), (0, "w", regs.REG_CANDIDATE_COUNT,
                                                  cfg.record_capacity),
           (cut_at, "i", 40, 0), (cut_at, "w", regs.REG_CONTROL, regs.CONTROL_SOFT_RESET_MASK),
           (idle_at, "i", 512, 0),
           (idle_at, "w", regs.REG_CONTROL, regs.CONTROL_SOFT_RESET_MASK)]
    return beats, ops, (cut_at, idle_at), (2, 3)


def _restart_run(sim) -> tuple[str, str]:
    """The ``restart`` run: after the first soft reset the cut trailer
    (:func:`~dptbd.hw.candidate_layout.pack_cut_trailer` of the records sent) comes in the
    cycle of the write's B response, and the next beat is taken :data:`RESTART_DELAY`
    cycles after it; after the second (no list open) the next beat is taken
    :data:`RESTART_DELAY` cycles after the B response."""
    from dptbd.hw.candidate_layout import pack_cut_trailer
    from dptbd.sim.verilator.axi import run_axi

    beats, ops, (cut_at, idle_at), (first, second) = restart_plan(sim.cfg)
    run = run_axi(sim, beats, ops)
    problems = []
    if run.status != "done" or int(run.counters.get("accepted", -1)) != len(beats):
        problems.append(f"{run.status}: {run.counters.get('accepted')} of {len(beats)} "
                        "beats accepted")
    elif list(run.op_resp) != [0] * 4:
        problems.append(f"responses {list(run.op_resp)}")
    else:
        words, flags, cycles = (list(map(int, a)) for a in (run.out_words, run.out_flags,
                                                            run.out_cycles))
        done = int(run.op_cycles[first])
        at = next((j for j, c in enumerate(cycles) if c >= done), None)
        if at is None or cycles[at] != done or flags[at] & 2 == 0:
            problems.append(f"no trailer in cycle {done}, the soft reset's B response")
        else:
            start = max(j for j in range(at + 1) if flags[j] & 1)
            want = pack_cut_trailer(sim.cfg, at - start)
            if words[at] != want:
                problems.append(f"the cut trailer is {words[at]:#x}, expected {want:#x}")
            taken = int(run.accept_cycles[cut_at])
            if taken != cycles[at] + RESTART_DELAY:
                problems.append(f"after the cut trailer (cycle {cycles[at]}) beat {cut_at} "
                                f"was taken in cycle {taken}, expected "
                                f"{cycles[at] + RESTART_DELAY}")
        done = int(run.op_cycles[second])
        taken = int(run.accept_cycles[idle_at])
        if taken != done + RESTART_DELAY:
            problems.append(f"after the soft reset with no list open (B response in cycle "
                            f"{done}) beat {idle_at} was taken in cycle {taken}, expected "
                            f"{done + RESTART_DELAY}")
    return ("killed" if problems else "survived"), "; ".join(problems) or "passed"


def decode_steps(cfg: DPConfig) -> tuple:
    """The beats and steps of the ``decode`` run: right after reset, a read of every word
    address of the register space (2**ADDRESS_BITS bytes; a mapped register gives its reset
    value with OKAY, the write-only LUT window and every other address 0 with SLVERR) and
    of every mapped register's three unaligned addresses (0, SLVERR); then a write of all
    ones to every address that takes no write (unmapped, past the LUT window, constant,
    counter and status registers: SLVERR, nothing changes, no ERROR bit) and the read sweep
    again; then, for every setting register and every bit above its upper limit, a write of
    its reset value with that bit set (refused, SLVERR: every bit of the written word is
    compared), each register read back unchanged and ERROR.write_refused set; then two
    frames (one segment of K = 2) checked against the model."""
    import numpy as np

    from dptbd.hw.register_map import register_map
    from dptbd.sim.axi.stimulus import clean_beats
    from dptbd.sim.verilator.axi import OKAY, SLVERR

    regmap = register_map(cfg)
    lut = regmap.window("LUT")
    mapped = {r.address: r for r in regmap.registers}
    reset = {a: r.reset for a, r in mapped.items()}
    reads = []
    for address in range(0, 1 << regmap.address_bits, 4):
        reads.append(["r", address, OKAY, reset[address]] if address in mapped
                     else ["r", address, SLVERR, 0])
    reads += [["r", a + k, SLVERR, 0] for a in sorted(mapped) for k in (1, 2, 3)]
    writes = [["w", a, 2**32 - 1, 0xF, SLVERR] for a in range(0, 1 << regmap.address_bits, 4)
              if not lut.base <= a < lut.end
              and (a not in mapped or mapped[a].kind in ("constant", "counter", "status"))]
    bits, back = [], []
    for reg in regmap.registers:
        if reg.kind != "setting":
            continue
        (field,) = reg.fields
        bits += [["w", reg.address, reset[reg.address] | 1 << b, 0xF, SLVERR]
                 for b in range(32) if 1 << b > field.limits[1]]
        back.append(["r", reg.address, OKAY, reset[reg.address]])
    refused = sum(f.reset << f.lsb for f in regmap["ERROR"].fields) | next(
        1 << f.lsb for f in regmap["ERROR"].fields if f.name == "write_refused")
    back.append(["r", regmap["ERROR"].address, OKAY, refused])
    rng = np.random.default_rng([0, 0xA78])
    beats = clean_beats(rng.integers(0, 1 << cfg.input_bits, size=(2, cfg.height, cfg.width)))
    return beats, [{"bus": reads + writes + reads + bits + back, "stop": 0},
                   {"stop": len(beats)}]


#: The values of n of the ``n-values`` run, one segment (K = 1) each: every bit of n set
#: and clear, the ends 0, 1, C − 1, C, and 89 … 95 (the values whose bit 5 inverted
#: passes C).
N_VALUES = (0, 1, 2, 3, 4, 5, 8, 16, 31, 32, 33, 47, 63, 64, 65, 89, 90, 91, 92, 93, 94, 95,
            96, 100, 111, 119, 120)


def n_steps(cfg: DPConfig) -> tuple:
    """The beats and steps of the ``n-values`` run: K = 1, one frame of uniform noise per
    value of :data:`N_VALUES` (n written before the frame, taken at its first pixel), every
    list against the model."""
    import numpy as np

    from dptbd.sim.axi.stimulus import clean_beats

    rng = np.random.default_rng([0, 0xA79])
    frames = rng.integers(0, 1 << cfg.input_bits, size=(len(N_VALUES), cfg.height, cfg.width))
    beats = clean_beats(frames)
    frame = cfg.width * cfg.height
    steps = [{"writes": [["SEGMENT_FRAMES", 1], ["CANDIDATE_COUNT", n]], "stop": (j + 1) * frame}
             for j, n in enumerate(N_VALUES)]
    return beats, steps


#: Idle cycles of the ``stalls`` run between its two reads of OUTPUT_STALLS: past 2**21, so
#: that the second read has bit 21 set (the highest bit any register of the slice's other
#: runs never reads as 1; a counter bit above it takes 2**22 cycles and more).
STALL_CYCLES = (1 << 21) + 1000


def stall_plan(cfg: DPConfig) -> tuple:
    """The ``stalls`` run: K = 1 and one frame, whose list's trailer ``m_axis_cand`` offers
    and never hands over (``tready`` held low); OUTPUT_STALLS read 300 cycles on and again
    :data:`STALL_CYCLES` cycles later; then ``aresetn`` (the only way to drop the word).
    The beats and the operations."""
    import numpy as np

    from dptbd.hw.flow.register_export import constants_namespace
    from dptbd.sim.axi.stimulus import clean_beats

    regs = constants_namespace(cfg)
    rng = np.random.default_rng([0, 0xA7A])
    beats = clean_beats(rng.integers(0, 1 << cfg.input_bits, size=(1, cfg.height, cfg.width)))
    end = len(beats)
    ops = [(0, "w", regs.REG_SEGMENT_FRAMES, 1), (end, "i", 300, 0),
           (end, "r", regs.REG_OUTPUT_STALLS, 0), (end, "i", STALL_CYCLES, 0),
           (end, "r", regs.REG_OUTPUT_STALLS, 0), (end, "a", 4, 0)]
    return beats, ops


def _stalls_run(sim) -> tuple[str, str]:
    """The ``stalls`` run: OUTPUT_STALLS counts every cycle of the held word, so the two
    reads differ by exactly the cycles between them (both reads take the same cycles from
    request to response) and the second is past 2**21."""
    from dptbd.sim.verilator.axi import run_axi

    beats, ops = stall_plan(sim.cfg)
    run = run_axi(sim, beats, ops, ready_pause=1.0 - 2.0**-52,
                  max_cycles=STALL_CYCLES + 20 * len(beats) + 10_000)
    problems = []
    if run.status != "done" or int(run.counters.get("accepted", -1)) != len(beats):
        problems.append(f"{run.status}: {run.counters.get('accepted')} of {len(beats)} "
                        "beats accepted")
    elif list(run.op_resp) != [0, 0, 0] or len(run.out_words):
        problems.append(f"responses {list(run.op_resp)}, {len(run.out_words)} words out")
    else:
        first, second = (int(v) for v in run.op_data[1:3])
        cycles = int(run.op_cycles[2]) - int(run.op_cycles[1])
        if not 0 < first < 300 or second - first != cycles:
            problems.append(f"OUTPUT_STALLS read {first}, then {second} {cycles} cycles "
                            f"later (expected {first + cycles})")
    return ("killed" if problems else "survived"), "; ".join(problems) or "passed"


def noise_steps(cfg: DPConfig, seed: int) -> tuple:
    """The beats and steps of ``noise`` run ``seed``: 16 frames of uniform noise under the
    build's LUT (never written: every predecessor direction and move reached with the
    build's codes, which the ``lut`` runs overwrite from their first beat), K = K_max,
    n = C (every pixel's E and direction in the lists)."""
    import numpy as np

    from dptbd.sim.axi.stimulus import clean_beats

    rng = np.random.default_rng([seed, 0xA7B])
    beats = clean_beats(rng.integers(0, 1 << cfg.input_bits,
                                     size=(16, cfg.height, cfg.width)))
    return beats, [{"writes": [["SEGMENT_FRAMES", cfg.k_max],
                               ["CANDIDATE_COUNT", cfg.record_capacity]],
                    "stop": len(beats)}]


def resync_steps(cfg: DPConfig, seed: int) -> tuple:
    """The beats and steps of ``resync`` run ``seed``: 8 frames of two targets (K = 2);
    inside the segment that begins at frame 2, K (seed 0, 3), n (seed 1, 4) or s (seed 2, 5)
    is written, and 20 beats later a start of frame in mid-line (``sof_unexpected``) begins
    a segment at a resync, which keeps the settings of the segment before it
    (``docs/arithmetic.md`` §6.5a); the next segment start takes the written value. Seeds 3
    to 5 write one beat after the segment's first and resynchronise two beats later, before
    that first beat has reached the segmenter: a top that latched its settings at the
    resync would hand the segmenter the written value for the segment begun at frame 2."""
    import numpy as np

    from dptbd.sim.axi.stimulus import Beats, clean_beats
    from dptbd.sim.scenarios import make_frames

    beats = clean_beats(make_frames("two-targets", cfg, 8, seed=seed))
    frame = cfg.width * cfg.height
    write_at, resync_at = ((2 * frame + 10, 2 * frame + 30) if seed < 3
                           else (2 * frame + 1, 2 * frame + 3))
    first = np.asarray(beats.first).copy()
    first[resync_at] = True
    beats = Beats(beats.pixel, first, beats.last)
    name, value = (("SEGMENT_FRAMES", 3), ("CANDIDATE_COUNT", 7),
                   ("HISTOGRAM_SHIFT", 2))[seed % 3]
    steps = [{"writes": [["CANDIDATE_COUNT", cfg.record_capacity]], "stop": write_at},
             {"writes": [[name, value]], "stop": len(beats)}]
    return beats, steps


#: Lists of the ``lists`` run (K = 1, one a frame): past 2**13, with bit 13 set.
LIST_COUNT = (1 << 13) + 100


def lists_plan(cfg: DPConfig) -> tuple:
    """The ``lists`` run: one frame of noise offered :data:`LIST_COUNT` times over
    (:func:`~dptbd.sim.verilator.axi.run_axi`'s ``repeat``) at K = 1 and n = 0 (each list
    its trailer); after the settle FRAMES, SEGMENTS and LISTS read three times, 0, 1 and 2
    idle cycles apart (a counter bit that toggles every cycle is read at both parities).
    The frame's beats, the operations and the model's words of the first three lists
    (from the third on, every list is the same: the same frame, primed)."""
    import numpy as np

    from dptbd.hw.flow.register_export import constants_namespace
    from dptbd.sim.axi.stimulus import clean_beats, expected_outputs
    from dptbd.sim.candidate_scoreboard import list_words

    regs = constants_namespace(cfg)
    rng = np.random.default_rng([0, 0xA7C])
    frame = rng.integers(0, 1 << cfg.input_bits, size=(1, cfg.height, cfg.width))
    beats = clean_beats(frame)
    steps = [{"writes": [["SEGMENT_FRAMES", 1], ["CANDIDATE_COUNT", 0]], "stop": 3 * len(beats)}]
    three = clean_beats(np.repeat(frame, 3, axis=0))
    words = [w for lst in list_words(cfg, expected_outputs(cfg, three, steps).lists)
             for w in lst]
    end = len(beats) * LIST_COUNT
    ops = [(0, "w", regs.REG_SEGMENT_FRAMES, 1), (0, "w", regs.REG_CANDIDATE_COUNT, 0),
           (end, "i", 400, 0)]
    for idle in (0, 1, 2):
        if idle:
            ops.append((end, "i", idle, 0))
        ops += [(end, "r", getattr(regs, f"REG_{name}"), 0)
                for name in ("FRAMES", "SEGMENTS", "LISTS")]
    return beats, ops, [int(w) for w in words]


def _lists_run(sim) -> tuple[str, str]:
    """The ``lists`` run: every beat taken, :data:`LIST_COUNT` words, each a trailer with
    ``tuser[0]`` and ``tlast``, the first three the model's and the rest equal to the
    third, and every read of FRAMES, SEGMENTS and LISTS :data:`LIST_COUNT`."""
    import numpy as np

    from dptbd.sim.verilator.axi import run_axi

    beats, ops, words = lists_plan(sim.cfg)
    run = run_axi(sim, beats, ops, repeat=LIST_COUNT)
    problems = []
    got = [int(w) for w in run.out_words]
    if run.status != "done" or int(run.counters.get("accepted", -1)) != len(beats) * LIST_COUNT:
        problems.append(f"{run.status}: {run.counters.get('accepted')} beats accepted")
    elif got != words + [words[-1]] * (LIST_COUNT - len(words)):
        problems.append(f"{len(got)} words, not {LIST_COUNT} trailers as the model's")
    elif not np.all(np.asarray(run.out_flags) == 3):
        problems.append("a list's word without tuser[0] and tlast")
    elif list(run.op_resp) != [0] * 11 or list(run.op_data[2:]) != [LIST_COUNT] * 9:
        problems.append(f"FRAMES, SEGMENTS, LISTS read {list(map(int, run.op_data[2:]))} "
                        f"(responses {list(map(int, run.op_resp))}), expected {LIST_COUNT}")
    return ("killed" if problems else "survived"), "; ".join(problems) or "passed"


def _checked(result) -> tuple[str, str]:
    if hang_verdict(result.run.status, result.report()):
        return "timeout", (f"cycle budget ({result.run.cycles} cycles) ran out: "
                           f"{result.report()}")
    return ("survived" if result.passed else "killed"), result.report()


def run(sim, kind: str, seed: int) -> tuple[str, str]:
    from dptbd.sim.verilator.axi import check_axi

    if kind == "lists":
        return _lists_run(sim)
    if kind == "stalls":
        return _stalls_run(sim)
    if kind == "noise":
        return _checked(check_axi(sim, *noise_steps(sim.cfg, seed)))
    if kind == "resync":
        return _checked(check_axi(sim, *resync_steps(sim.cfg, seed)))
    if kind == "lut-reverse":
        return _checked(check_axi(sim, *lut_scenario(sim.cfg, seed, reverse=True), seed=seed))
    if kind == "decode":
        return _checked(check_axi(sim, *decode_steps(sim.cfg)))
    if kind == "n-values":
        return _checked(check_axi(sim, *n_steps(sim.cfg)))
    if kind == "irq":
        return _irq_run(sim)
    if kind == "restart":
        return _restart_run(sim)
    if kind == "random":
        return _axi_random_run(sim, seed)
    if kind == "counters":
        return _counters_run(sim)
    if kind == "lut":
        beats, steps = lut_scenario(sim.cfg, seed)
        result = check_axi(sim, beats, steps, seed=seed)
        if hang_verdict(result.run.status, result.report()):
            return "timeout", (f"cycle budget ({result.run.cycles} cycles) ran out: "
                               f"{result.report()}")
        return ("survived" if result.passed else "killed"), result.report()
    beats, steps, gap, pause = axi_scenario(sim.cfg, seed)
    if kind == "backpressure":
        gap, pause = 0.0, BACKPRESSURE[seed % 4]
    result = check_axi(sim, beats, steps, valid_gap=gap, ready_pause=pause, seed=seed)
    if hang_verdict(result.run.status, result.report()):
        return "timeout", (f"cycle budget ({result.run.cycles} cycles) ran out: "
                           f"{result.report()}")
    # the stall counters against the harness's own count of the same cycles
    stalls = [f"{name} = {result.reads.get(name)}, the harness counted {result.run.counters[key]}"
              for name, key in (("INPUT_STALLS", "stalled_input_cycles"),
                                ("OUTPUT_STALLS", "paused_output_cycles"))
              if result.reads.get(name) != result.run.counters[key]]
    if result.passed and stalls:
        return "killed", "; ".join(stalls)
    return ("survived" if result.passed else "killed"), result.report()
