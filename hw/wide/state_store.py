"""The P-pixel pipeline's state store: W·H/P words of P states, one per beat."""

from __future__ import annotations

from amaranth.hdl import Module
from amaranth.lib import wiring
from amaranth.lib.memory import Memory
from amaranth.lib.wiring import In, Out

from dptbd.config import DPConfig
from dptbd.hw.wide.layouts import beat_word_layout


class WideStateStoreSignature(wiring.Signature):
    """:class:`~dptbd.hw.state_store.StateStoreSignature` with one word per beat: addresses
    are beat positions ``row * W/P + beat`` in ``[0, W*H/P)``, data
    :func:`beat_word_layout`; the same timing."""

    def __init__(self, cfg: DPConfig):
        self._cfg = cfg
        words = cfg.frame_beats
        layout = beat_word_layout(cfg)
        super().__init__({
            "read_addr": Out(range(words)),
            "read_en": Out(1),
            "read_data": In(layout),
            "write_addr": Out(range(words)),
            "write_data": Out(layout),
            "write_en": Out(1),
        })

    def __eq__(self, other):
        return type(other) is type(self) and other._cfg == self._cfg

    def __repr__(self):
        return (f"WideStateStoreSignature({self._cfg.width}x{self._cfg.height}, "
                f"P={self._cfg.pixels_per_clock})")


class WideStateStore(wiring.Component):
    """On-chip state store of W*H/P words of P states (one synchronous non-transparent read
    port, one write port; contents start at 0), as :class:`~dptbd.hw.state_store.StateStore`.

    Members
    -------
    bus : In(WideStateStoreSignature(cfg))
    """

    def __init__(self, cfg: DPConfig):
        self._cfg = cfg
        super().__init__({"bus": In(WideStateStoreSignature(cfg))})

    def elaborate(self, platform):
        m = Module()
        cfg = self._cfg
        m.submodules.memory = memory = Memory(
            shape=beat_word_layout(cfg), depth=cfg.frame_beats, init=[])
        read = memory.read_port(domain="sync")
        write = memory.write_port(domain="sync")
        m.d.comb += [
            read.addr.eq(self.bus.read_addr),
            read.en.eq(self.bus.read_en),
            self.bus.read_data.eq(read.data),
            write.addr.eq(self.bus.write_addr),
            write.data.eq(self.bus.write_data),
            write.en.eq(self.bus.write_en),
        ]
        return m
