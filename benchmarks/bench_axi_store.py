"""Cycles per pixel of the DP pipeline with its state in external memory (``DPPipelineAxi``)
against the memory's latency, in Amaranth simulation.

    python benchmarks/bench_axi_store.py                      # 64 x 32, 3 frames
    python benchmarks/bench_axi_store.py --latency 0 100 500 --outstanding 4 8 16
    python benchmarks/bench_axi_store.py --simulator verilator --width 640 --height 512 --frames 30

    python benchmarks/bench_axi_store.py --simulator verilator --width 4096 --height 256 \
        --frames 4 --scene range_doppler --outstanding 4 16
    python benchmarks/bench_axi_store.py --simulator verilator --width 640 --height 512 \
        --frames 4 --pixels-per-clock 2 4 --outstanding 4 16

``--pixels-per-clock`` builds the P-pixel core (``DPCoreWide``, store words of P states in the
same byte layout); cycles per pixel are then cycles per accepted beat over P (1/P = one
beat of P pixels per clock).

``--simulator verilator`` runs the Verilog on Verilator with the harness's C++ AXI4 memory
model (:mod:`dptbd.sim.verilator.dp_axi`; data widths 32 and 64), the same conditions.
The frames are uniform random pixels (``--scene uniform``, the default), or
(``--scene range_doppler``) a range–Doppler scene of :func:`dptbd.scenes.range_doppler.rd_scene`:
Rayleigh noise with a Swerling 1 target at 10 dB on a straight track, ``width`` range cells
along each line and ``height`` Doppler cells, quantised at 16 LSB per unit of the noise's
Rayleigh parameter (the throughput does not depend on the scene; the bits are checked on it).

The memory (:class:`dptbd.sim.axi4_memory.Axi4Memory`) answers every burst after a fixed
latency (cycles from the address handshake to the first read beat, and from the last write
beat to the response), all channels always ready; the input offers a pixel in every cycle
and the output always takes. Reported: cycles from the first to the last accepted pixel
over the pixels (1.0 = one pixel per clock), and the estimate ``(latency + burst_beats + 3)
/ (outstanding * burst_states)`` cycles per pixel (at least 1) of the prefetch depth (a
burst is in flight for its latency plus its beats plus a few register cycles; the beat
FIFO's credit returns only when a beat is consumed, so a slow run is somewhat slower). Every run is checked
bit-exact against the golden model. This script only reports.
"""

from __future__ import annotations

import argparse

import numpy as np

from dptbd.config import DPConfig
from dptbd.hw.axi_store.pipeline import DPPipelineAxi
from dptbd.hw.layouts import pack_pixel
from dptbd.sim.axi4_memory import Axi4Memory
from dptbd.sim.scoreboard import expected_words


def measure(cfg: DPConfig, frames: np.ndarray, latency: int, **store_fields) -> tuple[float, bool]:
    """(cycles per accepted pixel, bit-exact) of one run."""
    from amaranth.sim import Simulator

    store = cfg.axi_store(**store_fields)
    dut = DPPipelineAxi(store)
    memory = Axi4Memory(dut, store, latency=(latency, latency))
    p = cfg.pixels_per_clock
    flat = np.asarray(frames).reshape(len(frames), -1)
    stream = [(tuple(int(v) for v in frame[i:i + p]), i == 0) for frame in flat
              for i in range(0, frame.size, p)]
    if p == 1:
        pack = lambda pixels, first: pack_pixel(cfg, pixels[0], first)  # noqa: E731
    else:
        from dptbd.hw.wide import pack_beat as pack_wide
        pack = lambda pixels, first: pack_wide(cfg, pixels, first)  # noqa: E731
    accepted, outputs = [], []

    async def bench(ctx):
        ctx.set(dut.states.ready, 1)
        cycle = 0
        while len(outputs) < len(stream):
            if len(accepted) < len(stream):
                pixel, first = stream[len(accepted)]
                ctx.set(dut.pixels.payload.as_value(), pack(pixel, first))
                ctx.set(dut.pixels.valid, 1)
            else:
                ctx.set(dut.pixels.valid, 0)
            took = len(accepted) < len(stream) and ctx.get(dut.pixels.ready)
            if ctx.get(dut.states.valid):
                outputs.append(ctx.get(dut.states.payload.as_value()))
            await ctx.tick()
            if took:
                accepted.append(cycle)
            cycle += 1

    sim = Simulator(dut)
    sim.add_clock(1e-8)
    sim.add_testbench(bench)
    sim.add_testbench(memory.process(), background=True)
    sim.run()
    if p > 1:
        from dptbd.sim.rtl.check import beat_state_words
        outputs = [int(w) for w in beat_state_words(cfg, np.array(outputs, dtype=np.uint64))]
    exact = outputs == [int(w) for w in expected_words(cfg, frames).reshape(-1)]
    return (accepted[-1] - accepted[0] + 1) / (len(stream) * p), exact


