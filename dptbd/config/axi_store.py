"""The state store in external memory over an AXI4 manager port: :class:`AxiStoreConfig`,
its parameters, the memory layout derived from them and every refusal (made by
:meth:`dptbd.config.DPConfig.axi_store`; ``docs/integration.md``, "State store in external
memory")."""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING

from dptbd.errors import ConfigError, check_int

if TYPE_CHECKING:
    from dptbd.config import DPConfig

__all__ = ["AXI_DATA_BITS", "AxiStoreConfig"]

#: Data widths of the state store's AXI4 manager port (``AxiStoreConfig.data_bits``).
AXI_DATA_BITS = (32, 64, 128)


@dataclasses.dataclass(frozen=True)
class AxiStoreConfig:
    """The state store in external memory over an AXI4 manager port: build parameters,
    refusals and the memory layout (``docs/integration.md``, "State store in external
    memory"). Made by :meth:`DPConfig.axi_store`.

    Pixel ``a = row * W + col`` keeps its state (E in the low bits, d above it) in the
    :attr:`DPConfig.state_slot_bits`-bit slot at byte address
    ``base_address + a * slot_bits / 8``, little endian; one frame's states, in place. The
    layout is the same at every :attr:`DPConfig.pixels_per_clock` P: the store port's word
    of P states (one beat of pixels) is P consecutive slots, ``words_per_beat = S / P`` of
    them in a data beat, so ``data_bits`` must hold P slots.

    Parameters
    ----------
    frame : DPConfig
        The configuration whose state is stored.
    data_bits : int
        Width of the AXI4 data bus, one of :data:`AXI_DATA_BITS`.
    id_bits : int
        Width of ``ARID`` / ``AWID`` / ``RID`` / ``BID``, in [1, 16]; the port uses ID 0.
    burst_beats : int
        Beats of a full INCR burst, a power of two in [2, 256] with at most 4096 bytes per
        burst (a burst then never crosses a 4 KB boundary).
    address_bits : int
        Width of ``ARADDR`` / ``AWADDR``, in [12, 64].
    base_address : int
        Reset value of the base address register, a multiple of the burst size
        :attr:`burst_bytes`; the whole frame must lie below ``2**address_bits``.
    outstanding : int
        Most bursts in flight per direction (reads issued without their last beat, writes
        without their response), in [1, 16].
    """

    frame: DPConfig
    data_bits: int = 64
    id_bits: int = 1
    burst_beats: int = 16
    address_bits: int = 32
    base_address: int = 0
    outstanding: int = 4

    def __post_init__(self) -> None:
        if self.data_bits not in AXI_DATA_BITS:
            raise ConfigError(f"data_bits must be one of {AXI_DATA_BITS}, "
                              f"got {self.data_bits!r}")
        slot = self.frame.state_slot_bits
        if slot > self.data_bits:
            raise ConfigError(
                f"data_bits={self.data_bits} cannot hold one {slot}-bit state slot "
                f"(state_bits={self.frame.state_bits}); use data_bits >= {slot}")
        lanes = self.frame.pixels_per_clock
        if self.states_per_beat < lanes:
            need = lanes * slot
            fix = (f"use data_bits >= {need}" if need <= max(AXI_DATA_BITS) else
                   f"no data_bits in {AXI_DATA_BITS} holds them; use fewer pixels_per_clock "
                   f"or a narrower state")
            raise ConfigError(
                f"data_bits={self.data_bits} holds {self.states_per_beat} {slot}-bit state "
                f"slot(s) per beat, fewer than the {lanes} states of a store word at "
                f"pixels_per_clock={lanes} (a word is never split over beats); {fix}")
        check_int("id_bits", self.id_bits, 1, 16, error=ConfigError)
        check_int("address_bits", self.address_bits, 12, 64, error=ConfigError)
        check_int("outstanding", self.outstanding, 1, 16, error=ConfigError)
        check_int("burst_beats", self.burst_beats, 2, 256, error=ConfigError)
        most = min(256, 4096 // self.beat_bytes)
        if self.burst_beats & (self.burst_beats - 1) or self.burst_beats > most:
            raise ConfigError(
                f"burst_beats must be a power of two in [2, {most}] (at most 4096 bytes of "
                f"{self.beat_bytes}-byte beats), got {self.burst_beats}")
        pixels = self.frame.width * self.frame.height
        if pixels % self.states_per_beat:
            raise ConfigError(
                f"width*height={pixels} is not a multiple of the {self.states_per_beat} "
                f"states per {self.data_bits}-bit beat; choose a frame size or data_bits "
                f"that divides it")
        ahead = self.frame.radius * (self.frame.width + lanes)   # the read-ahead, in states
        if pixels - ahead < 2 * self.burst_states:
            raise ConfigError(
                f"width={self.frame.width} x height={self.frame.height} is too small for "
                f"bursts of {self.burst_states} states: the external state store needs "
                f"width*height - radius*(width+{lanes}) >= 2 * {self.burst_states}, but it "
                f"is {pixels - ahead}; use a larger frame or fewer burst_beats")
        check_int("base_address", self.base_address, 0, error=ConfigError)
        if self.base_address % self.burst_bytes:
            raise ConfigError(
                f"base_address={self.base_address:#x} is not aligned to the burst size of "
                f"{self.burst_bytes} bytes ({self.burst_beats} beats of {self.beat_bytes})")
        end = self.base_address + self.frame_bytes
        if end > 1 << self.address_bits:
            raise ConfigError(
                f"the state of a frame ends at {end:#x} (base_address={self.base_address:#x} "
                f"+ {self.frame_bytes} bytes), beyond address_bits={self.address_bits} "
                f"({1 << self.address_bits:#x}); use more address bits or a lower base")

    @property
    def slot_bits(self) -> int:
        """Bits per stored state, :attr:`DPConfig.state_slot_bits`."""
        return self.frame.state_slot_bits

    @property
    def states_per_beat(self) -> int:
        """S, states packed in one data beat: ``data_bits / slot_bits`` (a power of two)."""
        return self.data_bits // self.slot_bits

    @property
    def beat_bytes(self) -> int:
        """Bytes per data beat (``AxSIZE = log2`` of it)."""
        return self.data_bits // 8

    @property
    def burst_bytes(self) -> int:
        """Bytes of a full burst, ``burst_beats * beat_bytes`` (<= 4096)."""
        return self.burst_beats * self.beat_bytes

    @property
    def burst_states(self) -> int:
        """States of a full burst, ``burst_beats * states_per_beat``."""
        return self.burst_beats * self.states_per_beat

    @property
    def frame_beats(self) -> int:
        """Data beats of one frame's state, ``W * H / S``."""
        return self.frame.width * self.frame.height // self.states_per_beat

    @property
    def word_states(self) -> int:
        """P, states in one word of the store port (the pipeline's beat):
        :attr:`DPConfig.pixels_per_clock`."""
        return self.frame.pixels_per_clock

    @property
    def word_bits(self) -> int:
        """Bits of one store word in memory: P slots, ``P * slot_bits``."""
        return self.word_states * self.slot_bits

    @property
    def words_per_beat(self) -> int:
        """Store words in one data beat, ``S / P`` (a power of two, at least 1)."""
        return self.states_per_beat // self.word_states

    @property
    def frame_words(self) -> int:
        """Store words of one frame, ``W * H / P`` (the store port's addresses)."""
        return self.frame.width * self.frame.height // self.word_states

    @property
    def burst_words(self) -> int:
        """Store words of a full burst, ``burst_beats * words_per_beat``."""
        return self.burst_beats * self.words_per_beat

    @property
    def frame_bytes(self) -> int:
        """Bytes of one frame's state, read once and written once per frame."""
        return self.frame_beats * self.beat_bytes
