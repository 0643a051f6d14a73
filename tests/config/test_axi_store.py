"""``dptbd.config.AxiStoreConfig``: the external state store's layout and refusals
(``docs/integration.md``, "State store in external memory")."""

from __future__ import annotations

import warnings

import pytest

from dptbd import ConfigError, DPConfig, EnergyWidthWarning
from helpers.refusals import whole


@pytest.mark.parametrize("kw, slot, per_beat, frame_bytes, burst_bytes", [
    (dict(width=640, height=512), 32, 2, 640 * 512 * 4, 16 * 8),        # 20-bit state
    (dict(width=640, height=512, segment_frames=2, energy_bits=9), 16, 4, 640 * 512 * 2, 128),
    (dict(width=1280, height=1024, segment_frames=1, input_bits=4, energy_bits=4), 8, 8,
     1280 * 1024, 128),                                                  # 8-bit state
])
def test_axi_store_layout(kw, slot, per_beat, frame_bytes, burst_bytes):
    store = DPConfig(**kw).axi_store()
    assert (store.slot_bits, store.states_per_beat) == (slot, per_beat)
    assert (store.frame_bytes, store.burst_bytes) == (frame_bytes, burst_bytes)
    assert store.frame_beats * store.beat_bytes == store.frame_bytes
    assert store.burst_states == 16 * per_beat


def test_state_slot_bits_is_a_power_of_two_of_at_least_a_byte():
    assert DPConfig(segment_frames=1, input_bits=2, energy_bits=2).state_slot_bits == 8  # 6 bits
    assert DPConfig().state_slot_bits == 32                                  # 20 bits
    assert DPConfig(energy_bits=32).state_slot_bits == 64                    # 36 bits


AXI_STORE_BAD = [
    (dict(), dict(data_bits=48), "data_bits must be one of (32, 64, 128), got 48"),
    (dict(energy_bits=32), dict(data_bits=32),
     "data_bits=32 cannot hold one 64-bit state slot (state_bits=36); use data_bits >= 64"),
    (dict(), dict(id_bits=0), "id_bits must be an integer in [1, 16], got 0"),
    (dict(), dict(address_bits=65), "address_bits must be an integer in [12, 64], got 65"),
    (dict(), dict(outstanding=17), "outstanding must be an integer in [1, 16], got 17"),
    (dict(), dict(burst_beats=1), "burst_beats must be an integer in [2, 256], got 1"),
    (dict(), dict(burst_beats=12),
     "burst_beats must be a power of two in [2, 256] (at most 4096 bytes of 8-byte beats), "
     "got 12"),
    (dict(), dict(data_bits=128, burst_beats=512),
     "burst_beats must be an integer in [2, 256], got 512"),
    (dict(width=130, height=3), dict(data_bits=128, burst_beats=2),
     "width*height=390 is not a multiple of the 4 states per 128-bit beat; choose a frame "
     "size or data_bits that divides it"),
    (dict(width=16, height=4), dict(burst_beats=16),
     "width=16 x height=4 is too small for bursts of 32 states: the external state store "
     "needs width*height - radius*(width+1) >= 2 * 32, but it is 47; use a larger frame or "
     "fewer burst_beats"),
    (dict(width=16, height=12, pixels_per_clock=4), dict(data_bits=64),
     "data_bits=64 holds 2 32-bit state slot(s) per beat, fewer than the 4 states of a store "
     "word at pixels_per_clock=4 (a word is never split over beats); use data_bits >= 128"),
    (dict(width=16, height=12, pixels_per_clock=4, energy_bits=32), dict(data_bits=128),
     "data_bits=128 holds 2 64-bit state slot(s) per beat, fewer than the 4 states of a store "
     "word at pixels_per_clock=4 (a word is never split over beats); no data_bits in (32, 64, "
     "128) holds them; use fewer pixels_per_clock or a narrower state"),
    (dict(width=12, height=3, pixels_per_clock=4), dict(data_bits=128, burst_beats=4),
     "width=12 x height=3 is too small for bursts of 16 states: the external state store "
     "needs width*height - radius*(width+4) >= 2 * 16, but it is 20; use a larger frame or "
     "fewer burst_beats"),
    (dict(), dict(base_address=-1), "base_address must be an integer in [0, inf), got -1"),
    (dict(), dict(base_address=0x1040),
     "base_address=0x1040 is not aligned to the burst size of 128 bytes (16 beats of 8)"),
    (dict(width=640, height=512), dict(address_bits=20),
     "the state of a frame ends at 0x140000 (base_address=0x0 + 1310720 bytes), beyond "
     "address_bits=20 (0x100000); use more address bits or a lower base"),
    (dict(width=640, height=512), dict(base_address=0xFFF00000),
     "the state of a frame ends at 0x100040000 (base_address=0xfff00000 + 1310720 bytes), "
     "beyond address_bits=32 (0x100000000); use more address bits or a lower base"),
]


@pytest.mark.parametrize("frame, fields, message", AXI_STORE_BAD,
                         ids=[m.split(" ")[0] + str(i) for i, (_, _, m) in enumerate(AXI_STORE_BAD)])
def test_axi_store_refusals(frame, fields, message):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        cfg = DPConfig(**frame)
    with pytest.raises(ConfigError, match=whole(message)):
        cfg.axi_store(**fields)


def test_axi_store_accepts_the_4kb_burst_and_a_full_address_space():
    store = DPConfig(width=640, height=512).axi_store(data_bits=128, burst_beats=256,
                                                      base_address=0x1000)
    assert store.burst_bytes == 4096
    assert DPConfig(width=640, height=512).axi_store(
        address_bits=21, base_address=0x200000 - 640 * 512 * 4).frame_bytes == 1310720


@pytest.mark.parametrize("kw, fields, words_per_beat, frame_words", [
    (dict(pixels_per_clock=2, energy_bits=10), dict(data_bits=32), 1, 96),   # 16-bit slots
    (dict(pixels_per_clock=2, energy_bits=10), dict(data_bits=128, burst_beats=2), 4, 96),
    (dict(pixels_per_clock=4), dict(data_bits=128), 1, 48),                  # 32-bit slots
    (dict(), dict(data_bits=64), 2, 192),
])
def test_a_store_word_is_p_slots_in_the_p1_layout(kw, fields, words_per_beat, frame_words):
    """The byte layout does not depend on P: a store word is P consecutive slots, and a
    beat holds S / P of them."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        cfg = DPConfig(width=16, height=12, **kw)
    store = cfg.axi_store(**fields)
    p = cfg.pixels_per_clock
    assert (store.word_states, store.word_bits) == (p, p * store.slot_bits)
    assert (store.words_per_beat, store.frame_words) == (words_per_beat, frame_words)
    assert store.burst_words * p == store.burst_states
    assert store.frame_bytes == 16 * 12 * store.slot_bits // 8           # as at P = 1
