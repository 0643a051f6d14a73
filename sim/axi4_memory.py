"""A Python AXI4 subordinate (memory) for the Amaranth simulator, adversarial and strict
(used by the AXI4 state store's tests, ``tests/hw/test_axi_*.py``, and
``benchmarks/bench_axi_store.py``).

:class:`Axi4Memory` answers an AXI4 manager port (:func:`dptbd.hw.axi_store.bus.axi4_signature`)
with a random latency per burst and random ready/valid on every channel, and checks every
AXI4 rule it sees: INCR bursts of full-width beats, at most 256 beats, never crossing a
4 KB boundary, full write strobes, ``WLAST`` on exactly the last beat, no more bursts in
flight than allowed, and valid/payload held until the handshake.

It is adversarial about ordering: a read takes the memory's contents when its address is
accepted, and a write changes them only when its response is sent, so a read issued
before an earlier write's response may see the old data, as AXI4 allows. Bytes never
written read as seeded random values. ``errors`` maps byte addresses to a response code:
a read beat or a write burst that touches one gets that response, like a failing DRAM: the
read beat carries garbage, the write is not applied. With ``once=True`` an address fails
only its first read beat and its first write burst (a transient fault).
"""

from __future__ import annotations

import collections
import dataclasses
import random

from amaranth.hdl import Elaboratable, Module
from amaranth.lib import wiring

from dptbd.config import AxiStoreConfig
from dptbd.hw.axi_store.bus import BURST_INCR, axi4_signature, size_code


class AxiRuleError(AssertionError):
    """The manager broke an AXI4 rule."""


