"""Runs of the ``axi`` slice that drive the register block
(:mod:`dptbd.sim.mutation.slices.axi`): a sweep of the whole register address space
(:func:`decode_steps`), a run through many values of n (:func:`n_steps`), ``noise`` runs
under the build's LUT (:func:`noise_steps`), settings written inside a segment that a
resync then ends (:func:`resync_steps`), a run through every histogram shift
(:func:`shift_steps`), frames whose last line ends at the next start of frame
(:func:`line_end_steps`), a LUT under which one entry's code bit 0 shows
(:func:`lut_entry_steps`), low energies thresholded at shift 1 through every threshold
(:func:`low_shift_steps`), lists of every length ending with a selected pixel
(:func:`list_length_steps`) and noise under output back-pressure that keeps the DP output
FIFO full (:func:`full_fifo_steps`)."""

from __future__ import annotations

from dptbd.config import DPConfig

__all__ = ["N_VALUES", "LUT_ENTRY", "LOW_SHIFT_THRESHOLDS", "decode_steps", "n_steps",
           "noise_steps", "resync_steps", "shift_steps", "line_end_steps", "lut_entry_codes",
           "lut_entry_steps", "low_shift_steps", "list_length_steps", "FULL_FIFO_PAUSE",
           "full_fifo_steps"]

def decode_steps(cfg: DPConfig) -> tuple:
    """The beats and steps of the ``decode`` run: right after reset, a read of every word
    address of the register space (2**ADDRESS_BITS bytes; a mapped register gives its reset
    value with OKAY, the write-only LUT window and every other address 0 with SLVERR) and
    of every mapped register's three unaligned addresses (0, SLVERR); then a write of all
    ones to every address that takes no write (unmapped, past the LUT window, constant,
    counter and status registers: SLVERR, nothing changes, no ERROR bit) and the read sweep
    again; then, for every setting register and every bit above its upper limit, a write of
    its reset value with that bit set (refused, SLVERR: every bit of the written word is
    compared), each register read back unchanged and ERROR.write_refused set; a LUT write
    with each byte strobe clear in turn and one of a code in range with every strobe at each
    unaligned address of the window's first word (refused, SLVERR); ERROR cleared with all ones (W1C):
    IRQ_STATUS keeps its pending fault (a write decoded at both registers clears it) and
    ERROR reads 0; a refused write sets them again; the handshake accesses of
    ``_handshake_accesses`` (late W with ``awaddr`` changed, reads probed while
    pending); then two frames (one segment of K = 2) checked against the model."""
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
    bits += [["w", lut.base, 0, 0xF & ~(1 << k), SLVERR] for k in range(4)]
    bits += [["w", lut.base + k, 0, 0xF, SLVERR] for k in (1, 2, 3)]
    refused = sum(f.reset << f.lsb for f in regmap["ERROR"].fields) | next(
        1 << f.lsb for f in regmap["ERROR"].fields if f.name == "write_refused")
    error, status = regmap["ERROR"].address, regmap["IRQ_STATUS"].address
    fault = next(1 << f.lsb for f in regmap["IRQ_STATUS"].fields if f.name == "fault")
    k = regmap["SEGMENT_FRAMES"]
    back += [["r", error, OKAY, refused], ["r", status, OKAY, fault],
             ["w", error, 2**32 - 1, 0xF, OKAY], ["r", status, OKAY, fault],
             ["r", error, OKAY, 0],
             ["w", k.address, k.reset | 1 << 31, 0xF, SLVERR], ["r", error, OKAY, refused]]
    rng = np.random.default_rng([0, 0xA78])
    beats = clean_beats(rng.integers(0, 1 << cfg.input_bits, size=(2, cfg.height, cfg.width)))
    return beats, [{"bus": reads + writes + reads + bits + back + _handshake_accesses(
                        regmap, {**reset, error: refused, status: fault}), "stop": 0},
                   {"stop": len(beats)}]


