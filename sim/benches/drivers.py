"""cocotb verification components for the ``dptbd_dp`` module: drivers, monitors, pauses.

Structure after cocotb's ``examples/matrix_multiplier`` (driver, monitor, model, checker)
and the valid/ready pause generators of alexforencich's ``verilog-axis`` testbenches:

* :func:`pause_generator` — seeded iterators of "pause this cycle" flags;
* :class:`StreamSource` — drives ``pixels`` (valid/payload), holds a word until ``ready``,
  inserts idle cycles from a pause generator;
* :class:`StreamSink` — drives ``states.ready`` from a pause generator (back-pressure);
* :class:`StreamMonitor` — watches ``states`` and hands every transferred payload to a
  callback (the :class:`~dptbd.sim.scoreboard.Scoreboard`);
* :func:`write_lut` — writes weight codes through ``lut_addr``/``lut_data``/``lut_we``;
* :func:`start_in_reset` — the clock and the reset sequence every test starts with.

Handshakes are sampled right after the rising clock edge, before the design's registers
update in that time step (the usual cocotb idiom), so a transfer is "valid and ready both
high at the edge". A transfer at an edge where ``rst`` is high is not counted: the
synchronous reset discards it. Cycle numbers are counted from simulation time.
"""

from __future__ import annotations

import collections
import itertools
import random
from typing import Callable, Iterable, Iterator

from cocotb.clock import Clock
from cocotb.handle import SimHandleBase
from cocotb.simtime import get_sim_time
from cocotb.triggers import RisingEdge

import cocotb

__all__ = ["pause_generator", "optional_pauses", "pause_probability", "StreamSource",
           "StreamSink", "StreamMonitor", "write_lut", "Cycles", "start_in_reset"]


def pause_generator(spec: dict | None) -> Iterator[bool]:
    """Pause flags (True = idle this cycle) from a JSON-able spec.

    ``None`` or ``{"kind": "none"}``: never pause. ``{"kind": "random", "probability": p,
    "seed": s}``: each cycle pauses with probability p (seeded ``random.Random``).
    ``{"kind": "pattern", "pattern": [1, 1, 0, …]}``: the pattern repeated (verilog-axis's
    ``cycle_pause`` is ``[1, 1, 1, 0]``).
    """
    spec = spec or {"kind": "none"}
    kind = spec.get("kind", "none")
    if kind == "none":
        return itertools.repeat(False)
    if kind == "random":
        p = float(spec["probability"])
        if not 0.0 <= p < 1.0:
            raise ValueError(f"pause probability must be in [0, 1), got {p}")
        rng = random.Random(spec.get("seed", 0))
        return (rng.random() < p for _ in itertools.count())
    if kind == "pattern":
        pattern = [bool(v) for v in spec["pattern"]]
        if not pattern or all(pattern):
            raise ValueError("a pause pattern must be non-empty and contain a 0")
        return itertools.cycle(pattern)
    raise ValueError(f"unknown pause kind {kind!r}; use none, random or pattern")


def optional_pauses(spec: dict | None) -> Iterator[bool] | None:
    """:func:`pause_generator` of ``spec``, or ``None`` when it never pauses."""
    if not spec or spec.get("kind", "none") == "none":
        return None
    return pause_generator(spec)


def pause_probability(spec: dict | None) -> float:
    """The fraction of cycles a pause spec pauses (its probability, or the pattern's share
    of 1s)."""
    if not spec or spec.get("kind", "none") == "none":
        return 0.0
    if spec["kind"] == "random":
        return float(spec["probability"])
    pattern = spec["pattern"]
    return sum(map(bool, pattern)) / len(pattern)


class Cycles:
    """Cycle number of the current rising edge, from simulation time (no extra coroutine)."""

    def __init__(self, period_steps: int):
        self.period_steps = int(period_steps)

    def now(self) -> int:
        return int(get_sim_time("step")) // self.period_steps


def _is_high(handle: SimHandleBase) -> bool:
    value = handle.value
    return value.is_resolvable and bool(value)


