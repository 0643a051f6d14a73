"""Runs of the ``axi`` slice that check exact cycles and counters
(:mod:`dptbd.sim.mutation.slices.axi`): ``irq`` after every IRQ_ENABLE and IRQ_STATUS write
(:func:`irq_plan`), the first beat taken after a soft reset (:func:`restart_plan`), 2**21
cycles of output back-pressure (:func:`stall_plan`) and 8 292 one-frame lists read at both
clock parities (:func:`lists_plan`); every counter preset to values that set each of its
bits to 1 and to 0, read, and counted on to a wrap (:func:`presets_plan`)."""

from __future__ import annotations

from dptbd.config import DPConfig

__all__ = ["IRQ_WRITES", "RESTART_DELAY", "STALL_CYCLES", "LIST_COUNT", "irq_plan",
           "restart_plan", "stall_plan", "lists_plan", "irq_run", "restart_run",
           "stalls_run", "lists_run", "PRESETS", "PRESET_FRAMES", "presets_plan", "presets_run"]

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

    from dptbd.hw.register_map import constants_namespace
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


def irq_run(sim) -> tuple[str, str]:
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


#: Cycles from the cycle a soft reset's outputs close (the cut trailer's transfer, or the
#: cycle of the write's B response when no list is open) to the first beat taken after it
#: (``docs/integration.md``, "Reset and soft reset"): the restart is registered, in the
#: cycle after (the core is reset at its end), the input is held up to the core's
#: post-reset cycle included (``s_axis_video_tready`` low; the harness offers the next beat
#: from the cycle after the write's response), and the core takes it in the cycle after.
RESTART_DELAY = 3


def restart_plan(cfg: DPConfig) -> tuple:
    """The ``restart`` run: K = 1, n = C (long lists), three frames at full speed and, 10
    beats into the third, a soft reset 40 idle cycles on, while the second frame's list is
    being sent (its cut trailer is the restart); then two more frames, the settle and a
    second soft reset with no list open; one more frame. The beats, the operations, the
    beats before which the two soft resets are written, and the index of the two writes
    among the w/r operations."""
    import numpy as np

    from dptbd.hw.register_map import constants_namespace
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


def restart_run(sim) -> tuple[str, str]:
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

    from dptbd.hw.register_map import constants_namespace
    from dptbd.sim.axi.stimulus import clean_beats

    regs = constants_namespace(cfg)
    rng = np.random.default_rng([0, 0xA7A])
    beats = clean_beats(rng.integers(0, 1 << cfg.input_bits, size=(1, cfg.height, cfg.width)))
    end = len(beats)
    ops = [(0, "w", regs.REG_SEGMENT_FRAMES, 1), (end, "i", 300, 0),
           (end, "r", regs.REG_OUTPUT_STALLS, 0), (end, "i", STALL_CYCLES, 0),
           (end, "r", regs.REG_OUTPUT_STALLS, 0), (end, "a", 4, 0)]
    return beats, ops


def stalls_run(sim) -> tuple[str, str]:
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

    from dptbd.hw.register_map import constants_namespace
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


def lists_run(sim) -> tuple[str, str]:
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


#: The values the ``presets`` run loads into every counter, each then read back: every bit
#: at 1 in one of the first two and at 0 in the other (a mutation that flips, inverts or
#: sticks a counter bit, while another bit is 1 or 0, shows in one of the reads), the last
#: three below 2**32 so that the frames after it carry through every bit and wrap.
PRESETS = (0xAAAA_AAAA, 0x5555_5555, 0xFFFF_FFFD)

#: Frames of the ``presets`` run after its last preset (K = 1 and n = 0: a list each).
PRESET_FRAMES = 6


