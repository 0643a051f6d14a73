"""The coverage campaign's own run sets: stimulus the campaign's cases cannot give.

:func:`extra_cases`: campaign :class:`~dptbd.sim.campaign.Case` s run on coverage builds only
(a segmenter whose energy saturates). :func:`axi_cases`: the AXI top's runs (:class:`AxiCase`:
the scenario of ``tests/sim/verilator/test_axi.py`` — every fault class, register writes
refused and taken, a LUT rewrite, a soft reset — scored by
:func:`~dptbd.sim.verilator.axi.check_axi`). :func:`coverage_run` runs one of either, or a
campaign case, as a task of the execution layer (:func:`dptbd.sim.coverage.report.run_coverage`).
"""

from __future__ import annotations

import dataclasses
import time

__all__ = ["AxiCase", "COUNTER_EVENTS", "COUNTER_CONFIG", "extra_cases", "axi_cases",
           "counter_scene", "check_axi_run", "coverage_run"]


@dataclasses.dataclass(frozen=True)
class AxiCase:
    """An AXI run of the coverage campaign: a configuration, seeds and the scene
    (``"faults"``: :func:`!_axi_scene`; ``"bright"``: the same with a full-scale line in every
    frame; ``"counters"``: :func:`counter_scene`), the build's FPGA family as a campaign
    :class:`~dptbd.sim.campaign.Case`'s."""

    name: str
    config: dict
    runs: int
    design: str = "axi"
    scene: str = "faults"
    family: str | None = None


#: The event counters' bits up to 19 are reached by 2**19 events of each (bit k first
#: becomes 1 at the 2**k-th event); bits 20-31 are excluded (``exclusions.toml``).
COUNTER_EVENTS = 1 << 19

#: The counter run's configuration: the smallest frame the read-ahead allows (3 x 6:
#: ``check_supported``), K = 1 (a segment and a list per frame) and K_max = 2 with B_E = 8
#: for 8-bit pixels (two bright frames saturate).
COUNTER_CONFIG = dict(width=3, height=6, segment_frames=1, max_segment_frames=2,
                      energy_bits=8, candidate_count=1, candidate_capacity=2, histogram_bits=2)


def extra_cases() -> list:
    """Coverage runs beyond the campaign's cases (stimulus the campaign's parameter sets
    cannot give): a segmenter whose energy saturates (B_E = 9 for 8-bit pixels), so the
    high bits of E and of the weighted sums toggle."""
    from dptbd.sim.campaign import Case

    every = ("reset", "misaligned_first", "short_frame", "long_frame", "lut", "settings")
    return [Case("segmenter-24x16-in8-e9-sat", dict(width=24, height=16, segment_frames=6,
                                                    input_bits=8, energy_bits=9,
                                                    candidate_count=3, histogram_bits=6),
                 "segmenter", 300, 4, every)]


def axi_cases() -> list[AxiCase]:
    """The AXI top's coverage runs (the scenario of ``tests/sim/verilator/test_axi.py``)."""
    small = dict(width=12, height=10, segment_frames=2, max_segment_frames=4,
                 candidate_count=4, candidate_capacity=6, histogram_bits=6, histogram_shift=2)
    return [AxiCase("axi-12x10-k2-faults", small, 8),
            AxiCase("axi-12x10-e9-saturating", dict(small, energy_bits=9), 4, scene="bright"),
            AxiCase("axi-3x6-counters", COUNTER_CONFIG, 1, scene="counters")]


