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
(:func:`lut_scenario`, ``lut-reverse``); every histogram shift (:func:`shift_steps`);
frames whose last line ends at the next start of frame (:func:`line_end_steps`); a LUT
under which entry :data:`LUT_ENTRY`'s code bit 0 shows (:func:`lut_entry_steps`); low
energies at shift 1 through every threshold (:func:`low_shift_steps`); lists of every
length, each ending with a selected pixel (:func:`list_length_steps`); noise under output
back-pressure that keeps the DP output FIFO full (:func:`full_fifo_steps`); 8 292
one-frame lists read at both clock parities (:func:`lists_plan`); every counter preset, read and counted on to a wrap
(:func:`presets_plan`); and runs compared cycle for cycle with the original design's
(:func:`reference_run`). The runs of exact cycles and counters are in
:mod:`~dptbd.sim.mutation.slices.axi.timing`, those driving the register block in
:mod:`~dptbd.sim.mutation.slices.axi.registers`; their names are re-exported here."""

from __future__ import annotations

from dptbd.config import DPConfig
from dptbd.sim.mutation.slices import BACKPRESSURE, CONFIGS
from dptbd.sim.mutation.slices.axi.registers import (FULL_FIFO_PAUSE, LOW_SHIFT_THRESHOLDS,
                                                     LUT_ENTRY, N_VALUES, decode_steps,
                                                     full_fifo_steps, line_end_steps,
                                                     list_length_steps, low_shift_steps,
                                                     lut_entry_codes, lut_entry_steps,
                                                     n_steps, noise_steps, resync_steps,
                                                     shift_steps)
from dptbd.sim.mutation.slices.axi.timing import (IRQ_WRITES, LIST_COUNT, PRESET_FRAMES,
                                                  PRESETS, RESTART_DELAY, STALL_CYCLES, irq_plan,
                                                  irq_run, lists_plan, lists_run,
                                                  presets_plan, presets_run, restart_plan,
                                                  restart_run, stall_plan, stalls_run)
from dptbd.sim.mutation.verdict import hang_verdict

__all__ = ["RANDOM_AXI_RUNS", "RANDOM_AXI_FRAMES", "LUT_RUNS", "COUNTER_FRAMES",
           "COUNTER_READS", "IRQ_WRITES", "RESTART_DELAY", "RUNS", "axi_scenario",
           "lut_scenario", "counter_plan", "irq_plan", "restart_plan", "N_VALUES",
           "decode_steps", "n_steps", "STALL_CYCLES", "stall_plan", "noise_steps", "resync_steps",
           "shift_steps", "line_end_steps", "LUT_ENTRY", "lut_entry_codes", "lut_entry_steps",
           "LOW_SHIFT_THRESHOLDS", "low_shift_steps", "list_length_steps", "FULL_FIFO_PAUSE",
           "full_fifo_steps",
           "LIST_COUNT", "lists_plan", "PRESETS", "PRESET_FRAMES", "presets_plan",
           "REFERENCE_PRESET", "REFERENCE_PAUSE", "reference_plan", "reference_run", "run"]

#: Random AXI runs of the ``axi`` slice (:func:`dptbd.sim.axi.runs.draw_run` on the slice's
#: configuration, :data:`RANDOM_AXI_FRAMES` frames each): every refused access class,
#: soft resets with words in flight, aresetn, W1C, clear_counters, LUT and settings writes,
#: every register read with its expected value.
RANDOM_AXI_RUNS, RANDOM_AXI_FRAMES = 32, 24

#: Frames of the ``counters`` run: K = 1 and n = 0 (each frame a segment, each list its
#: trailer), so that FRAMES, SEGMENTS and LISTS pass 2**10 (their high bits are reached by
#: the ``presets`` run, :func:`presets_plan`); at full speed without back-pressure the
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
             + [("counters", 0), ("presets", 0), ("irq", 0), ("restart", 0), ("decode", 0),
                ("n-values", 0), ("noise", 0), ("noise", 1),
                *(("resync", s) for s in range(6)),
                ("lut-reverse", 0), ("lut-reverse", 1), ("shifts", 0), ("line-ends", 0),
                ("lut-entry", 0), ("low-shift", 0), ("list-lengths", 0), ("full-fifo", 0),
                ("reference", 0), ("reference", 1), ("stalls", 0), ("lists", 0)])

#: The ``reference`` runs (:func:`reference_run`): every counter's preset (bit 14 and every
#: other even bit set: an increment then carries the counter's other bits along) and the
#: output back-pressure, by seed.
REFERENCE_PRESET = 0x5555_5555
#: The reference run's pause probabilities (see :data:`REFERENCE_PRESET`).
REFERENCE_PAUSE = (0.9, 0.8)

#: The original design's ``reference`` runs, per build and seed (one per process).
_ORIGINAL_RUNS: dict = {}


def reference_plan(sim, seed: int) -> tuple:
    """The beats and operations of ``reference`` run ``seed``: every counter preset to
    :data:`REFERENCE_PRESET` at the first beat, then (even seeds) :func:`axi_scenario`'s
    steps of that seed (every frame-sync fault class, K / n / s writes, the LUT, W1C) with
    its soft reset issued at once (``"now"``), or (odd seeds) 4 frames of noise at K = 1,
    n = C with a soft reset issued at once in the middle of frame 1, whose list (every
    pixel) is then streaming under the back-pressure of :data:`REFERENCE_PAUSE`: the cut
    meets a word offered and not taken; and every counter read at the end."""
    import numpy as np

    from dptbd.sim.axi.stimulus import clean_beats
    from dptbd.sim.mutation.presets import preset_counters
    from dptbd.sim.verilator.axi import settle_cycles, step_operations

    cfg = sim.cfg
    if seed % 2 == 0:
        beats, steps, _gap, _pause = axi_scenario(cfg, seed)
        steps = [dict(step, soft_reset="now") if step.get("soft_reset") else step
                 for step in steps]
    else:
        rng = np.random.default_rng([seed, 0xA7E])
        beats = clean_beats(rng.integers(0, 1 << cfg.input_bits,
                                         size=(4, cfg.height, cfg.width)))
        frame = cfg.width * cfg.height
        steps = [{"writes": [["SEGMENT_FRAMES", 1], ["CANDIDATE_COUNT", cfg.record_capacity]],
                  "stop": frame + frame // 2},
                 {"soft_reset": "now", "stop": len(beats)}]
    counters = preset_counters(cfg)
    ops, _ = step_operations(cfg, steps, settle_cycles(sim, REFERENCE_PAUSE[seed % 2]),
                             [name.upper() for name in counters])
    return beats, [(0, "p", i, REFERENCE_PRESET) for i in range(len(counters))] + ops


def reference_run(sim, seed: int) -> tuple[str, str]:
    """Run ``seed`` of :func:`reference_plan` compared with the original design's run of it
    (``mutsel = 0`` on the same build, MCY's reference; the harness's back-pressure is a
    seeded function of the cycle): every output word, its flags and cycle, every beat's
    acceptance cycle, every register operation's data and response and every change of
    ``irq`` must be the original's. It sees what the model-based checks accept either way:
    a soft reset's cut that takes another prefix of the list (a held word dropped), a
    counter's increment from a value with high bits set."""
    import os

    import numpy as np

    from dptbd.sim.verilator.axi import run_axi

    beats, ops = reference_plan(sim, seed)
    pause = REFERENCE_PAUSE[seed % 2]
    key = (str(sim.executable), seed)
    if key not in _ORIGINAL_RUNS:
        mutant = os.environ.get("DPTBD_MUTANT")
        os.environ["DPTBD_MUTANT"] = "0"
        try:
            original = run_axi(sim, beats, ops, ready_pause=pause, seed=seed)
        finally:
            if mutant is None:
                os.environ.pop("DPTBD_MUTANT", None)
            else:
                os.environ["DPTBD_MUTANT"] = mutant
        if original.status != "done":
            raise RuntimeError(f"the original's reference run of seed {seed}: "
                               f"{original.status} after {original.cycles} cycles")
        _ORIGINAL_RUNS[key] = original
    original = _ORIGINAL_RUNS[key]
    run = run_axi(sim, beats, ops, ready_pause=pause, seed=seed)
    for what in ("out_words", "out_flags", "out_cycles", "accept_cycles", "op_data",
                 "op_resp", "irq_cycles"):
        got, want = getattr(run, what), getattr(original, what)
        if len(got) != len(want) or (got != want).any():
            i = int(np.argmax(got != want)) if len(got) == len(want) else min(len(got),
                                                                               len(want))
            show = [int(v[i]) if i < len(v) else "-" for v in (got, want)]
            return "killed", (f"{what}[{i}] = {show[0]}, the original's {show[1]} "
                              f"({len(got)} and {len(want)} entries)")
    if run.status != "done":
        return "timeout", f"cycle budget ({run.cycles} cycles) ran out, as the original's"
    return "survived", f"as the original: {len(run.out_words)} words, {len(run.op_data)} operations"


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

        from dptbd.hw.register_map import constants_namespace
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

    from dptbd.hw.register_map import FAULTS, constants_namespace, register_map
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
    return _checked(result)