@dataclasses.dataclass
class Axi4Memory:
    """Memory model behind ``port`` (the DUT's ``axi`` member, or a DUT with flat AXI ports
    and a ``channel(name)`` method), see the module doc.

    Parameters
    ----------
    latency : (int, int)
        Cycles from a read address handshake to the first read beat, and from a write's
        last beat to its response, uniform in this closed range.
    write_latency : (int, int) or None
        The write responses' own range, when it differs (slow writes, fast reads: the
        case where a read could overtake an earlier write).
    ready, valid : float
        Probability of each ready (AR, AW, W) and each valid (R, B) being high in a cycle.
    """

    port: object
    store: AxiStoreConfig
    seed: int = 0
    latency: tuple = (0, 0)
    write_latency: tuple | None = None
    ready: float = 1.0
    valid: float = 1.0
    errors: dict = dataclasses.field(default_factory=dict)
    once: bool = False

    def __post_init__(self):
        self.rng = random.Random(self.seed)
        self.contents: dict[int, int] = {}
        self.stats = collections.Counter()
        self.bursts = []                           # ("AR" | "AW", address, beats) in order
        self.used = set()                          # (address, direction) errors used up
        self.read_bursts = collections.deque()    # [due, addr, beats left, data list]
        self.write_bursts = collections.deque()   # AW accepted: [addr, beats]
        self.write_data = collections.deque()     # W beats: (data, strb, last)
        self.responses = collections.deque()      # [due, addr, data list, resp]
        self.writes_open = 0                       # AW accepted, B not yet sent
        self.cycle = 0

    # ---- memory --------------------------------------------------------------------
    def byte(self, addr: int) -> int:
        if addr not in self.contents:
            self.contents[addr] = random.Random(f"{self.seed}:{addr}").randrange(256)
        return self.contents[addr]

    def beat(self, addr: int) -> int:
        return int.from_bytes(bytes(self.byte(addr + k) for k in range(self.store.beat_bytes)),
                              "little")

    def resp(self, addr: int, beats: int, direction: str = "") -> int:
        """The response of ``beats`` beats from ``addr``: the worst error code among the
        addresses they touch (0: OKAY). With ``once``, a ``direction`` ("read" / "write")
        uses up the addresses' errors for that direction."""
        span = range(addr, addr + beats * self.store.beat_bytes)
        hits = [a for a in self.errors if a in span and (a, direction) not in self.used]
        if self.once and direction:
            self.used.update((a, direction) for a in hits)
        return max((self.errors[a] for a in hits), default=0)

    # ---- rules ---------------------------------------------------------------------
    def check_address(self, channel: str, addr: int, length: int, size: int, burst: int):
        store = self.store
        if burst != BURST_INCR:
            raise AxiRuleError(f"{channel}: burst type {burst}, expected INCR")
        if size != size_code(store.beat_bytes):
            raise AxiRuleError(f"{channel}: size {size}, expected full beats")
        if addr % store.beat_bytes:
            raise AxiRuleError(f"{channel}: address {addr:#x} not aligned to the beat")
        if length + 1 > 256:
            raise AxiRuleError(f"{channel}: {length + 1} beats > 256")
        if addr // 4096 != (addr + (length + 1) * store.beat_bytes - 1) // 4096:
            raise AxiRuleError(f"{channel}: burst at {addr:#x} of {length + 1} beats "
                               f"crosses a 4 KB boundary")
        if not (store.base_address <= addr and addr + (length + 1) * store.beat_bytes
                <= store.base_address + store.frame_bytes):
            raise AxiRuleError(f"{channel}: burst at {addr:#x} outside the frame's state")

    @staticmethod
    def check_held(name: str, before, now):
        """A valid that was high without its ready must stay high with the same payload."""
        if before is not None and before != now:
            raise AxiRuleError(f"{name}: valid or payload changed before the handshake "
                               f"({before} -> {now})")

    # ---- the process ---------------------------------------------------------------
    def process(self):
        p = self.port
        if hasattr(p, "channel"):            # flat m_axi_state_* ports (DPPipelineAxi)
            p = type("port", (), {name: p.channel(name) for name in ("ar", "r", "aw", "w", "b")})
        store = self.store
        names = [p.ar.arvalid, p.ar.araddr, p.ar.arlen, p.ar.arsize, p.ar.arburst,
                 p.aw.awvalid, p.aw.awaddr, p.aw.awlen, p.aw.awsize, p.aw.awburst,
                 p.w.wvalid, p.w.wdata, p.w.wstrb, p.w.wlast, p.r.rready, p.b.bready]
        full_strobe = (1 << store.beat_bytes) - 1

        async def run(ctx):
            rng = self.rng
            ar_ready = aw_ready = w_ready = False
            r_beat = None          # (data, resp, last) on offer
            b_resp = None
            held = {"ar": None, "aw": None, "w": None}
            async for _clk, _rst, *values in ctx.tick().sample(*names):
                (arvalid, araddr, arlen, arsize, arburst, awvalid, awaddr, awlen, awsize,
                 awburst, wvalid, wdata, wstrb, wlast, rready, bready) = values
                self.cycle += 1
                # ---- handshakes at this edge, and what the manager must hold -----------
                ar = (arvalid, araddr, arlen, arsize, arburst)
                self.check_held("AR", held["ar"], ar)
                held["ar"] = ar if arvalid and not ar_ready else None
                if arvalid and ar_ready:
                    self.check_address("AR", araddr, arlen, arsize, arburst)
                    self.bursts.append(("AR", araddr, arlen + 1))
                    if len(self.read_bursts) >= store.outstanding:
                        raise AxiRuleError(f"AR: more than {store.outstanding} reads in flight")
                    due = self.cycle + rng.randint(*self.latency)
                    codes = self.resp_list(araddr, arlen)
                    data = [rng.randrange(1 << store.data_bits) if code else
                            self.beat(araddr + k * store.beat_bytes)
                            for k, code in enumerate(codes)]
                    self.read_bursts.append([due, araddr, data, codes])
                    self.stats["read_bursts"] += 1
                    self.stats["read_beats"] += arlen + 1
                aw = (awvalid, awaddr, awlen, awsize, awburst)
                self.check_held("AW", held["aw"], aw)
                held["aw"] = aw if awvalid and not aw_ready else None
                if awvalid and aw_ready:
                    self.check_address("AW", awaddr, awlen, awsize, awburst)
                    self.bursts.append(("AW", awaddr, awlen + 1))
                    if self.writes_open >= store.outstanding:
                        raise AxiRuleError(f"AW: more than {store.outstanding} writes in flight")
                    self.writes_open += 1
                    self.write_bursts.append([awaddr, awlen + 1, []])
                    self.stats["write_bursts"] += 1
                w = (wvalid, wdata, wstrb, wlast)
                self.check_held("W", held["w"], w)
                held["w"] = w if wvalid and not w_ready else None
                if wvalid and w_ready:
                    if wstrb != full_strobe:
                        raise AxiRuleError(f"W: strobe {wstrb:#x}, expected full beats")
                    self.write_data.append((wdata, wlast))
                    self.stats["write_beats"] += 1
                self.take_write_beats()
                if r_beat is not None and rready:
                    if r_beat[2]:
                        self.read_bursts.popleft()
                    r_beat = None
                if b_resp is not None and bready:
                    due, addr, data, code = self.responses.popleft()
                    for k, beat in enumerate(data if not code else ()):  # failed: not applied
                        for j in range(store.beat_bytes):
                            self.contents[addr + k * store.beat_bytes + j] = beat >> (8 * j) & 255
                    self.writes_open -= 1
                    b_resp = None
                # ---- what this side offers in the next cycle --------------------------
                ar_ready = rng.random() < self.ready
                aw_ready = rng.random() < self.ready
                w_ready = rng.random() < self.ready
                if r_beat is None and self.read_bursts and self.read_bursts[0][0] <= self.cycle \
                        and rng.random() < self.valid:
                    burst = self.read_bursts[0]
                    data, codes = burst[2], burst[3]
                    r_beat = (data.pop(0), codes.pop(0), not data)
                if b_resp is None and self.responses and self.responses[0][0] <= self.cycle \
                        and rng.random() < self.valid:
                    b_resp = self.responses[0][3]
                ctx.set(p.ar.arready, ar_ready)
                ctx.set(p.aw.awready, aw_ready)
                ctx.set(p.w.wready, w_ready)
                ctx.set(p.r.rvalid, r_beat is not None)
                ctx.set(p.r.rdata, 0 if r_beat is None else r_beat[0])
                ctx.set(p.r.rresp, 0 if r_beat is None else r_beat[1])
                ctx.set(p.r.rlast, r_beat is not None and r_beat[2])
                ctx.set(p.b.bvalid, b_resp is not None)
                ctx.set(p.b.bresp, 0 if b_resp is None else b_resp)

        return run

    def resp_list(self, addr: int, length: int) -> list:
        return [self.resp(addr + k * self.store.beat_bytes, 1, "read")
                for k in range(length + 1)]

    def take_write_beats(self):
        """Match W beats to accepted AW bursts in order; a complete burst gets its response
        due after the latency."""
        while self.write_bursts and self.write_data:
            burst = self.write_bursts[0]
            addr, beats, data = burst
            wdata, wlast = self.write_data.popleft()
            data.append(wdata)
            if bool(wlast) != (len(data) == beats):
                raise AxiRuleError(f"W: WLAST {int(wlast)} on beat {len(data)} of {beats}")
            if len(data) == beats:
                self.write_bursts.popleft()
                due = self.cycle + self.rng.randint(*(self.write_latency or self.latency))
                self.responses.append([due, addr, data, self.resp(addr, beats, "write")])


class OneSided(Elaboratable):
    """A component with only the write (``aw``, ``w``, ``b``) or only the read (``ar``,
    ``r``) channels of an AXI4 port, given the full port ``axi`` the memory model drives
    (the other direction idle)."""

    def __init__(self, inner, store):
        self.inner = inner
        self.axi = axi4_signature(store).create()

    def elaborate(self, platform):
        m = Module()
        m.submodules.inner = self.inner
        for name in ("ar", "r", "aw", "w", "b"):
            if hasattr(self.inner, name):
                wiring.connect(m, getattr(self.inner, name), wiring.flipped(getattr(self.axi, name)))
        return m