def _handshake_accesses(regmap, now: dict) -> list:
    """Bus accesses of the ``decode`` run that take addresses at their handshakes only:
    every setting written its upper limit with W offered after the AW handshake and
    ``awaddr`` changed then (``"w-late"``: the write goes to the first address), every
    mapped register read with ``araddr`` changed after the AR handshake while AR (every
    other register: AR, AW and W) is offered and ``rready`` is held low (``"r-probe"``,
    ``"r-probe-all"``: its own value, nothing taken meanwhile), the settings written back to ``now`` (the values before)."""
    from dptbd.sim.verilator.axi import OKAY

    settings = [reg for reg in regmap.registers if reg.kind == "setting"]
    values = dict(now)
    late = []
    for reg in settings:
        (field,) = reg.fields
        values[reg.address] = field.limits[1]
        late.append(["w-late", reg.address, field.limits[1], 0xF, OKAY])
    probes = [["r-probe-all" if i % 2 else "r-probe", reg.address, OKAY, values[reg.address]]
              for i, reg in enumerate(regmap.registers)]
    restore = [["w", reg.address, now[reg.address], 0xF, OKAY] for reg in settings]
    return late + probes + restore


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


def shift_steps(cfg: DPConfig) -> tuple:
    """The beats and steps of the ``shifts`` run: for every histogram shift s = 0 … B_E − 1,
    in that order, two segments of K = 1 (one frame of uniform noise each), n = C and
    n = C / 4 written with s before them (taken at the segment's first pixel): one list of
    each pair holds every pixel (T = 0), each selected by the comparison at shift s (the
    other runs need not draw every s); every list against the model."""
    import numpy as np

    from dptbd.sim.axi.stimulus import clean_beats

    rng = np.random.default_rng([0, 0xA7C])
    frames = rng.integers(0, 1 << cfg.input_bits,
                          size=(2 * cfg.energy_bits, cfg.height, cfg.width))
    beats = clean_beats(frames)
    frame = cfg.width * cfg.height
    steps = [{"writes": [["SEGMENT_FRAMES", 1], ["CANDIDATE_COUNT", n],
                         ["HISTOGRAM_SHIFT", s]], "stop": (2 * s + j + 1) * frame}
             for s in range(cfg.energy_bits)
             for j, n in enumerate((cfg.record_capacity, cfg.record_capacity // 4))]
    return beats, steps


def line_end_steps(cfg: DPConfig) -> tuple:
    """The beats and steps of the ``line-ends`` run: 8 frames of two targets (K = 2, n = C)
    whose last line in frames 0, 2, 3 and 6 comes without ``tlast``: W beats, then the next
    frame's start of frame, which begins a new line (no ``line_length`` fault; the fault
    runs drop ``tlast`` only on a frame's first line, whose next beat is the line after
    it); the lists and the fault counters against the model."""
    import numpy as np

    from dptbd.sim.axi.stimulus import Beats, clean_beats
    from dptbd.sim.scenarios import make_frames

    beats = clean_beats(make_frames("two-targets", cfg, 8, seed=0))
    frame = cfg.width * cfg.height
    last = np.asarray(beats.last).copy()
    for j in (0, 2, 3, 6):
        last[(j + 1) * frame - 1] = False
    return Beats(beats.pixel, beats.first, last), [
        {"writes": [["CANDIDATE_COUNT", cfg.record_capacity]], "stop": len(beats)}]


#: The weight LUT entry (p, m) of the ``lut-entry`` run.
LUT_ENTRY = (3, 8)


def lut_entry_codes(cfg: DPConfig, entry: tuple[int, int] = LUT_ENTRY) -> list[list[int]]:
    """The LUT of the ``lut-entry`` run: column p (move p) at 2**F in every row, so that
    most pixels take direction p; entry (p, m) at 2**F - 1 (odd: its bit 0 counts), every
    other code 1. From a predecessor of direction p, move m is then the runner-up of move
    p and wins wherever its neighbour is the larger."""
    p, m = entry
    unity = 1 << cfg.weight_frac_bits
    codes = [[1] * cfg.n_moves for _ in range(cfg.n_moves + 1)]
    for row in codes:
        row[p] = unity
    codes[p][m] = unity - 1
    return codes


def lut_entry_steps(cfg: DPConfig) -> tuple:
    """The beats and steps of the ``lut-entry`` run: :func:`lut_entry_codes` written from
    the first beat, 8 frames of uniform noise, K = K_max, n = C (every pixel's E and
    direction in the lists): a code of :data:`LUT_ENTRY` with bit 0 changed changes the
    lists (``tests/sim/mutation/slices/axi/test_registers.py`` shows it on the model)."""
    import numpy as np

    from dptbd.sim.axi.stimulus import clean_beats

    rng = np.random.default_rng([0, 0xA7D])
    beats = clean_beats(rng.integers(0, 1 << cfg.input_bits, size=(8, cfg.height, cfg.width)))
    return beats, [{"writes": [["SEGMENT_FRAMES", cfg.k_max],
                               ["CANDIDATE_COUNT", cfg.record_capacity]],
                    "lut_codes": lut_entry_codes(cfg), "stop": len(beats)}]


#: The thresholds the ``low-shift`` run's lists are cut at, in order (list 0 is empty: the
#: first list after reset).
LOW_SHIFT_THRESHOLDS = tuple(range(16, -1, -1))


def low_shift_steps(cfg: DPConfig) -> tuple:
    """The beats and steps of the ``low-shift`` run: s = 1, K = 1, one frame of uniform
    noise below 2**(b + 1) per list (every E in a bin of its own at s = 1, none clamped),
    each frame's n the count of its pixels in the bins at or above the next list's
    threshold, so that the lists are cut at :data:`LOW_SHIFT_THRESHOLDS` (2**b, then
    every bin from the top down to 0): the selection ``E[1:] >= T`` of low energies at
    every T, every list against the model."""
    import numpy as np

    from dptbd.sim.axi.stimulus import clean_beats

    rng = np.random.default_rng([0, 0xA7E])
    top = 1 << (cfg.histogram_bits + 1)
    assert top <= 1 << cfg.input_bits
    frames = rng.integers(0, top, size=(len(LOW_SHIFT_THRESHOLDS), cfg.height, cfg.width))
    beats = clean_beats(frames)
    frame = cfg.width * cfg.height
    counts = [int(((f >> 1) >= t).sum()) for f, t in zip(frames, LOW_SHIFT_THRESHOLDS[1:])]
    counts.append(cfg.record_capacity)
    steps = [{"writes": [["SEGMENT_FRAMES", 1], ["HISTOGRAM_SHIFT", 1],
                         ["CANDIDATE_COUNT", min(n, cfg.record_capacity)]],
              "stop": (j + 1) * frame} for j, n in enumerate(counts)]
    return beats, steps


def list_length_steps(cfg: DPConfig) -> tuple:
    """The beats and steps of the ``list-lengths`` run: K = 1 and n = C - 1 from the first
    beat; frame 0 has C - 1 bright pixels, then one frame for each m = 1 ... C - 1 in a
    seeded order, then one of m = C: m bright pixels (at least 2**s: bin 1 and up; the
    frame's last pixel among them), the others 0. Each frame before the last has at most
    C - 1 pixels in bins 1 and up and one at least in bin 0, so the next list's T is 1 and
    it holds exactly its frame's bright pixels: every list length, each ending with a
    selected pixel (a compare of the emitter's count with a constant is seen at every
    count), every list against the model."""
    import numpy as np

    from dptbd.sim.axi.stimulus import clean_beats

    from dptbd.sim.mutation.slices.segmenter import list_length_frames

    rng = np.random.default_rng([0, 0xA7F])
    size, capacity = cfg.width * cfg.height, cfg.record_capacity
    assert capacity <= size
    lengths = list(range(1, capacity))
    rng.shuffle(lengths)
    frames = list_length_frames(cfg, lengths, rng).astype(np.int64)
    beats = clean_beats(frames.reshape(-1, cfg.height, cfg.width))
    return beats, [{"writes": [["SEGMENT_FRAMES", 1], ["CANDIDATE_COUNT", capacity - 1]],
                    "stop": len(beats)}]


#: Output back-pressure of the ``full-fifo`` run (:func:`full_fifo_steps`).
FULL_FIFO_PAUSE = 0.97


def full_fifo_steps(cfg: DPConfig) -> tuple:
    """The beats and steps of the ``full-fifo`` run, under output back-pressure
    :data:`FULL_FIFO_PAUSE`: 24 frames of uniform noise at K = 1 and n = C, every pixel a
    record: the emitter is full, the segmenter takes a state only as the output drains, so
    the DP output FIFO stays full and its credits stall the input before nearly every pixel,
    a frame's last one among them (the flags of a word waiting in the FIFO are read long
    after they were written), every list against the model."""
    import numpy as np

    from dptbd.sim.axi.stimulus import clean_beats

    rng = np.random.default_rng([0, 0xA80])
    beats = clean_beats(rng.integers(0, 1 << cfg.input_bits, size=(24, cfg.height, cfg.width)))
    return beats, [{"writes": [["SEGMENT_FRAMES", 1], ["CANDIDATE_COUNT", cfg.record_capacity]],
                    "stop": len(beats)}]