class StreamSource:
    """Drives a valid/ready stream (the ``pixels`` input), one word per transfer.

    Parameters
    ----------
    clock, valid, ready, payload : handles
        ``clk``, ``pixels__valid``, ``pixels__ready``, ``pixels__payload``.
    reset : handle, optional
        ``rst``; a handshake at an edge with reset high is not a transfer.
    pause : iterator of bool
        Idle cycles (:func:`pause_generator`); a word once offered is held until taken.
    cycles : Cycles
        Cycle numbering.
    on_accept : callable, optional
        ``on_accept(index, cycle)`` for every transferred word (index from 0).
    """

    def __init__(self, clock, valid, ready, payload, *, cycles: Cycles, reset=None,
                 pause: Iterator[bool] | None = None,
                 on_accept: Callable[[int, int], None] | None = None):
        self._clock, self._valid, self._ready, self._payload = clock, valid, ready, payload
        self._reset = reset
        self._pause = pause if pause is not None else itertools.repeat(False)
        self._cycles = cycles
        self._on_accept = on_accept
        self._queue: collections.deque[int] = collections.deque()
        self._offering = False
        self.accepted = 0
        self.accept_cycles: list[int] = []
        self.idle = cocotb.triggers.Event()
        self.idle.set()
        self._valid.value = 0
        self._task = cocotb.start_soon(self._run())

    def send(self, words: Iterable[int]) -> None:
        """Queue payload words (already packed)."""
        self._queue.extend(int(w) for w in words)
        if self._queue:
            self.idle.clear()

    def clear(self) -> None:
        """Drop every queued word and stop offering (e.g. when reset is asserted)."""
        self._queue.clear()
        self._offering = False
        self._valid.value = 0
        self.idle.set()

    def kill(self) -> None:
        self._task.cancel()

    async def _run(self) -> None:
        edge = RisingEdge(self._clock)
        ready, valid, payload = self._ready, self._valid, self._payload
        reset = self._reset
        while True:
            await edge
            if self._offering and _is_high(ready) and not (reset is not None and _is_high(reset)):
                self._queue.popleft()
                cycle = self._cycles.now()
                self.accept_cycles.append(cycle)
                if self._on_accept is not None:
                    self._on_accept(self.accepted, cycle)
                self.accepted += 1
                self._offering = False
            if self._offering:
                continue                       # hold the word until it is taken
            if self._queue and not next(self._pause):
                payload.value = self._queue[0]
                valid.value = 1
                self._offering = True
            else:
                valid.value = 0
                if not self._queue:
                    self.idle.set()


class StreamSink:
    """Drives ``ready`` of a stream output (``states``) from a pause generator."""

    def __init__(self, clock, ready, *, pause: Iterator[bool] | None = None):
        self._clock, self._ready = clock, ready
        self._pause = pause
        self._ready.value = 1
        self._task = cocotb.start_soon(self._run()) if pause is not None else None

    def kill(self) -> None:
        if self._task is not None:
            self._task.cancel()

    async def _run(self) -> None:
        edge = RisingEdge(self._clock)
        ready, pause = self._ready, self._pause
        current = 1
        while True:
            await edge
            new = 0 if next(pause) else 1
            if new != current:
                ready.value = new
                current = new


class StreamMonitor:
    """Watches a valid/ready stream and hands each transferred payload to ``callback``.

    ``callback(word, cycle)``; ``ready`` is sampled from the bus, so the monitor works
    with any sink.
    """

    def __init__(self, clock, valid, ready, payload, callback: Callable[[int, int], None], *,
                 cycles: Cycles, reset=None):
        self._clock, self._valid, self._ready, self._payload = clock, valid, ready, payload
        self._reset = reset
        self._callback = callback
        self._cycles = cycles
        self.count = 0
        self.first_cycle: int | None = None
        self.last_cycle: int | None = None
        self._task = cocotb.start_soon(self._run())

    def kill(self) -> None:
        self._task.cancel()

    async def _run(self) -> None:
        edge = RisingEdge(self._clock)
        valid, ready, payload, reset = self._valid, self._ready, self._payload, self._reset
        while True:
            await edge
            if _is_high(valid) and _is_high(ready) and not (reset is not None and _is_high(reset)):
                cycle = self._cycles.now()
                if self.first_cycle is None:
                    self.first_cycle = cycle
                self.last_cycle = cycle
                self.count += 1
                self._callback(payload.value.to_unsigned(), cycle)


async def write_lut(clock, addr, data, we, writes: Iterable[tuple[int, int]]) -> int:
    """Write ``(address, code)`` pairs, one per cycle; returns the number written.

    Address ``cfg.lut_address(p, m)`` (``p * M + m``) is the code of move m for predecessor
    direction p (``docs/gateware.md``). Call it while no pixel is offered: a write applies
    to every pixel accepted in the same cycle or later.
    """
    edge = RisingEdge(clock)
    n = 0
    for address, code in writes:
        addr.value = int(address)
        data.value = int(code)
        we.value = 1
        await edge
        n += 1
    we.value = 0
    return n


async def start_in_reset(dut, period_ns: int, output_ready, settings=None) -> Cycles:
    """Start ``dut.clk`` (``period_ns``), hold ``rst`` for three rising edges with no pixel
    offered, no LUT write and ``output_ready`` high, and release it. ``settings`` maps
    run-time setting ports to the values they hold from now on (a Verilog input has no
    reset value: ``{"segment_frames": cfg.segment_frames, ...}``).

    Returns
    -------
    Cycles
        The cycle counter, its period measured in simulator steps between two edges.
    """
    cycles = Cycles(1)
    Clock(dut.clk, period_ns, unit="ns", impl="gpi").start(start_high=False)
    dut.rst.value = 1
    dut.pixels__valid.value = 0
    dut.lut_we.value = 0
    dut.lut_addr.value = 0
    dut.lut_data.value = 0
    for name, value in (settings or {}).items():
        getattr(dut, name).value = int(value)
    output_ready.value = 1
    await RisingEdge(dut.clk)
    t0 = get_sim_time("step")
    await RisingEdge(dut.clk)
    cycles.period_steps = int(get_sim_time("step") - t0)
    await RisingEdge(dut.clk)
    dut.rst.value = 0
    return cycles
