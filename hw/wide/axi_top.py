"""``dptbd_axi`` at P = 2 or 4 pixels per clock, on-chip state store: :class:`AXITopWide`
(``docs/integration.md``, ``docs/gateware.md`` "P pixels per clock").

The ports are :class:`~dptbd.hw.axi_top.AXITop`'s except ``s_axis_video``, which carries P
pixels per beat (:func:`~dptbd.hw.wide.axis_video.video_in_signature_wide`: pixel 0 in the
low lane, ``tuser[0]`` on a frame's first beat, ``tlast`` on a row's last beat). Inside, the
same blocks as at P = 1 around :class:`~dptbd.hw.wide.dp_segmenter.DPSegmenterWide`: the
register file, the candidate output adapter with its soft reset, and the frame monitor
built for the beat configuration (W/P beats per line), so its fault classes count beats.
``m_axis_state`` (``state_output``) and the external state store are not built at P > 1;
the AXI4 state store is (:class:`~dptbd.hw.axi_store.top.AXITopStore`, on these blocks).
"""

from __future__ import annotations

from typing import Mapping

from amaranth.lib import wiring
from amaranth.lib.wiring import Out

from dptbd.config import DPConfig
from dptbd.hw.axi_lite import axi_lite_signature
from dptbd.hw.axi_top import AXITop, _flat
from dptbd.hw.axis_video import candidate_out_signature
from dptbd.hw.register_map import ADDRESS_BITS, register_map
from dptbd.hw.wide.axis_video import video_in_signature_wide
from dptbd.hw.wide.dp_segmenter import DPSegmenterWide

__all__ = ["AXITopWide", "axi_top", "wide_bundle_signatures"]


def wide_bundle_signatures(cfg: DPConfig) -> dict[str, wiring.Signature]:
    """The AXI bundles of ``dptbd_axi`` at P > 1 (flattened with their prefixes): the
    video input of P pixels per beat, the candidate lists, the register port."""
    return {
        "s_axis_video": video_in_signature_wide(cfg).flip(),
        "m_axis_cand": candidate_out_signature(cfg),
        "s_axil": axi_lite_signature(ADDRESS_BITS).flip(),
    }


class AXITopWide(AXITop):
    """``dptbd_axi`` at P = 2 or 4 (module doc). Members, properties, ``core_options`` and
    the elaboration (the family's options of the register file, the output adapter, the
    frame monitor and the input's hold included) as :class:`~dptbd.hw.axi_top.AXITop`'s
    (no ``state_output``, no external store); ``s_axis_video_tdata`` is P byte lanes
    wide."""

    def __init__(self, cfg: DPConfig, *, core_options: Mapping[str, str] | None = None):
        if cfg.pixels_per_clock == 1:
            raise ValueError("AXITopWide takes pixels_per_clock 2 or 4; at 1 use "
                             "dptbd.hw.axi_top.AXITop (dptbd.hw.wide.axi_top.axi_top picks by P)")
        self._cfg = cfg
        self._state_output = False
        self._external = False
        self._core = DPSegmenterWide(cfg, core_options=core_options)
        self._bundles = wide_bundle_signatures(cfg)
        self._register_map = register_map(cfg)
        members = {"aclk": wiring.In(1), "aresetn": wiring.In(1)}
        for prefix, signature in self._bundles.items():
            members.update(_flat(prefix, signature))
        members["irq"] = Out(1)
        wiring.Component.__init__(self, members)


def axi_top(cfg: DPConfig, *, core_options: Mapping[str, str] | None = None, **options):
    """``dptbd_axi`` for ``cfg``: :class:`~dptbd.hw.axi_top.AXITop` at P = 1 (``options``
    passed on), :class:`AXITopWide` at P = 2 or 4 (``state_output`` and
    ``external_state_store`` refused there)."""
    if cfg.pixels_per_clock == 1:
        return AXITop(cfg, core_options=core_options, **options)
    given = sorted(name for name, value in options.items() if value)
    if given:
        raise ValueError(f"{', '.join(given)}: not built at pixels_per_clock="
                         f"{cfg.pixels_per_clock}; dptbd_axi at P > 1 has the on-chip state "
                         f"store and no m_axis_state")
    return AXITopWide(cfg, core_options=core_options)