def scene_frames(cfg: DPConfig, frames: int, scene: str) -> np.ndarray:
    """``(frames, H, W)`` integer pixels of ``scene`` (``"uniform"`` or
    ``"range_doppler"``, see the module doc)."""
    if scene == "uniform":
        return np.random.default_rng(1).integers(0, 256, size=(frames, cfg.height, cfg.width))
    from dptbd.scenes.adc import quantise
    from dptbd.scenes.range_doppler import rd_scene, straight_track

    track = straight_track((cfg.width / 3, cfg.height / 2), (2.0, 0.5), frames)
    rd = rd_scene((cfg.width, cfg.height), frames, track, snr_db=10.0, seed=1)
    return quantise(np.swapaxes(rd.frames, 1, 2), cfg.input_bits, gain=16.0)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--width", type=int, default=64)
    parser.add_argument("--height", type=int, default=32)
    parser.add_argument("--frames", type=int, default=3)
    parser.add_argument("--latency", type=int, nargs="+", default=[0, 100, 500])
    parser.add_argument("--outstanding", type=int, nargs="+", default=[4, 16])
    parser.add_argument("--data-bits", type=int, default=64)
    parser.add_argument("--burst-beats", type=int, default=16)
    parser.add_argument("--simulator", choices=("amaranth", "verilator"), default="amaranth")
    parser.add_argument("--scene", choices=("uniform", "range_doppler"), default="uniform")
    parser.add_argument("--pixels-per-clock", type=int, nargs="+", default=[1],
                        help="P: pixels per clock (1, 2, 4), one table row set per P")
    args = parser.parse_args()
    first = True
    for p in args.pixels_per_clock:
        cfg = DPConfig(width=args.width, height=args.height,
                       pixels_per_clock=p).build_config()
        frames = scene_frames(cfg, args.frames, args.scene)
        if first:
            print(f"{cfg.describe()}, {args.frames} frames ({args.scene}), AXI "
                  f"{args.data_bits}-bit, bursts of {args.burst_beats} beats, {args.simulator}")
            print("| P | latency (cycles) | outstanding | cycles per pixel | 1/P + 1 % | "
                  "estimate | bit-exact |")
            print("|---|---|---|---|---|---|---|")
            first = False
        table(args, cfg, frames)


def table(args, cfg: DPConfig, frames: np.ndarray) -> None:
    """The rows of one P: every outstanding limit and latency."""
    p = cfg.pixels_per_clock
    for outstanding in args.outstanding:
        store = cfg.axi_store(data_bits=args.data_bits, burst_beats=args.burst_beats,
                              outstanding=outstanding)
        for latency in args.latency:
            if args.simulator == "verilator":
                from dptbd.sim.verilator import dp_axi as verilator_dp_axi
                run = verilator_dp_axi.run(verilator_dp_axi.build(store), frames,
                                           latency=(latency, latency))
                cpp, exact = run.cycles_per_pixel, run.bit_exact and not run.result["violations"]
            else:
                cpp, exact = measure(cfg, frames, latency, data_bits=args.data_bits,
                                     burst_beats=args.burst_beats, outstanding=outstanding)
            estimate = max(1.0 / p, (latency + args.burst_beats + 3)
                           / (outstanding * store.burst_states))
            print(f"| {p} | {latency} | {outstanding} | {cpp:.3f} | {1 / p * 1.01:.3f} | "
                  f"{estimate:.3f} | {exact} |")


if __name__ == "__main__":
    main()
