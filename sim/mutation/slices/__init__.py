"""The verification slice of each design's mutants: the configuration, the runs
(``(kind, seed)``, in order) and the runner ``run(sim, kind, seed) -> (verdict, report)``
of ``segmenter`` (:mod:`~dptbd.sim.mutation.slices.segmenter`, ``dptbd_seg``), ``axi``
(:mod:`~dptbd.sim.mutation.slices.axi`, ``dptbd_axi``), ``dp``
(:mod:`~dptbd.sim.mutation.slices.dp`, ``dptbd_dp``), ``dp2`` and ``dp4``
(:mod:`~dptbd.sim.mutation.slices.wide`, ``dptbd_dp`` at P = 2 and 4 pixels per clock)."""

from __future__ import annotations

__all__ = ["CONFIGS", "BACKPRESSURE", "SLICE_RUNS", "RUNNERS"]

#: The configuration of each design's mutants: 12 x 10 frames, B_in = 6, B_E = 8 (the
#: fewest bits that never saturate at K_max = 4), F = 4, n = 60 of C = 120 (lists long
#: enough to carry most pixels), 16 bins of width 16 (s = 4).
CONFIGS = {
    "segmenter": dict(width=12, height=10, segment_frames=2, max_segment_frames=4,
                      input_bits=6, energy_bits=8, weight_frac_bits=4, candidate_count=60,
                      candidate_capacity=120, histogram_bits=4, histogram_shift=4),
    "axi": dict(width=12, height=10, segment_frames=2, max_segment_frames=4,
                input_bits=6, energy_bits=8, weight_frac_bits=4, candidate_count=60,
                candidate_capacity=120, histogram_bits=4, histogram_shift=4),
    # dp: B_E = 7, one bit short of never saturating, and K = 3: full-scale pixels saturate
    # at K >= 3 (every bit of E and the clamp are reached); run-time K up to 4
    "dp": dict(width=12, height=10, segment_frames=3, max_segment_frames=4, input_bits=6,
               energy_bits=7, weight_frac_bits=4),
    # dp2: dp's at P = 2 pixels per clock (dptbd_dp of DPCoreWide, 6 beats a line)
    "dp2": dict(width=12, height=10, segment_frames=3, max_segment_frames=4, input_bits=6,
                energy_bits=7, weight_frac_bits=4, pixels_per_clock=2),
    # dp4: dp's at P = 4 (3 beats a line: a first, an inner and a last beat; 10 lines)
    "dp4": dict(width=12, height=10, segment_frames=3, max_segment_frames=4, input_bits=6,
                energy_bits=7, weight_frac_bits=4, pixels_per_clock=4),
}

#: Output back-pressure densities of the ``backpressure`` runs (seed % 4): the lists
#: pile up behind the output, every FIFO and credit counter fills.
BACKPRESSURE = (0.9, 0.95, 0.97, 0.99)

# the designs' modules use the constants above
from dptbd.sim.mutation.slices import axi, dp, segmenter, wide  # noqa: E402

#: Runs of each design's slice: ``(kind, seed)``, run in this order.
SLICE_RUNS = {
    "segmenter": segmenter.RUNS,
    "axi": axi.RUNS,
    "dp": dp.RUNS,
    "dp2": wide.RUNS,
    "dp4": wide.RUNS,
}

#: Each design's runner.
RUNNERS = {"segmenter": segmenter.run, "axi": axi.run, "dp": dp.run, "dp2": wide.run,
           "dp4": wide.run}
