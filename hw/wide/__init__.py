"""The DP pipeline at P = 2 or 4 pixels per clock (``DPConfig.pixels_per_clock``).

``docs/gateware.md``, "P pixels per clock", describes the design: a *beat* of P pixels of
one row per clock; the frame controller, the read-ahead and the line buffer of P = 1 built
for the beat configuration (:meth:`~dptbd.config.DPConfig.beat_config`, W / P columns);
a window of r + 2 beats (:class:`~dptbd.hw.wide.window.WideWindow`); and the per-pixel
datapath (weight LUT, weighted candidates, max tree, accumulator) built once per lane.
Every state is the one the golden model computes, as at P = 1. At P = 1 use
:class:`~dptbd.hw.dp_core.DPCore` and :class:`~dptbd.hw.dp_pipeline.DPPipeline`
(:func:`~dptbd.hw.wide.pipeline.dp_pipeline` picks by P).

The per-pixel datapath is the one of :meth:`DPCore.elaborate
<dptbd.hw.dp_core.DPCore.elaborate>` for paper 001 (identity merit, no penalty, no
forgetting), written again per lane here: the P = 1 core stays as it is (its netlist is the
one under mutation testing). Paper 000's family (``docs/arithmetic.md`` §8) is refused at
P > 1.

Modules: :mod:`.layouts` (the beats), :mod:`.state_store`, :mod:`.window`, :mod:`.core`
(``DPCoreWide``, ``check_wide``), :mod:`.pipeline` (``DPPipelineWide``, ``dp_pipeline``),
:mod:`!segmenter` (``SegmenterWide``, ``segmenter``);
their names are re-exported here.
"""

from __future__ import annotations

from dptbd.hw.wide.core import DPCoreWide, check_wide
from dptbd.hw.wide.layouts import (beat_word_layout, pack_beat, unpack_beat_states,
                                   wide_pixel_layout, wide_state_layout)
from dptbd.hw.wide.pipeline import DPPipelineWide, dp_pipeline
from dptbd.hw.wide.segmenter import SegmenterWide, segmenter
from dptbd.hw.wide.state_store import WideStateStore, WideStateStoreSignature
from dptbd.hw.wide.window import WideWindow, lane_column

__all__ = ["wide_pixel_layout", "wide_state_layout", "beat_word_layout", "pack_beat",
           "unpack_beat_states", "check_wide", "WideStateStoreSignature", "WideStateStore",
           "lane_column", "WideWindow", "DPCoreWide", "DPPipelineWide", "dp_pipeline",
           "SegmenterWide", "segmenter"]