def presets_plan(cfg: DPConfig) -> tuple:
    """The ``presets`` run (mutant builds: :mod:`dptbd.sim.mutation.presets`): K = 1, n = 0;
    each of :data:`PRESETS` loaded into every counter and every counter read, twice, one
    idle cycle apart (a mutant counter bit that toggles every cycle is read at both clock
    parities, as in the ``lists`` run); then :data:`PRESET_FRAMES` frames of noise at full
    speed, the settle and every counter read again, twice. After each preset's reads, every
    counter's three unaligned addresses are read: 0 with SLVERR, whatever bits the counter
    holds (a read select that ignores an address bit shows them). The beats, the operations
    and the value each read must give (``None``: 0 with SLVERR): the preset, and at the end
    the last preset plus the model's count modulo 2**32 (FRAMES, SEGMENTS, LISTS,
    SATURATED; no fault; INPUT_STALLS the histogram scans of all lists but the last,
    ``scan_cycles`` each, as in the ``counters`` run; no OUTPUT_STALLS)."""
    import numpy as np

    from dptbd.hw.register_map import constants_namespace
    from dptbd.hw.segmenter import scan_cycles
    from dptbd.sim.axi.stimulus import clean_beats, expected_outputs
    from dptbd.sim.mutation.presets import preset_counters

    regs = constants_namespace(cfg)
    counters = preset_counters(cfg)
    rng = np.random.default_rng([0, 0xA7D])
    beats = clean_beats(rng.integers(0, 1 << cfg.input_bits,
                                     size=(PRESET_FRAMES, cfg.height, cfg.width)))
    steps = [{"writes": [["SEGMENT_FRAMES", 1], ["CANDIDATE_COUNT", 0]], "stop": len(beats)}]
    counts = expected_outputs(cfg, beats, steps, cut_lists=True).counters()
    counts["INPUT_STALLS"] = (counts["LISTS"] - 1) * scan_cycles(cfg)
    ops = [(0, "w", regs.REG_SEGMENT_FRAMES, 1), (0, "w", regs.REG_CANDIDATE_COUNT, 0)]
    reads = [("r", getattr(regs, f"REG_{name.upper()}"), 0) for name in counters]
    unaligned = [("r", getattr(regs, f"REG_{name.upper()}") + k, 0) for name in counters
                 for k in (1, 2, 3)]
    want = []
    for value in PRESETS:
        ops += [(0, "p", i, value) for i in range(len(counters))]
        ops += [(0, *r) for r in reads] + [(0, "i", 1, 0)] + [(0, *r) for r in reads]
        ops += [(0, *r) for r in unaligned]
        want += [value] * (2 * len(counters)) + [None] * len(unaligned)
    end = len(beats)
    ops += [(end, "i", 64, 0)] + [(end, *r) for r in reads] + [(end, "i", 1, 0)]
    ops += [(end, *r) for r in reads]
    want += 2 * [(PRESETS[-1] + counts.get(name.upper(), 0)) % (1 << 32) for name in counters]
    return beats, ops, want


def presets_run(sim) -> tuple[str, str]:
    """The ``presets`` run: every beat taken, every read the value and response of
    :func:`presets_plan` (the first difference reported)."""
    from dptbd.sim.mutation.presets import preset_counters
    from dptbd.sim.verilator.axi import OKAY, SLVERR, run_axi

    beats, ops, want = presets_plan(sim.cfg)
    run = run_axi(sim, beats, ops)
    problems = []
    counters = preset_counters(sim.cfg)
    got = list(zip((int(r) for r in run.op_resp[2:]), (int(v) for v in run.op_data[2:])))
    if run.status != "done" or int(run.counters.get("accepted", -1)) != len(beats):
        problems.append(f"{run.status}: {run.counters.get('accepted')} of {len(beats)} "
                        "beats accepted")
    elif len(got) != len(want) or any(int(r) for r in run.op_resp[:2]):
        problems.append(f"responses {list(map(int, run.op_resp))}")
    else:
        addresses = [op[2] for op in ops if op[1] == "r"]
        aligned = 0                          # the index among the reads of a counter itself
        for (resp, data), value, address in zip(got, want, addresses):
            if value is None and (resp, data) != (SLVERR, 0):
                problems.append(f"read {address:#05x} (unaligned) gave {data:#010x} with "
                                f"response {resp}, expected 0 with SLVERR")
                break
            if value is not None:
                if (resp, data) != (OKAY, value):
                    name = counters[aligned % len(counters)].upper()
                    problems.append(f"read {aligned} ({name}) gave {data:#010x}"
                                    + (f" with response {resp}" if resp != OKAY else "")
                                    + f", expected {value:#010x}")
                    break
                aligned += 1
    return ("killed" if problems else "survived"), "; ".join(problems) or "passed"