def counter_scene(cfg, seed: int, events: int = COUNTER_EVENTS):
    """Beats and steps that raise every event counter of ``dptbd_axi`` at least ``events``
    times (FRAMES, SEGMENTS, LISTS, each FAULT_* and SATURATED; the final reads are
    checked against the golden model's and the fault rule's counts by
    :func:`~dptbd.sim.verilator.axi.check_axi`), on :data:`COUNTER_CONFIG`:

    1. ``events`` + 1 frames, each after the first without its start of frame: a frame
       (segment, list) and a ``frame_long`` each;
    2. ``events`` beats each ending a line of one beat: ``line_length``;
    3. ``events`` pairs of beats, each starting a frame: ``sof_unexpected``;
    4. ``events`` lines, each starting a frame: ``frame_short``;
    5. a clean frame, then K = 2 (``SEGMENT_FRAMES`` written) and full-scale frames, each
       second one saturating its energies: ``SATURATED`` >= ``events``.
    """
    import numpy as np

    from dptbd.sim.axi.stimulus import Beats, clean_beats

    rng = np.random.default_rng([seed, 0xC0])
    w, h = cfg.width, cfg.height

    def pixels(n):
        return rng.integers(0, cfg.pixel_max + 1, size=n, dtype=np.int64)

    long = clean_beats(pixels((events + 1) * w * h).reshape(events + 1, h, w))
    long.first[w * h:] = False
    line = Beats(pixels(events), np.zeros(events, bool), np.ones(events, bool))
    sof = Beats(pixels(2 * events), np.tile([True, False], events), np.zeros(2 * events, bool))
    short = Beats(pixels(w * events), np.tile(np.arange(w) == 0, events),
                  np.tile(np.arange(w) == w - 1, events))
    clean = clean_beats(pixels(w * h).reshape(1, h, w))
    per_segment = w * h                   # the second frame of a segment saturates each pixel
    bright_frames = 2 * (-(-events // per_segment) + 2)
    bright = clean_beats(np.full((bright_frames, h, w), cfg.pixel_max, dtype=np.int64))
    head = long + line + sof + short + clean
    steps = [{"stop": len(head)},
             {"writes": [["SEGMENT_FRAMES", 2]], "stop": len(head) + len(bright)}]
    return head + bright, steps


def _axi_scene(cfg, seed: int, bright: bool = False):
    import numpy as np

    from dptbd.hw.register_map import FAULTS, constants_namespace
    from dptbd.sim.axi.stimulus import fault_stretches
    from dptbd.sim.scenarios import make_frames

    regs = constants_namespace(cfg)
    frames = make_frames("two-targets", cfg, 4 + 2 * len(FAULTS), seed=seed)
    if bright:                             # a full-scale line in every frame: E saturates,
        frames[:, 1] = cfg.pixel_max       # the weighted sums reach their top bits
    beats, starts = fault_stretches(cfg, frames)
    frame = cfg.width * cfg.height
    every = sum(getattr(regs, f"ERROR_{k.upper()}_MASK") for k in FAULTS)
    # a LUT rewrite with random codes in [0, 2**F], 2**F - 1 and 2**F among them: every bit
    # of a code, and of the weighted candidates' shift-and-add sums, is driven
    unity = 1 << cfg.weight_frac_bits
    codes = np.random.default_rng([seed, 0x107]).integers(
        0, unity + 1, size=np.asarray(cfg.weight_codes).shape)
    codes.flat[:2] = (unity - 1, unity)
    from dptbd.hw.register_map import LUT_WINDOW_BASE, register_map

    names = [reg.name for reg in register_map(cfg).registers]
    top = max(getattr(regs, f"REG_{n}") for n in names)
    from dptbd.sim.verilator.axi import SLVERR as slverr  # each refused, changing nothing

    refused = [["w", regs.REG_SEGMENT_FRAMES + 1, 1, 0xF, slverr],             # unaligned
               ["r", regs.REG_ID + 2, slverr, None],
               ["w", top + 4, 7, 0xF, slverr], ["r", top + 4, slverr, None],   # unmapped
               ["r", LUT_WINDOW_BASE, slverr, None],                            # a LUT read
               ["w", LUT_WINDOW_BASE + 4, (1 << cfg.weight_frac_bits) + 1, 0xF,  # code > 2**F
                slverr]]
    steps = [{"check": {"ID": regs.MAGIC, **{n: None for n in names if n != "ID"}},
              "writes": [["CONTROL", regs.CONTROL_CLEAR_COUNTERS_MASK]],   # nothing counted yet
              "stop": 2 * frame},
             {"writes": [["SEGMENT_FRAMES", 1], ["CANDIDATE_COUNT", 6],
                         ["HISTOGRAM_SHIFT", cfg.energy_bits]], "bus": refused,
              "stop": 4 * frame},
             {"check": {"SEGMENTS": 3}, "lut_codes": codes.tolist(),
              "writes": [["SEGMENT_FRAMES", 3], ["ERROR", regs.ERROR_WRITE_REFUSED_MASK],
                         ["HISTOGRAM_SHIFT", min(6, cfg.energy_bits - 1)]],   # s's bit 2
              "stop": starts[2]},
             {"soft_reset": True, "writes": [["HISTOGRAM_SHIFT", 1]], "stop": len(beats)},
             {"check": {"ERROR": every}, "writes": [["ERROR", every]], "stop": len(beats)}]
    return beats, steps


def check_axi_run(case: AxiCase, seed: int, root, coverage: str):
    """Build (cached), run and check one AXI run on the coverage build."""
    import numpy as np

    from dptbd.sim.campaign import RunOutcome
    from dptbd.sim.verilator import build
    from dptbd.sim.verilator.axi import check_axi

    start = time.perf_counter()
    cfg = _config(case.config)
    sim = build(cfg, "axi", root=root, coverage=True, family=case.family)
    rng = np.random.default_rng([seed, 0xA71])
    if case.scene == "counters":
        beats, steps = counter_scene(cfg, seed)
        gap, pause = 0.0, 0.5             # output stalls on every other cycle or so
    else:
        beats, steps = _axi_scene(cfg, seed, bright=case.scene == "bright")
        gap, pause = float(rng.uniform(0.0, 0.5)), float(rng.uniform(0.0, 0.9))
    result = check_axi(sim, beats, steps, valid_gap=gap, ready_pause=pause, seed=seed,
                       coverage=coverage)
    return RunOutcome(case.name, seed, result.passed, result.report(), len(beats),
                      result.board.count, result.run.cycles, result.run.sim_seconds,
                      time.perf_counter() - start, (f"gaps {gap:.2f}, back-pressure {pause:.2f}",))


def _config(fields: dict):
    """The configuration, its saturation warning silenced (a saturating set is chosen)."""
    import warnings

    from dptbd.config import DPConfig, EnergyWidthWarning
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        return DPConfig(**fields)


def coverage_run(case, seed: int, root, coverage: str):
    """One run of the coverage campaign (a task of the execution layer): a campaign
    :class:`~dptbd.sim.campaign.Case` through :func:`~dptbd.sim.campaign.check_run` (an AXI
    case to :func:`dptbd.sim.axi.runs.check_run`), an :class:`AxiCase` through
    :func:`check_axi_run`; its coverage data written to the file ``coverage``."""
    if isinstance(case, AxiCase):
        return check_axi_run(case, seed, root, coverage)
    from dptbd.sim.campaign import check_run
    return check_run(case, seed, root, coverage=coverage)
