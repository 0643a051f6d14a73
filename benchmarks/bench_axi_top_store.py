"""Cycles per pixel of the drop-in core ``dptbd_axi`` with its state in external memory
(``dptbd verilog --top axi --state-store axi``) against the memory's latency, on Verilator.

    python benchmarks/bench_axi_top_store.py                  # 640 x 512, 30 frames
    python benchmarks/bench_axi_top_store.py --latency 0 100 500 --outstanding 4 16
    python benchmarks/bench_axi_top_store.py --width 4096 --height 256 --frames 8 \
        --scene range_doppler
    python benchmarks/bench_axi_top_store.py --synth ecp5      # does it fit? (Yosys, nextpnr)
    python benchmarks/bench_axi_top_store.py --synth ecp5 --pixels-per-clock 4 --seeds 1 2 3
    python benchmarks/bench_axi_top_store.py --pixels-per-clock 2 --frames 4

The build is ``dptbd.sim.verilator.build(cfg, "axi", state_store=...)``, the AXI harness
with the C++ AXI4 memory model (``sim/harness/axi4_memory.h``): every burst answered after
a fixed latency (cycles from the address handshake to the first read beat, and from the
last write beat to the response), every channel always ready; the input offers a beat in
every cycle and ``m_axis_cand`` always takes. The frames are uniform random pixels
(``--scene uniform``, the default) or (``--scene range_doppler``) the range–Doppler scene of
``benchmarks/bench_axi_store.py`` (:func:`dptbd.scenes.range_doppler.rd_scene`, ``width``
range cells along each line, ``height`` Doppler lines, a Swerling 1 target at 10 dB).
``--pixels-per-clock P`` (2 or 4) builds the core for beats of P pixels (1.0 / P = one beat
per clock). Reported: cycles from the first to the last accepted pixel over the pixels
(1.0 = one pixel per clock), that over the same build's figure at the first latency (the slowdown the
memory's latency causes), and whether every list word, flag and counter is the golden model's with
no AXI4 rule broken (:func:`dptbd.sim.verilator.axi.check_axi`), with the lists and records
scored. This script only reports.

``--synth FAMILY`` instead synthesises and places-and-routes the core (the family's DPCore
options, as ``dptbd verilog --family``) on the family's default device, one placement per
``--seeds`` seed (default 1; :func:`dptbd.hw.flow.synth.synthesize`, ``--jobs`` at a time,
each stopped after ``--pnr-timeout`` seconds); its ports, more than the package has pins,
folded onto two (:class:`~dptbd.hw.flow.registered_ports.FoldedPorts`, as the ``axi-ext``
synthesis case: about one flip-flop per port bit more), and reports the cells, whether it
fits, the utilisation, Fmax and the critical path per seed, and the median Fmax.
"""

from __future__ import annotations

import argparse
import pathlib
import sys

from dptbd.config import DPConfig
from dptbd.sim import verilator as V
from dptbd.sim.axi.stimulus import clean_beats
from dptbd.sim.verilator import axi as verilator_axi
from dptbd.sim.verilator.axi import check_axi, fault_pulse_array


