"""Shared Amaranth-simulator harness for the gateware tests: drive streams, score results.

``run_stream`` drives a component with ``pixels``/``states`` streams and LUT write members
(``DPPipeline`` or ``DPCore`` plus a store model) cycle by cycle, with random input gaps and
random output back-pressure; ``reference_states`` computes what must come out with the
golden model ``dptbd.model.fixed``; ``assert_states_equal`` compares bit for bit and names
the first mismatching frame, row, column and field.
"""

from __future__ import annotations

import contextlib
import dataclasses
import random
import subprocess

import numpy as np
import pytest
from amaranth.hdl import Elaboratable
from amaranth.sim import Simulator

from dptbd.config import DPConfig
from dptbd.hw.layouts import pack_pixel, unpack_state
from dptbd.hw.flow.verilog import VERILATOR_LINT_FLAGS
from dptbd.model.fixed import dp_step, segment_start

FIELDS = ("energy", "direction", "end_of_line", "end_of_frame", "end_of_segment")


@dataclasses.dataclass
class StreamRun:
    """What a simulation produced."""

    outputs: list            # unpacked `states` payloads (dicts), in order
    accept_cycles: list      # cycle of each accepted pixel
    output_cycles: list      # cycle of each output transfer
    cycles: int              # cycles simulated


def simulate(dut, *testbenches, background=()) -> None:
    """Run ``dut`` on a 100 MHz clock with the async ``testbenches`` (``f(ctx)``) until they
    return; ``background`` testbenches (e.g. a memory model) run beside them."""
    sim = Simulator(dut)
    sim.add_clock(1e-8)
    for bench in testbenches:
        sim.add_testbench(bench)
    for bench in background:
        sim.add_testbench(bench, background=True)
    sim.run()


async def stream_cycle(ctx, source, sink, offering: bool, taking: bool, transfers) -> bool:
    """One clock cycle of stream ``source`` (``valid`` = ``offering``) into the DUT and
    stream ``sink`` (``ready`` = ``taking``) out of it. Appends to ``transfers`` (a
    :class:`StreamRun`-like object with ``accept_cycles``, ``outputs``, ``output_cycles``
    and ``cycles``, the current cycle): the cycle of an accepted word, and the payload and
    cycle of an output transfer. Returns whether the source word was accepted; ticks."""
    ctx.set(source.valid, offering)
    ctx.set(sink.ready, taking)
    accepted = bool(offering and ctx.get(source.ready))
    if accepted:
        transfers.accept_cycles.append(transfers.cycles)
    if taking and ctx.get(sink.valid):
        transfers.outputs.append(int(ctx.get(sink.payload.as_value())))
        transfers.output_cycles.append(transfers.cycles)
    await ctx.tick()
    transfers.cycles += 1
    return accepted


def frames_to_stream(frames: np.ndarray) -> list[tuple[int, bool]]:
    """(pixel, first) in raster order, ``first`` on pixel (0, 0) of every frame."""
    out = []
    for frame in frames:
        for index, value in enumerate(np.asarray(frame).ravel()):
            out.append((int(value), index == 0))
    return out


def lut_writes_for(cfg: DPConfig, old: np.ndarray, new: np.ndarray) -> list[tuple[int, int]]:
    """(address, code) writes turning LUT ``old`` into ``new`` (address
    :meth:`~dptbd.config.DPConfig.lut_address`)."""
    return [(cfg.lut_address(p, m), int(new[p, m]))
            for p in range(old.shape[0]) for m in range(old.shape[1]) if old[p, m] != new[p, m]]


def run_stream(dut, cfg: DPConfig, stream: list[tuple[int, bool]], *, valid_probability=1.0,
               ready_probability=1.0, seed=0, lut_writes=None, timed_lut_writes=None,
               processes=(), max_cycles=None, expected_outputs=None, on_cycle=None) -> StreamRun:
    """Simulate ``dut`` until every pixel of ``stream`` has come out.

    Parameters
    ----------
    lut_writes : dict of int to list of (address, code), optional
        Writes to issue just before the pixel with that index is offered: the input is held
        idle while they are written, one per cycle, so that pixel and all later ones use
        the new codes and no earlier pixel does. A write ``(port, address, code)`` goes to
        the write port ``port`` (``"lut"``, or paper 000's ``"merit"`` / ``"penalty"``)
        instead of the weight LUT's.
    timed_lut_writes : dict of int to (address, code), optional
        Writes presented in exactly that cycle (cycle 0 is the first after reset),
        whatever the input does; they take precedence over ``lut_writes``.
    processes : sequence of callables
        Extra async testbenches (e.g. an external state-store model), ``f(ctx)``.
    on_cycle : callable, optional
        ``f(ctx, index)`` at the start of every cycle, ``index`` the pixel on offer or next
        to be offered (e.g. to drive the run-time K).
    """
    rng = random.Random(seed)
    pending = {k: list(v) for k, v in (lut_writes or {}).items()}
    n_out = len(stream) if expected_outputs is None else expected_outputs
    if max_cycles is None:
        slow = max(valid_probability, 0.05) * max(ready_probability, 0.05)
        max_cycles = int((len(stream) + 100) / slow * 3) + 200
    result = StreamRun([], [], [], 0)
    payload_in = dut.pixels.payload.as_value()
    ports = [port for port in ("lut", "merit", "penalty") if hasattr(dut, f"{port}_we")]

    async def bench(ctx):
        accepted = 0
        offering = False
        while len(result.outputs) < n_out:
            cycle = result.cycles
            if cycle >= max_cycles:
                raise AssertionError(
                    f"timeout after {cycle} cycles: {accepted}/{len(stream)} pixels accepted, "
                    f"{len(result.outputs)}/{n_out} states out")
            writes = pending.get(accepted)
            timed = (timed_lut_writes or {}).get(cycle)
            if timed is not None:
                write = timed
            elif writes and not offering:
                write = writes.pop(0)
            else:
                write = None
            port = None if write is None else "lut" if len(write) == 2 else write[0]
            for name in ports:
                ctx.set(getattr(dut, f"{name}_we"), name == port)
            if write is not None:
                ctx.set(getattr(dut, f"{port}_addr"), write[-2])
                ctx.set(getattr(dut, f"{port}_data"), write[-1])
            hold_input = write is not None and timed is None  # queued writes idle the input
            if not hold_input and not offering and accepted < len(stream):
                offering = rng.random() < valid_probability
                if offering:
                    pixel, first = stream[accepted]
                    ctx.set(payload_in, pack_pixel(cfg, pixel, first))
            taking = rng.random() < ready_probability
            if on_cycle is not None:
                on_cycle(ctx, accepted)
            if await stream_cycle(ctx, dut.pixels, dut.states, offering, taking, result):
                accepted += 1
                offering = False
        result.outputs[:] = [unpack_state(cfg, word) for word in result.outputs]

    simulate(dut, bench, background=processes)
    return result


