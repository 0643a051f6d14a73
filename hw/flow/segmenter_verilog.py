"""Verilog generation of the segmenter top: :class:`~dptbd.hw.dp_segmenter_top.DPSegmenter` as
the Verilog module ``dptbd_seg`` with a JSON manifest, like :mod:`dptbd.hw.flow.verilog` does
for ``dptbd_dp``; the cocotb harness (:mod:`dptbd.sim.benches.segmenter`) and the Verilator harness
(:mod:`dptbd.sim.verilator.cache`) read the manifest.
"""

from __future__ import annotations

import dataclasses
import json
import pathlib
from typing import Mapping

from amaranth.lib import data

from dptbd.config import DPConfig
from dptbd.errors import ConfigError
from dptbd.hw.candidate_layout import bits_per_segment, candidate_field_offsets, candidate_layout
from dptbd.hw.dp_segmenter_top import DPSegmenter
from dptbd.hw.flow.to_verilog import to_verilog
from dptbd.hw.flow.verilog import manifest_header, manifest_interface, port_list
from dptbd.hw.layouts import field_offsets

__all__ = ["SEGMENTER_MODULE_NAME", "segmenter_manifest", "generate_segmenter_verilog"]

#: Name of the generated Verilog module.
SEGMENTER_MODULE_NAME = "dptbd_seg"


def segmenter_manifest(cfg: DPConfig, top: DPSegmenter) -> dict:
    """Machine-readable description of ``dptbd_seg`` (JSON-serialisable); at P > 1
    (:class:`~dptbd.hw.wide.dp_segmenter.DPSegmenterWide`) its ``pixel`` layout is the
    beat's."""
    if cfg.pixels_per_clock > 1:
        from dptbd.hw.wide.layouts import wide_pixel_layout as pixel_layout
    else:
        from dptbd.hw.layouts import pixel_layout
    bits = bits_per_segment(cfg)
    return {
        **manifest_header(cfg, SEGMENTER_MODULE_NAME, top),
        "core_options": top.core_options,
        "derived": {
            "n_moves": cfg.n_moves,
            "direction_bits": cfg.direction_bits,
            "e_max": cfg.e_max,
            "n_candidates": cfg.n_candidates,
            "k_max": cfg.k_max,
            "record_capacity": cfg.record_capacity,
            "n_bins": cfg.n_bins,
            "bin_shift": cfg.bin_shift,
            "bin_count_bits": cfg.bin_count_bits,
            "threshold_bits": cfg.threshold_bits,
        },
        **manifest_interface(cfg),
        "latency": top.latency,
        "dp_latency": top.schedule.latency,
        "scan_cycles": top.scan_cycles,
        "ports": port_list(top),
        "layouts": {
            "pixel": field_offsets(pixel_layout(cfg)),
            "candidate": candidate_field_offsets(cfg),
            "candidate_width": data.Layout.cast(candidate_layout(cfg)).size,
        },
        "bits_per_segment": dataclasses.asdict(bits),
    }


def generate_segmenter_verilog(cfg: DPConfig, *, core_options: Mapping[str, str] | None = None,
                               manifest_path: str | pathlib.Path | None = None
                               ) -> tuple[str, dict]:
    """Convert :class:`DPSegmenter` for ``cfg`` to Verilog module ``dptbd_seg``
    (:class:`~dptbd.hw.wide.dp_segmenter.DPSegmenterWide` at ``pixels_per_clock`` 2 or 4).

    ``core_options``: the DP core's implementation options (``None``: DPCore's defaults;
    :meth:`~dptbd.hw.flow.family.Family.options_for` for a family's build), recorded in the
    manifest under ``core_options``.

    Returns
    -------
    tuple of (str, dict)
        The Verilog text and its manifest (also written to ``manifest_path`` if given).

    Raises
    ------
    ConfigError
        For n = 0 (``DPConfig.n_candidates``): a segmenter that never emits a point, whose
        Verilog would carry zero-width signals (``wire [-1:0]``). The default n, 0.2 % of
        W*H, is 0 below 250 pixels; set ``candidate_count``. (The Amaranth component itself
        accepts n = 0, which the tests use to exercise trailer-only lists.)
    """
    if cfg.n_candidates == 0:
        raise ConfigError(
            f"candidate_count: n = 0 candidate points per segment (0.2 % of {cfg.width}x"
            f"{cfg.height} = {cfg.width * cfg.height} pixels rounds to 0) gives a segmenter "
            f"that emits no points; set candidate_count to 1 … {cfg.width * cfg.height}")
    from dptbd.hw.wide.dp_segmenter import dp_segmenter
    top = dp_segmenter(cfg, core_options=core_options)
    text = to_verilog(top, SEGMENTER_MODULE_NAME)
    info = segmenter_manifest(cfg, top)
    if manifest_path is not None:
        pathlib.Path(manifest_path).write_text(json.dumps(info, indent=2) + "\n")
    return text, info
