"""AxiQuiet: bursts in flight per direction and ``quiet``, cycle by cycle, against a
reference count of the handshakes (Glasgow's ``cases`` / ``ref_*`` / ``rtl_*``)."""

import numpy as np

from dptbd.hw.axi_store.quiet import QUIET_INPUTS, AxiQuiet
from helpers.hw_harness import simulate


def cases(seed: int, cycles: int, outstanding: int):
    """Per cycle ``{signal: 0/1}``: a manager that keeps at most ``outstanding`` bursts in
    flight per direction, read bursts of 1 to 3 beats, one-beat writes whose W may come
    before, with or after their AW (AXI4 allows each), random ready / valid on both sides;
    it issues new bursts only in the first 60 of every 100 cycles (then the port drains)."""
    rng = np.random.default_rng(seed)
    reads, beats_left = 0, []                   # beats of each read burst still to come
    writes = []                                 # per write burst: [AW taken, W taken]
    arvalid = awvalid = False
    for cycle in range(cycles):
        issuing = cycle % 100 < 60
        arvalid = arvalid or (issuing and reads < outstanding and rng.random() < 0.3)
        if issuing and len(writes) < outstanding and rng.random() < 0.3:
            writes.append([False, False])       # a new burst: its AW and W each come later
        if not awvalid and any(not w[0] for w in writes) and rng.random() < 0.4:
            awvalid = True
        unsent = [w for w in writes if not w[1]]
        ready = [w for w in writes if w[0] and w[1]]
        step = {"arvalid": arvalid, "arready": rng.random() < 0.5,
                "rvalid": bool(beats_left) and rng.random() < 0.6, "rready": rng.random() < 0.8,
                "awvalid": awvalid, "awready": rng.random() < 0.5,
                "wvalid": bool(unsent) and rng.random() < 0.7,
                "bvalid": bool(writes) and writes[0] in ready and rng.random() < 0.5,
                "bready": rng.random() < 0.8}
        step["rlast"] = step["rvalid"] and beats_left[0] == 1
        if step["arvalid"] and step["arready"]:
            reads += 1
            beats_left.append(int(rng.integers(1, 4)))
            arvalid = False
        if step["rvalid"] and step["rready"]:
            beats_left[0] -= 1
            if beats_left[0] == 0:
                beats_left.pop(0)
                reads -= 1
        if step["awvalid"] and step["awready"]:
            next(w for w in writes if not w[0])[0] = True
            awvalid = False
        if step["wvalid"] and rng.random() < 0.5:           # WREADY: the beat taken
            unsent[0][1] = True
        if step["bvalid"] and step["bready"]:
            writes.pop(0)
        yield {k: int(v) for k, v in step.items()}


def ref_quiet(steps):
    """(reads, writes, quiet) in each cycle."""
    reads = writes = 0
    out = []
    for s in steps:
        quiet = reads == 0 and writes == 0 and not (s["arvalid"] or s["awvalid"] or s["wvalid"])
        out.append((reads, writes, int(quiet)))
        reads += (s["arvalid"] & s["arready"]) - (s["rvalid"] & s["rready"] & s["rlast"])
        writes += (s["awvalid"] & s["awready"]) - (s["bvalid"] & s["bready"])
    return out


def rtl_quiet(steps, outstanding):
    dut = AxiQuiet(outstanding)
    out = []

    async def bench(ctx):
        for s in steps:
            for name in QUIET_INPUTS:
                ctx.set(getattr(dut, name), s[name])
            out.append((ctx.get(dut.reads), ctx.get(dut.writes), ctx.get(dut.quiet)))
            await ctx.tick()

    simulate(dut, bench)
    return out


def test_quiet_counts_bursts_in_flight_cycle_by_cycle():
    for seed, outstanding in ((1, 1), (2, 2), (3, 3)):
        steps = list(cases(seed, 600, outstanding))
        want = ref_quiet(steps)
        assert rtl_quiet(steps, outstanding) == want
        assert 0 < sum(q for *_, q in want) < len(want)        # both states visited
        assert max(r for r, *_ in want) == outstanding          # the limit reached
        # W offered before its AW was taken, nothing else in flight: not quiet
        assert any(s["wvalid"] and not s["awvalid"] and r == w == 0
                   for s, (r, w, _q) in zip(steps, want))