def _model_once() -> None:
    """The golden model's outputs of a scene once for all runs: they do not depend on the
    memory's latency or the store's layout (minutes of Python per run at 30 frames of
    640 x 512 otherwise)."""
    model, memo = verilator_axi.expected_outputs, {}

    def expected_outputs(cfg, beats, steps, **options):
        key = (cfg, id(beats), repr(steps), repr(sorted(options.items())))
        if key not in memo:
            memo[key] = model(cfg, beats, steps, **options)
        return memo[key]

    verilator_axi.expected_outputs = expected_outputs


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--width", type=int, default=640)
    parser.add_argument("--height", type=int, default=512)
    parser.add_argument("--frames", type=int, default=30)
    parser.add_argument("--scene", choices=("uniform", "range_doppler"), default="uniform")
    parser.add_argument("--latency", type=int, nargs="+", default=[0, 100, 500])
    parser.add_argument("--outstanding", type=int, nargs="+", default=[4, 16])
    parser.add_argument("--data-bits", type=int, default=64)
    parser.add_argument("--burst-beats", type=int, default=16)
    parser.add_argument("--pixels-per-clock", type=int, default=1)
    parser.add_argument("--synth", choices=("ice40", "ecp5"), default=None)
    parser.add_argument("--seeds", type=int, nargs="+", default=[1],
                        help="placement seeds of --synth (default: 1)")
    parser.add_argument("--jobs", type=int, default=1, help="nextpnr runs of --synth at a time")
    parser.add_argument("--pnr-timeout", type=float, default=1800,
                        help="seconds after which a --synth seed's nextpnr is stopped")
    args = parser.parse_args()
    cfg = DPConfig(width=args.width, height=args.height,
                   pixels_per_clock=args.pixels_per_clock).build_config()
    if args.synth:
        return synth(cfg, cfg.axi_store(data_bits=args.data_bits, burst_beats=args.burst_beats,
                                        outstanding=args.outstanding[0]), args.synth,
                     seeds=args.seeds, jobs=args.jobs, timeout=args.pnr_timeout)
    sys.path.insert(0, str(pathlib.Path(__file__).parent))
    from bench_axi_store import scene_frames

    frames = scene_frames(cfg, args.frames, args.scene)
    beats = clean_beats(frames)
    pulses = fault_pulse_array(cfg, beats, [{"stop": len(beats)}])
    _model_once()
    print(f"dptbd_axi --state-store axi, {cfg.describe()}, {args.frames} frames "
          f"({args.scene}, {frames.size} pixels), AXI {args.data_bits}-bit, bursts of "
          f"{args.burst_beats} beats, Verilator")
    print("| latency (cycles) | outstanding | cycles per pixel | slowdown | bit-exact | "
          "lists (records) |")
    print("|---|---|---|---|---|---|")
    for outstanding in args.outstanding:
        store = cfg.axi_store(data_bits=args.data_bits, burst_beats=args.burst_beats,
                              outstanding=outstanding)
        sim = V.build(cfg, "axi", state_store=store)
        first = None
        for latency in args.latency:
            result = check_axi(sim, beats, [{"stop": len(beats)}], pulses=pulses,
                               memory=dict(latency=(latency, latency)))
            accepted = result.run.accept_cycles
            cpp = float(accepted[-1] - accepted[0] + 1) / len(accepted)
            first = cpp if first is None else first
            board = result.board
            print(f"| {latency} | {outstanding} | {cpp:.3f} | {cpp / first:.3f} | "
                  f"{result.passed} | "
                  f"{len(board.lists)} ({board.records_expected}) |", flush=True)


def synth(cfg: DPConfig, store, family: str, *, seeds=(1,), jobs: int = 1,
          timeout: float = 1800) -> None:
    """Synthesis and place-and-route of the core with its ports folded (see the module doc)."""
    from dptbd.hw.axi_store.top import AXITopStore
    from dptbd.hw.flow.family import get_family
    from dptbd.hw.flow.registered_ports import FoldedPorts
    from dptbd.hw.flow.synth import synthesize
    from dptbd.hw.flow.to_verilog import to_verilog

    options = get_family(family).options_for(cfg)
    text = to_verilog(FoldedPorts(AXITopStore(store, core_options=options)), "dptbd_dp")
    # the axi-store variant's flow, its text this core's (the store's options as asked)
    res = synthesize(cfg, variant="axi-store", family=family, seeds=tuple(seeds), jobs=jobs,
                     nextpnr_timeout=timeout, verilog_filter=lambda _text: text)
    print(f"dptbd_axi --state-store axi, {cfg.describe()}, AXI {store.data_bits}-bit, bursts "
          f"of {store.burst_beats}, {store.outstanding} outstanding, {family} {res.device} "
          f"{res.package}, ports folded")
    print(f"cells: {res.cells}")
    for run in res.runs:
        used = ", ".join(f"{bel} {u}/{a}" for bel, (u, a) in sorted(run.utilisation.items()))
        print(f"seed {run.seed}: fits {run.fits}, Fmax {run.fmax_mhz} MHz; {used}"
              + (f"; {run.error}" if run.error else ""))
        path = run.critical_path
        if path is not None:
            print(f"  critical path: {path.start} -> {path.end}: {path.total_ns:.2f} ns "
                  f"({path.logic_ns:.2f} logic, {path.routing_ns:.2f} routing)")
    median = res.fmax_median_mhz
    print("Fmax median: " + ("— (not every seed routed)" if median is None
                             else f"{median:.1f} MHz"))


if __name__ == "__main__":
    main()