def _checked(result) -> tuple[str, str]:
    if hang_verdict(result.run.status, result.report()):
        return "timeout", (f"cycle budget ({result.run.cycles} cycles) ran out: "
                           f"{result.report()}")
    return ("survived" if result.passed else "killed"), result.report()


def run(sim, kind: str, seed: int) -> tuple[str, str]:
    from dptbd.sim.verilator.axi import check_axi

    if kind == "lists":
        return lists_run(sim)
    if kind == "reference":
        return reference_run(sim, seed)
    if kind == "stalls":
        return stalls_run(sim)
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
    if kind == "line-ends":
        return _checked(check_axi(sim, *line_end_steps(sim.cfg)))
    if kind == "lut-entry":
        return _checked(check_axi(sim, *lut_entry_steps(sim.cfg)))
    if kind == "low-shift":
        return _checked(check_axi(sim, *low_shift_steps(sim.cfg)))
    if kind == "list-lengths":
        return _checked(check_axi(sim, *list_length_steps(sim.cfg)))
    if kind == "full-fifo":
        return _checked(check_axi(sim, *full_fifo_steps(sim.cfg), ready_pause=FULL_FIFO_PAUSE))
    if kind == "shifts":
        return _checked(check_axi(sim, *shift_steps(sim.cfg)))
    if kind == "irq":
        return irq_run(sim)
    if kind == "restart":
        return restart_run(sim)
    if kind == "random":
        return _axi_random_run(sim, seed)
    if kind == "counters":
        return _counters_run(sim)
    if kind == "presets":
        return presets_run(sim)
    if kind == "lut":
        return _checked(check_axi(sim, *lut_scenario(sim.cfg, seed), seed=seed))
    beats, steps, gap, pause = axi_scenario(sim.cfg, seed)
    if kind == "backpressure":
        gap, pause = 0.0, BACKPRESSURE[seed % 4]
    result = check_axi(sim, beats, steps, valid_gap=gap, ready_pause=pause, seed=seed)
    verdict = _checked(result)
    if verdict[0] == "timeout":
        return verdict
    # the stall counters against the harness's own count of the same cycles
    stalls = [f"{name} = {result.reads.get(name)}, the harness counted {result.run.counters[key]}"
              for name, key in (("INPUT_STALLS", "stalled_input_cycles"),
                                ("OUTPUT_STALLS", "paused_output_cycles"))
              if result.reads.get(name) != result.run.counters[key]]
    if result.passed and stalls:
        return "killed", "; ".join(stalls)
    return ("survived" if result.passed else "killed"), result.report()
