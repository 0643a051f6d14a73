"""The specification of a comparison (:mod:`dptbd.evaluation.compare.spec`): LUTs, the ADC
mapping, the sweep grid, the TOML examples of ``docs/compare.md``."""

from __future__ import annotations

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.evaluation.compare import spec as compare_spec
from dptbd.evaluation.compare.spec import build_spec, cosine_weights


def test_cosine_lut():
    lut = cosine_weights(1)
    assert lut.shape == (10, 9) and np.all(lut[9] == 1) and np.all(lut[:, 4] == 1)
    assert lut[0, 0] == pytest.approx(1.0) and lut[0, 8] == pytest.approx(0.0)
    assert lut[1, 5] == pytest.approx(0.5) and lut[0, 1] == pytest.approx((1 + 0.5 ** 0.5) / 2)
    assert not DPConfig(weights=lut, weight_frac_bits=8).weights_exact


def test_adc_mapping_puts_the_window_on_the_codes():
    for bits in (3, 8, 12):
        gain, offset = compare_spec.adc_mapping(bits, 30.0, 2.0)
        assert gain * (30.0 - 12.0) + offset == pytest.approx(0.0)           # mu - 6 sigma -> 0
        assert gain * (30.0 + 20.0) + offset == pytest.approx(2 ** bits)     # mu + 10 sigma -> 2**B
        assert gain * 2.0 == pytest.approx(2 ** bits / 16)                   # sigma in LSB


def test_sweep_grid_and_dedup_against_explicit_configs():
    # "mine" is the sweep point 5/8/0 (8 = the worst-case width for K = 6, 5-bit pixels):
    # it is listed once, marked as a sweep member
    spec = build_spec({"trials": 1,
                       "config": [{"name": "mine", "input_bits": 5, "weight_frac_bits": 0}],
                       "sweep": {"input_bits": [4, 5], "energy_headroom": [0, -1],
                                 "weight_frac_bits": [0]}})
    names = [f.name for f in spec.configs]
    assert names == ["mine", "4/7/0 truncate paper", "4/6/0 truncate paper", "5/7/0 truncate paper"]
    assert spec.configs[0].in_sweep and spec.configs[0].explicit
    assert spec.configs[0].cfg.energy_bits == 8 and not spec.configs[0].saturates
    assert spec.configs[2].saturates and not spec.configs[2].explicit


def test_the_toml_examples_in_docs_compare_md_are_valid():
    import pathlib
    import re
    import tomllib
    text = (pathlib.Path(__file__).resolve().parents[3] / "docs" / "compare.md").read_text()
    blocks = re.findall(r"```toml\n(.*?)```", text, re.S)
    assert len(blocks) >= 2
    specs = [build_spec(tomllib.loads(b)) for b in blocks]
    default = build_spec({})
    assert [f.name for f in specs[0].configs] == [f.name for f in default.configs]
    assert len(specs[1].configs) == 1 + 3 + 4 * 2 and specs[1].trials == 2000
