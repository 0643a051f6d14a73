"""The plan of a comparison (:mod:`dptbd.evaluation.compare.plan`): configurations that
compute identical bits share one detector."""

from __future__ import annotations

from dptbd.evaluation.compare.plan import make_plan
from dptbd.evaluation.compare.spec import build_spec


def test_identical_configurations_share_one_detector():
    spec = build_spec({
        "trials": 1, "sweep": {},
        "config": [{"name": "a", "input_bits": 8, "weight_frac_bits": 0},
                   {"name": "b", "input_bits": 8, "weight_frac_bits": 8, "rounding": "half_up",
                    "energy_bits": 20},               # paper LUT: F, rounding irrelevant; no saturation
                   {"name": "c", "input_bits": 8, "energy_bits": 9},     # may saturate
                   {"name": "d", "lut": "cosine", "weight_frac_bits": 2},
                   {"name": "e", "lut": "cosine", "weight_frac_bits": 2, "rounding": "half_up"}]})
    plan = make_plan(spec)
    det = dict(zip([f.name for f in spec.configs], plan.config_detector))
    assert det["a"] == det["b"] and len({det["a"], det["c"], det["d"], det["e"]}) == 4
    assert len(plan.floats) == 2  # paper and cosine
    assert spec.configs[0].cfg.energy_bits == 11  # "needed" for K = 6, 8-bit pixels
    assert spec.configs[2].saturates