def reference_states(cfg: DPConfig, frames: np.ndarray, lut_changes=()) -> np.ndarray:
    """Expected ``states`` of every pixel: array ``(T, H, W, 5)`` in :data:`FIELDS` order.

    Frames are grouped into segments of K from frame 0 (``segment_start`` on frames
    0, K, 2K, …, ``dp_step`` on the others). ``lut_changes`` is a sequence of
    ``(pixel_index, codes)``: from that global pixel index on, the LUT is ``codes``.
    """
    frames = np.asarray(frames)
    n_frames, height, width = frames.shape
    k = cfg.segment_frames
    tables = [(0, cfg)] + [(index, cfg.with_weight_codes(codes)) for index, codes in lut_changes]
    out = np.zeros((n_frames, height, width, len(FIELDS)), dtype=np.int64)
    energy = direction = None
    for t in range(n_frames):
        if t % k == 0:
            energy, direction = segment_start(frames[t], cfg)
        else:
            first_pixel = t * height * width
            index = first_pixel + np.arange(height * width).reshape(height, width)
            new_e = np.zeros((height, width), dtype=np.int64)
            new_d = np.zeros((height, width), dtype=np.int64)
            for n, (start, table) in enumerate(tables):
                stop = tables[n + 1][0] if n + 1 < len(tables) else None
                mask = index >= start if stop is None else (index >= start) & (index < stop)
                if mask.any():
                    e, d = dp_step(energy, direction, frames[t], table)
                    new_e[mask] = e[mask]
                    new_d[mask] = d[mask]
            energy, direction = new_e, new_d
        out[t, ..., 0] = energy
        out[t, ..., 1] = direction
        out[t, :, -1, 2] = 1
        out[t, -1, -1, 3] = 1
        out[t, -1, -1, 4] = int(t % k == k - 1)
    return out


def assert_states_equal(outputs: list, expected: np.ndarray) -> None:
    """Compare the unpacked outputs with ``expected`` (``(T, H, W, 5)``) bit for bit."""
    n_frames, height, width, _ = expected.shape
    flat = expected.reshape(-1, len(FIELDS))
    assert len(outputs) == len(flat), f"{len(outputs)} states out, expected {len(flat)}"
    for n, (got, want) in enumerate(zip(outputs, flat)):
        for f, name in enumerate(FIELDS):
            if got[name] != want[f]:
                t, rest = divmod(n, height * width)
                y, x = divmod(rest, width)
                raise AssertionError(
                    f"first mismatch at frame {t}, row {y}, col {x}, field {name}: "
                    f"got {got[name]}, expected {int(want[f])} "
                    f"(got {got}, expected {dict(zip(FIELDS, map(int, want)))})")


@contextlib.contextmanager
def refused(exception, match):
    """``pytest.raises`` for a component constructor that refuses its arguments.

    The half-built components on the traceback are never elaborated; mark them so that
    Amaranth does not warn ``UnusedElaboratable`` when they are collected later.
    """
    with pytest.raises(exception, match=match) as info:
        yield info
    traceback = info.tb
    while traceback is not None:
        obj = traceback.tb_frame.f_locals.get("self")
        if isinstance(obj, Elaboratable):
            obj._MustUse__silence = True  # private Amaranth flag: "not using it is fine"
        traceback = traceback.tb_next


def assert_verilator_lints_clean(path, module: str) -> None:
    """``verilator`` with the project's lint flags (``VERILATOR_LINT_FLAGS``, each waiver
    justified there) on ``path``, top module ``module``: no warning, no error."""
    run = subprocess.run(["verilator", *VERILATOR_LINT_FLAGS, "--top-module", module, str(path)],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr


def event_counter(events, counts: dict):
    """A background testbench adding up the one-cycle pulses of an ``events`` port
    (:func:`dptbd.hw.layouts.event_layout`) into ``counts`` (field -> pulses)."""
    names = [name for name, _ in events.shape()]
    counts.update({name: 0 for name in names})

    async def bench(ctx):
        async for _, _, value in ctx.tick().sample(events):
            for name in names:
                counts[name] += int(getattr(value, name))
    return bench
