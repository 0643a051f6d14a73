"""The on-chip state store read a pixel ahead: a two-cycle block-RAM read behind the
one-cycle :class:`~dptbd.hw.state_store.StateStoreSignature`.

:class:`~dptbd.hw.dp_core.DPCore` reads the store in raster order: the read of a pixel that
continues the raster is at the previous read's address + 1 (mod W*H), which the controller
knows a pixel early (``next_read_addr``). This store reads that address into the block RAM
with the previous read, and moves it to an output register with the read itself, so the
word reaches ``read_data`` in the cycle after ``read_en`` as the signature requires, from a
register, and the block RAM's own read has a whole cycle (on ECP5 the DP16KD's output
register, ``REGMODE = "OUTREG"``, which Yosys does not infer; ``docs/synthesis.md``).

A read that does not continue the raster (the first pixel after a resynchronisation) gets
the word read ahead, not its own: that pixel begins a segment, whose first frame ignores the
previous state (``docs/gateware.md``, "Read-ahead"), so no output changes. The word of an
address is read one pixel earlier than DPCore reads it, so the frame needs one cycle more
than DPCore's constraint (:func:`check_read_ahead_store`).
"""

from __future__ import annotations

from amaranth.hdl import Module, Mux, Signal
from amaranth.lib import wiring
from amaranth.lib.memory import Memory
from amaranth.lib.wiring import In

from dptbd.config import DPConfig
from dptbd.errors import ConfigError
from dptbd.hw.dp16kd import DP16KD_MAX_DEPTH, dp16kd_memory
from dptbd.hw.layouts import state_word_layout
from dptbd.hw.state_store import StateStoreSignature

__all__ = ["STATE_STORE_STYLES", "ReadAheadStore", "check_read_ahead_store"]

#: ``ReadAheadStore(style=…)`` (and ``DPCore(state_store_style=…)``).
STATE_STORE_STYLES = ("memory", "dp16kd")


def check_read_ahead_store(cfg: DPConfig, write_latency: int) -> None:
    """Refuse a frame too small for the on-chip store's read-ahead.

    DPCore needs ``W*H - r*(W+1) > write_latency`` (:func:`~dptbd.hw.schedule.check_supported`);
    :class:`ReadAheadStore` reads every word one pixel earlier, so it needs
    ``W*H - r*(W+1) - 1 > write_latency``.

    Raises
    ------
    dptbd.errors.ConfigError
        Naming the frame, the margin it has and the one it needs.
    """
    margin = cfg.width * cfg.height - cfg.radius * (cfg.width + 1) - 1
    if margin <= write_latency:
        raise ConfigError(
            f"width={cfg.width} x height={cfg.height} is too small for the on-chip state "
            f"store's read-ahead at radius={cfg.radius}: it needs width*height - "
            f"radius*(width+1) - 1 > write latency {write_latency} cycles, but it is "
            f"{margin}; use a larger frame or the state store outside")


class ReadAheadStore(wiring.Component):
    """On-chip state store whose block RAM reads the next raster address a pixel ahead.

    Parameters
    ----------
    cfg : DPConfig
        Frame size and widths.
    style : {"memory", "dp16kd"}
        ``"memory"`` (default): an :class:`~amaranth.lib.memory.Memory` and a register after
        its read port (any FPGA, and simulation). ``"dp16kd"``: ECP5 ``DP16KD`` instances
        (:func:`~dptbd.hw.dp16kd.dp16kd_memory`, one set per 16384-word bank; 16384 x 1 each
        at 128 x 128) reading through their output register (``REGMODE_B = "OUTREG"``);
        with more than one bank the registered outputs are selected by a bank index
        registered with them. Same cycles; a synthesis choice for ECP5 only (no simulation
        model). Anything else raises ``ValueError``.
    dp16kd : callable or None
        ``dp16kd(**ports)`` builds one DP16KD (``cell`` of
        :func:`~dptbd.hw.dp16kd.dp16kd_memory`; ``None``: the ``Instance``). Tests pass a
        behavioural model to simulate the ``"dp16kd"`` style's wiring.

    Members
    -------
    bus : In(StateStoreSignature(cfg))
        The pipeline's side, as :class:`~dptbd.hw.state_store.StateStore`'s.
    next_read_addr : In(range(W*H))
        The address the next read will be if it continues the raster (the controller's
        ``next_read_addr``), sampled with ``read_en``.
    """

    def __init__(self, cfg: DPConfig, *, style: str = "memory", dp16kd=None):
        if style not in STATE_STORE_STYLES:
            raise ValueError(f"style must be one of {STATE_STORE_STYLES}, got {style!r}")
        self._cfg = cfg
        self._style = style
        self._dp16kd = dp16kd
        words = cfg.width * cfg.height
        super().__init__({"bus": In(StateStoreSignature(cfg)),
                          "next_read_addr": In(range(words))})

    @property
    def style(self) -> str:
        """``"memory"`` or ``"dp16kd"``."""
        return self._style

    def elaborate(self, platform):
        m = Module()
        cfg = self._cfg
        layout = state_word_layout(cfg)
        words = cfg.width * cfg.height
        bus = self.bus
        if self._style == "memory":
            m.submodules.memory = memory = Memory(shape=layout, depth=words, init=[])
            read = memory.read_port(domain="sync")
            write = memory.write_port(domain="sync")
            held = Signal(layout)       # the output register: the word read a pixel ahead
            m.d.comb += [
                read.addr.eq(self.next_read_addr),
                read.en.eq(bus.read_en),
                write.addr.eq(bus.write_addr),
                write.data.eq(bus.write_data),
                write.en.eq(bus.write_en),
                bus.read_data.eq(held),
            ]
            with m.If(bus.read_en):
                m.d.sync += held.eq(read.data)
            return m

        # ---- ECP5: DP16KDs, the output register in the block RAM ----------------------
        bits = layout.size
        banks = -(-words // DP16KD_MAX_DEPTH)
        low = DP16KD_MAX_DEPTH.bit_length() - 1                 # 14 address bits per bank
        outputs = []
        for bank in range(banks):
            write_here = bus.write_en
            if banks > 1:
                write_here = bus.write_en & (bus.write_addr[low:] == bank)
            outputs.append(dp16kd_memory(
                m, f"bank{bank}", width=bits, depth=min(words, DP16KD_MAX_DEPTH),
                read_addr=self.next_read_addr[:low], read_en=bus.read_en,
                out_en=bus.read_en, write_addr=bus.write_addr[:low],
                write_data=bus.write_data, write_en=write_here, cell=self._dp16kd))
        if banks == 1:
            m.d.comb += bus.read_data.as_value().eq(outputs[0])
        else:
            # The bank of the word in the output registers: registered with the same
            # enables as the block RAMs' address (stage 1) and output (stage 2) registers.
            ahead_bank = Signal(range(banks))
            held_bank = Signal(range(banks))
            with m.If(bus.read_en):
                m.d.sync += [ahead_bank.eq(self.next_read_addr[low:]), held_bank.eq(ahead_bank)]
            selected = outputs[0]
            for bank in range(1, banks):
                selected = Mux(held_bank == bank, outputs[bank], selected)
            m.d.comb += bus.read_data.as_value().eq(selected)
        return m

