"""``dptbd.config.energy``: the warning that B_E saturates, and the width that never does."""

from __future__ import annotations

import warnings

import pytest

from dptbd import DPConfig, EnergyWidthWarning


def test_non_saturating_energy_bits():
    from dptbd.config import non_saturating_energy_bits
    assert non_saturating_energy_bits(12, 6) == 15          # 6 * 4095 = 24570 < 2**15
    assert non_saturating_energy_bits(8, 1) == 8
    assert DPConfig(width=16, height=12, segment_frames=6, input_bits=12).energy_bits_needed == 15


# ---------------------------------------------------------------------------------------
# EnergyWidthWarning
# ---------------------------------------------------------------------------------------

@pytest.mark.parametrize("input_bits, k", [(8, 4), (8, 5), (1, 1), (4, 16), (16, 2), (12, 100)])
def test_energy_width_warning_exactly_below_needed(input_bits, k):
    needed = max(input_bits, (k * (2**input_bits - 1)).bit_length())
    for energy_bits in range(input_bits, 33):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            cfg = DPConfig(input_bits=input_bits, segment_frames=k, energy_bits=energy_bits)
        hits = [w for w in caught if issubclass(w.category, EnergyWidthWarning)]
        assert cfg.energy_bits_needed == needed
        if energy_bits < needed:
            assert len(hits) == 1, energy_bits
            assert "energy_bits" in str(hits[0].message)
            assert f">= {needed}" in str(hits[0].message)
        else:
            assert not hits, energy_bits
