"""The ``axi`` slice (``dptbd_axi``): seeded runs of
:func:`dptbd.sim.verilator_axi.check_axi` (every fault class, settings and LUT writes,
refused writes, W1C, soft reset, register reads, gaps and back-pressure) and random AXI runs
of the campaign (:func:`dptbd.sim.axi_runs.draw_run`)."""

from __future__ import annotations

from dptbd.config import DPConfig
from dptbd.sim.mutation.slices import BACKPRESSURE, CONFIGS
from dptbd.sim.mutation.verdict import hang_verdict

__all__ = ["RANDOM_AXI_RUNS", "RANDOM_AXI_FRAMES", "RUNS", "axi_scenario", "run"]

#: Random AXI runs of the ``axi`` slice (:func:`dptbd.sim.axi_runs.draw_run` on the slice's
#: configuration, :data:`RANDOM_AXI_FRAMES` frames each): every refused access class,
#: soft resets with words in flight, aresetn, W1C, clear_counters, LUT and settings writes,
#: every register read with its expected value.
RANDOM_AXI_RUNS, RANDOM_AXI_FRAMES = 32, 24

#: The runs of the slice: ``(kind, seed)``, in this order.
RUNS = tuple([("faults", s) for s in range(16)]
             + [("backpressure", s) for s in (1, 4, 7, 14)]
             + [("random", s) for s in range(RANDOM_AXI_RUNS)])


def axi_scenario(cfg: DPConfig, seed: int) -> tuple:
    """The beats, steps and stimulus of AXI run ``seed``: two clean segments and every fault
    class (:func:`dptbd.sim.axi_stimulus.with_fault`), K / n / s writes (one refused), the
    LUT rewritten, ERROR W1C, a soft reset, register checks; gaps and back-pressure from the
    seed."""
    import numpy as np

    from dptbd.hw.flow.register_export import constants_namespace
    from dptbd.hw.register_map import FAULTS, register_map
    from dptbd.sim.axi_stimulus import fault_stretches
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
    from dptbd.sim.axi_runs import AXI_FAULTS, draw_run
    from dptbd.sim.campaign import Case
    from dptbd.sim.verilator_axi import check_axi

    case = Case("mutant-axi-random", CONFIGS["axi"], "axi", RANDOM_AXI_FRAMES, 1, AXI_FAULTS)
    plan = draw_run(case, seed)
    result = check_axi(sim, plan.beats, plan.steps, valid_gap=plan.valid_gap,
                       ready_pause=plan.ready_pause, seed=seed, pulses=plan.pulses)
    if hang_verdict(result.run.status, result.report()):
        return "timeout", (f"cycle budget ({result.run.cycles} cycles) ran out: "
                           f"{result.report()}")
    return ("survived" if result.passed else "killed"), result.report()


def run(sim, kind: str, seed: int) -> tuple[str, str]:
    from dptbd.sim.verilator_axi import check_axi

    if kind == "random":
        return _axi_random_run(sim, seed)
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
