"""Frame/segment controller: positions, flags, read-ahead addresses and resynchronisation."""

import random


from dptbd.config import DPConfig
from dptbd.hw.controller import Controller
from helpers.hw_harness import simulate


def reference_positions(cfg, firsts, ks=None):
    """Expected (read_addr, next_read_addr, resync, segment_begin, row, col, flags…) for each accepted pixel;
    ``ks[i]`` is the run-time K on the port when pixel i is accepted (sampled at a segment's
    first pixel, clamped to [1, K_max]). Recursive mode (§8.6): one-frame output segments,
    ``segment_start`` only until the first frame after reset or a resync has ended."""
    width, height, k = cfg.width, cfg.height, cfg.segment_frames
    ks = [cfg.segment_frames] * len(firsts) if ks is None else ks
    pixels = width * height
    ahead = cfg.radius * (width + 1)
    position, frame = 0, 0
    recursing = False
    out = []
    for first, k_port in zip(firsts, ks):
        resync = bool(first) and position != 0
        if resync:
            position, frame, recursing = 0, 0, False
        begins = position == 0 and frame == 0
        if begins:
            k = 1 if cfg.recursive else min(max(k_port, 1), cfg.k_max)
        start = not recursing if cfg.recursive else frame == 0
        row, col = divmod(position, width)
        eol = col == width - 1
        eof = eol and row == height - 1
        out.append({
            "read_addr": (position + ahead) % pixels,
            "next_read_addr": (position + ahead + 1) % pixels, "resync": int(resync),
            "segment_begin": int(begins),
            "row": row, "col": col, "start_of_frame": int(position == 0),
            "segment_start": int(start), "end_of_line": int(eol),
            "end_of_frame": int(eof), "end_of_segment": int(eof and frame == k - 1),
            "row_inside": sum(1 << i for i in range(2 * cfg.radius + 1)
                              if 0 <= row + cfg.radius - i < height),
            "col_inside": sum(1 << i for i in range(2 * cfg.radius + 1)
                              if 0 <= col + cfg.radius - i < width),
        })
        position = (position + 1) % pixels
        if eof:
            frame = (frame + 1) % k
            recursing = True
    return out


def run_controller(cfg, firsts, seed=0, ks=None):
    """The outputs per accepted pixel, the same for ``registered=True`` (the ECP5 build's
    end of segment) as for the generic controller under the same stimulus."""
    got = run_build(cfg, firsts, seed, ks, registered=False)
    assert run_build(cfg, firsts, seed, ks, registered=True) == got
    return got


def run_build(cfg, firsts, seed, ks, *, registered):
    dut = Controller(cfg, registered=registered)
    rng = random.Random(seed)
    got = []
    ks = [cfg.segment_frames] * len(firsts) if ks is None else ks

    async def bench(ctx):
        pending = None
        index = 0
        while index < len(firsts) or pending is not None:
            accept = index < len(firsts) and rng.random() < 0.7
            ctx.set(dut.accept, accept)
            ctx.set(dut.first, firsts[index] if accept else rng.random() < 0.5)
            ctx.set(dut.segment_frames, ks[index] if accept else rng.randrange(1 << len(
                dut.segment_frames)))
            if pending is not None:
                assert ctx.get(dut.valid) == 1
                position = ctx.get(dut.position)
                pending.update({name: getattr(position, name) for name in (
                    "row", "col", "start_of_frame", "segment_start", "end_of_line",
                    "end_of_frame", "end_of_segment")})
                pending.update(row_inside=ctx.get(dut.row_inside),
                               col_inside=ctx.get(dut.col_inside))
                got.append(pending)
                pending = None
            else:
                assert ctx.get(dut.valid) == 0
            if accept:
                pending = {"read_addr": ctx.get(dut.read_addr),
                           "next_read_addr": ctx.get(dut.next_read_addr),
                           "resync": ctx.get(dut.resync),
                           "segment_begin": ctx.get(dut.segment_begin)}
                index += 1
            else:
                assert ctx.get(dut.segment_begin) == 0
            await ctx.tick()

    simulate(dut, bench)
    return got


