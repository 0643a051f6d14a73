"""The plan of a comparison (:mod:`dptbd.evaluation.compare.plan`): configurations that
compute identical bits share one detector, unless the ``gateware-bins`` rule selects their
candidates on different histograms."""

from __future__ import annotations

import pytest

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


@pytest.mark.parametrize("tie_rule, shared", [("random", True), ("gateware", True),
                                               ("gateware-bins", False)])
def test_a_histogram_of_its_own_is_a_detector_of_its_own_under_gateware_bins(tie_rule, shared):
    # "a" and "s0" compute the same bits (8-bit ADC, paper LUT, no saturation); their
    # histograms differ: s = 1 (the default for B_E = 11 over 1024 bins) and s = 0. Only
    # gateware-bins looks at the histogram, so only there they are two detectors, each
    # running with its own configuration (its own s); "s0b" shares "s0"'s histogram.
    spec = build_spec({"trials": 1, "sweep": {}, "tie_rule": tie_rule,
                       "config": [{"name": "a", "input_bits": 8},
                                  {"name": "s0", "input_bits": 8, "histogram_shift": 0},
                                  {"name": "s0b", "input_bits": 8, "histogram_shift": 0,
                                   "energy_bits": 16}]})
    plan = make_plan(spec)
    det = dict(zip([f.name for f in spec.configs], plan.config_detector))
    assert det["s0"] == det["s0b"] and (det["a"] == det["s0"]) == shared
    n_float = len(plan.floats)
    assert [c.bin_shift for c in plan.fixed] == ([1] if shared else [1, 0])
    assert plan.fixed[det["s0"] - n_float].bin_shift == (1 if shared else 0)
    assert plan.detector_names()[n_float:] == (["a = s0 = s0b"] if shared else ["a", "s0 = s0b"])
