"""``RegisterFile(bounds_registered=True)`` (the ECP5 build's range check of a written
setting by bytes, from flags of the current value kept in registers) against the generic
check: every output in every cycle the same, under random writes of values at and around
the settings' limits with random byte strobes, reads, and late responses; and
``RegisterFile(refusal_registered=True)`` against the same file without."""

import numpy as np
import pytest
from amaranth.lib.wiring import Out

from dptbd.hw.register_file import RegisterFile
from dptbd.hw.register_map import register_map
from helpers.hw_harness import simulate
from helpers.seg_harness import make_config


def lockstep(cfg, regmap, seed, cycles, replay=None, spread=0.2, others=None, **options):
    """Every output of a ``RegisterFile(cfg, regmap, **options)`` in every cycle under a
    random stimulus (or ``replay``'s, the stimulus of an earlier trace), with the settings'
    values (``options`` default: ``bounds_registered`` when replaying); ``spread``: the
    share of writes to any register (or to one of ``others``) rather than a setting."""
    options = options or {"bounds_registered": replay is not None}
    dut = RegisterFile(cfg, regmap, **options)
    rng = np.random.default_rng(seed)
    settings = [reg for reg in regmap.registers if reg.kind == "setting"]
    addresses = [reg.address for reg in regmap.registers]
    targets = addresses if others is None else others
    near = sorted({v & 0xFFFFFFFF for reg in settings for lim in reg.fields[0].limits
                   for v in (lim - 1, lim, lim + 1, lim ^ 0x100, lim + 0x100, lim << 8)})
    outputs = [(path, value) for path, member, value in dut.signature.flatten(dut)
               if member.flow == Out]
    axil = dut.axil
    trace = []

    async def bench(ctx):
        for cycle in range(cycles):
            if replay is not None:
                draw = replay[cycle][0]
            else:
                reg = settings[rng.integers(len(settings))]
                draw = {
                    "awvalid": int(rng.random() < 0.3),
                    "awaddr": int(reg.address if rng.random() < 1 - spread
                                  else rng.choice(targets)),
                    "wvalid": int(rng.random() < 0.3),
                    "wdata": int(rng.choice(near) if rng.random() < 0.7
                                 else rng.integers(1 << 32, dtype=np.uint64)),
                    "wstrb": int(0xF if rng.random() < 0.5 else rng.integers(16)),
                    "bready": int(rng.random() < 0.6),
                    "arvalid": int(rng.random() < 0.2),
                    "araddr": int(rng.choice(addresses)),
                    "rready": int(rng.random() < 0.6),
                }
            for name, value in draw.items():
                channel = name[:2] if name[:2] in ("aw", "ar") else name[0]
                ctx.set(getattr(getattr(axil, channel), name), value)
            out = tuple(ctx.get(value) for _path, value in outputs)
            trace.append((draw, out))
            await ctx.tick()

    simulate(dut, bench)
    return trace, [path for path, _v in outputs]


@pytest.mark.parametrize("store", [None, (4, 12), (64, 16)],
                         ids=["plain", "state_store", "state_store_512"])
def test_bounds_registered_answers_as_the_generic_check(store):
    """Two-byte settings (C = 600), K >= 1 (a lower limit), and with the state store in
    external memory STATE_BASE (32 bits, a multiple of the burst: 32 bytes, or 512, whose
    low bits span two bytes): the same outputs."""
    cfg = make_config(width=32, height=32, candidate_count=300)
    store_cfg = (None if store is None else
                 cfg.axi_store(data_bits=64, burst_beats=store[0], address_bits=store[1]))
    regmap = register_map(cfg, store_cfg)
    generic, paths = lockstep(cfg, regmap, 3, 6000)
    registered, _ = lockstep(cfg, regmap, 3, 6000, replay=generic)
    for cycle, ((_d, want), (_e, got)) in enumerate(zip(generic, registered)):
        assert got == want, (cycle, [p for p, a, b in zip(paths, want, got) if a != b])
    # not vacuous: writes taken and refused, with partial strobes, on every setting
    out = dict(zip(paths, zip(*[o for _d, o in generic])))
    bresp = [r for r, v, d in zip(out[("axil", "b", "bresp")], out[("axil", "b", "bvalid")],
                                  [d for d, _o in generic]) if v & d["bready"]]
    assert bresp.count(0) > 100 and bresp.count(2) > 100
    for reg in regmap.registers:
        if reg.kind == "setting":
            lo, hi = reg.fields[0].limits
            values = set(out[(reg.fields[0].name,)])
            assert len(values) >= min(3, hi - lo + 1), (reg.name, values)


