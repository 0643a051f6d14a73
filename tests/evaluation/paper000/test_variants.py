"""``dptbd.evaluation.paper000.variants``: 000's variants as DPConfigs, E mapped back to h."""

from __future__ import annotations

import numpy as np
import pytest

from dptbd.evaluation.detectors import merits, paper000, unified
from dptbd.evaluation.detectors._checks import DetectorError
from dptbd.evaluation.paper000.variants import (ADC_GAIN, ADC_OFFSET, LIKELIHOOD_SCALE,
                                                fixed_maps, fixed_variant, quantise_scene)
from dptbd.scenes import synthetic as scenes

EQ15, EQ24, LIK6, LIK3 = paper000.CASES


def test_eq15_is_paper_001s_datapath_and_the_others_are_family_configurations():
    assert fixed_variant(EQ15).cfg.is_paper001_datapath
    assert fixed_variant(EQ24).cfg.family_fields_in_use == ["penalty_codes"]
    assert fixed_variant(LIK6).cfg.family_fields_in_use == ["merit_codes", "penalty_codes"]
    cfg = fixed_variant(LIK3, frames=7).cfg
    assert (cfg.width, cfg.height, cfg.segment_frames, cfg.radius, cfg.weight_frac_bits) == \
        (64, 64, 7, 2, 0)


def test_likelihood_merit_and_penalty_codes_are_the_scaled_rounded_tables():
    cfg = fixed_variant(LIK6).cfg
    z = (np.arange(256) - ADC_OFFSET) / ADC_GAIN
    assert np.array_equal(cfg.merit_code_array,
                          np.floor(LIKELIHOOD_SCALE * LIK6.merit_fn()(z) + 0.5).astype(np.int64))
    assert np.array_equal(cfg.penalty_code_array,
                          np.floor(-LIKELIHOOD_SCALE * LIK6.transition() + 0.5).astype(np.int64))


@pytest.mark.parametrize("case", [EQ15, EQ24])
def test_amplitude_variants_map_back_to_the_float_dp_of_the_codes_exactly(case):
    # identity merit: E = sum of codes - sum of Qc, so (E - T 128) / 16 is the float DP of
    # the codes' measurements with Q = -Qc / 16 (integer LUTs, nothing clamps)
    frames = scenes.paper000_scenario(case.snr_db, seed=3, trials=2, frames=6).frames
    variant = fixed_variant(case, frames=6)
    codes = quantise_scene(frames)
    got, tally = fixed_maps(variant, codes, "model")
    z = (codes.astype(np.float64) - ADC_OFFSET) / ADC_GAIN
    want = unified.run_unified(z, merits.amplitude_merit(),
                               -variant.cfg.penalty_code_array / ADC_GAIN).value
    assert tally is None
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-9)


def test_unknown_engine_is_refused():
    with pytest.raises(DetectorError, match=r"^engine must be one of \('model', 'rtl'\), got 'gpu'$"):
        fixed_maps(fixed_variant(EQ15, frames=2), np.zeros((1, 2, 64, 64), np.uint16), "gpu")