def test_counts_frames_and_segments():
    cfg = DPConfig(width=4, height=3, segment_frames=3)
    firsts = [index % 12 == 0 for index in range(12 * 7)]
    assert run_controller(cfg, firsts) == reference_positions(cfg, firsts)


def test_missing_first_flags_are_ignored():
    cfg = DPConfig(width=5, height=4, segment_frames=2, radius=1)
    firsts = [False] * (20 * 3)
    assert run_controller(cfg, firsts, seed=1) == reference_positions(cfg, firsts)


def test_unexpected_first_restarts_the_segment():
    cfg = DPConfig(width=5, height=4, segment_frames=3, radius=2)
    # A full frame, 7 pixels of a second one, then frames with `first` again.
    firsts = [i == 0 for i in range(20)] + [i == 0 for i in range(7)] \
        + [i % 20 == 0 for i in range(20 * 4)]
    got = run_controller(cfg, firsts, seed=2)
    want = reference_positions(cfg, firsts)
    assert got == want
    assert [n for n, g in enumerate(got) if g["resync"]] == [27]
    assert got[27]["segment_start"] == 1 and got[27]["read_addr"] == 12


def test_single_frame_segments():
    cfg = DPConfig(width=3, height=3, segment_frames=1)
    firsts = [i % 9 == 0 for i in range(9 * 3)]
    got = run_controller(cfg, firsts, seed=3)
    assert got == reference_positions(cfg, firsts)
    assert all(g["segment_start"] for g in got)
    assert sum(g["end_of_segment"] for g in got) == 3


def test_run_time_k_is_sampled_at_each_segment_start():
    """K changes between and inside segments: each segment uses the K on the port at its
    first pixel; mid-segment writes wait for the next segment start."""
    cfg = DPConfig(width=3, height=3, segment_frames=2, max_segment_frames=5)
    ks_per_segment = [3, 1, 5, 2, 4]
    firsts, ks = [], []
    for k in ks_per_segment:
        for f in range(k):
            firsts += [i == 0 for i in range(9)]
            ks += [k] * 9 if f == 0 else [random.Random(f).randint(1, 5)] * 9   # ignored
        ks[-9 * k] = k
    got = run_controller(cfg, firsts, seed=4, ks=ks)
    assert got == reference_positions(cfg, firsts, ks)
    assert [n for n, g in enumerate(got) if g["end_of_segment"]] == \
        [9 * sum(ks_per_segment[:j + 1]) - 1 for j in range(len(ks_per_segment))]
    assert sum(g["segment_begin"] for g in got) == len(ks_per_segment)


def test_run_time_k_out_of_range_is_clamped():
    """K = 0 counts as 1 and K above K_max as K_max (the register block never writes them)."""
    cfg = DPConfig(width=3, height=3, segment_frames=1, max_segment_frames=2)
    ks = [0] * 9 + [3] * 18 + [2] * 18            # K port: 0, then 3 (> K_max = 2)
    firsts = [i % 9 == 0 for i in range(len(ks))]
    got = run_controller(cfg, firsts, seed=5, ks=ks)
    assert got == reference_positions(cfg, firsts, ks)
    assert [n for n, g in enumerate(got) if g["end_of_segment"]] == [8, 26, 44]


def test_recursive_mode_starts_only_after_reset_and_resync():
    """§8.6: the first frame after reset and after a resync is a start frame, no other;
    every frame ends a one-frame output segment and the run-time K is ignored."""
    cfg = DPConfig(width=5, height=4, segment_frames=3, recursive=True)
    firsts = [i % 20 == 0 for i in range(20 * 3)] + [i == 0 for i in range(9)] \
        + [i % 20 == 0 for i in range(20 * 3)]
    ks = [random.Random(i).randrange(1, 4) for i in range(len(firsts))]
    got = run_controller(cfg, firsts, seed=4, ks=ks)
    assert got == reference_positions(cfg, firsts, ks)
    starts = [n for n, g in enumerate(got) if g["segment_start"]]
    assert starts == list(range(20)) + list(range(69, 89))   # frame 0, then after the resync at 69
    assert sum(g["end_of_segment"] for g in got) == sum(g["end_of_frame"] for g in got) == 6