@pytest.mark.parametrize("bounds", [False, True], ids=["generic", "bounds_registered"])
def test_a_refusal_sets_its_bits_a_cycle_later(bounds):
    """``refusal_registered=True`` (the ECP5 build's: a refused write sets its sticky bits
    from a register, a cycle later) against the same file without: every output but
    ``irq`` the same in every cycle (so every read, of ``ERROR`` and ``IRQ_STATUS`` too),
    and ``irq`` the same but in the cycle after a refused write, where it is the cycle
    before's."""
    cfg = make_config(width=32, height=32, candidate_count=300)
    regmap = register_map(cfg)
    # half the writes to IRQ_STATUS / IRQ_ENABLE: the fault bit enabled and cleared often
    irq_regs = [reg.address for reg in regmap.registers if reg.name.startswith("IRQ_")]
    generic, paths = lockstep(cfg, regmap, 5, 6000, spread=0.5, others=irq_regs,
                              bounds_registered=bounds)
    registered, _ = lockstep(cfg, regmap, 5, 6000, replay=generic, spread=0.5,
                             others=irq_regs, bounds_registered=bounds,
                             refusal_registered=True)
    irq = paths.index(("irq",))
    rest = [i for i in range(len(paths)) if i != irq]
    # the refused writes: bvalid raised with SLVERR on a setting's range (w_stb the cycle
    # before), seen from the generic trace's outputs
    bvalid, bresp = paths.index(("axil", "b", "bvalid")), paths.index(("axil", "b", "bresp"))
    raised = {c for c in range(1, len(generic))
              if generic[c][1][bvalid] and not generic[c - 1][1][bvalid]}
    late = 0
    for cycle, ((_d, want), (_e, got)) in enumerate(zip(generic, registered)):
        assert [got[i] for i in rest] == [want[i] for i in rest], cycle
        if got[irq] != want[irq]:
            # the cycle after a write: irq is the cycle before's
            assert cycle in raised and want[irq] and not got[irq], cycle
            assert registered[cycle + 1][1][irq] == generic[cycle + 1][1][irq], cycle
            late += 1
    # not vacuous: refused writes raised irq a cycle later
    assert sum(generic[c][1][bresp] == 2 for c in raised) > 50
    assert late > 10


def test_handshake_apart_answers_as_the_generic_port():
    """``handshake_apart=True`` (the ECP5 build's: the AW and W handshakes from a copy of
    the port's ``busy``, the AR handshake from a register of its own): every output the
    same in every cycle."""
    cfg = make_config(width=32, height=32, candidate_count=300)
    regmap = register_map(cfg)
    generic, paths = lockstep(cfg, regmap, 7, 4000)
    apart, _ = lockstep(cfg, regmap, 7, 4000, replay=generic, handshake_apart=True)
    for cycle, ((_d, want), (_e, got)) in enumerate(zip(generic, apart)):
        assert got == want, (cycle, [p for p, a, b in zip(paths, want, got) if a != b])
    out = dict(zip(paths, zip(*[o for _d, o in generic])))
    assert sum(out[("axil", "b", "bvalid")]) > 500 and sum(out[("axil", "r", "rvalid")]) > 100
