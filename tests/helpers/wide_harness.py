"""Amaranth-simulator harness for the P-pixel pipeline (``dptbd.hw.wide``): beats in,
beats out, scored per pixel with :mod:`helpers.hw_harness`'s ``reference_states`` and
``assert_states_equal``."""

from __future__ import annotations

import random
import warnings

import numpy as np

from dptbd.config import DPConfig, EnergyWidthWarning
from dptbd.hw.wide import pack_beat, unpack_beat_states
from helpers.hw_harness import StreamRun, simulate, stream_cycle


def make_config(**kw) -> DPConfig:
    """``DPConfig(**kw)``, a narrow energy width allowed."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        return DPConfig(**kw)


def random_frames(cfg: DPConfig, n_frames: int, seed: int) -> np.ndarray:
    """``n_frames`` frames of uniform random pixels."""
    rng = np.random.default_rng(seed)
    return rng.integers(0, cfg.pixel_max + 1, size=(n_frames, cfg.height, cfg.width))


def frames_to_beats(cfg: DPConfig, frames: np.ndarray) -> list[tuple[tuple[int, ...], bool]]:
    """(P pixels, first) per beat in raster order, ``first`` on every frame's first beat."""
    p = cfg.pixels_per_clock
    out = []
    for frame in frames:
        flat = [int(v) for v in np.asarray(frame).ravel()]
        out += [(tuple(flat[i:i + p]), i == 0) for i in range(0, len(flat), p)]
    return out


def run_beats(dut, cfg: DPConfig, beats, *, valid_probability=1.0, ready_probability=1.0,
              seed=0, lut_writes=None, max_cycles=None, on_cycle=None, processes=()) -> StreamRun:
    """Simulate ``dut`` until every beat of ``beats`` has come out; ``outputs`` are the
    states per pixel (:func:`~dptbd.hw.wide.unpack_beat_states`), ``accept_cycles`` and
    ``output_cycles`` per beat. ``lut_writes`` as :func:`helpers.hw_harness.run_stream`'s
    (index: the beat before which they are written, the input idle meanwhile); ``processes``
    run beside (e.g. a state-store model, an event counter)."""
    rng = random.Random(seed)
    pending = {k: list(v) for k, v in (lut_writes or {}).items()}
    if max_cycles is None:
        slow = max(valid_probability, 0.05) * max(ready_probability, 0.05)
        max_cycles = int((len(beats) + 100) / slow * 3) + 200
    result = StreamRun([], [], [], 0)
    payload_in = dut.pixels.payload.as_value()

    async def bench(ctx):
        accepted = 0
        offering = False
        while len(result.outputs) < len(beats):
            if result.cycles >= max_cycles:
                raise AssertionError(f"timeout after {result.cycles} cycles: {accepted}/"
                                     f"{len(beats)} beats accepted, {len(result.outputs)} out")
            writes = pending.get(accepted)
            write = writes.pop(0) if writes and not offering else None
            ctx.set(dut.lut_we, write is not None)
            if write is not None:
                ctx.set(dut.lut_addr, write[0])
                ctx.set(dut.lut_data, write[1])
            elif not offering and accepted < len(beats):
                offering = rng.random() < valid_probability
                if offering:
                    ctx.set(payload_in, pack_beat(cfg, *beats[accepted]))
            taking = rng.random() < ready_probability
            if on_cycle is not None:
                on_cycle(ctx, accepted)
            if await stream_cycle(ctx, dut.pixels, dut.states, offering, taking, result):
                accepted += 1
                offering = False
        words = list(result.outputs)
        result.outputs[:] = [state for word in words for state in unpack_beat_states(cfg, word)]

    simulate(dut, bench, background=processes)
    return result
