"""The specification of a comparison (:mod:`dptbd.evaluation.compare.spec`): the sweep grid,
the refusals, the TOML examples of ``docs/compare.md``."""

from __future__ import annotations

import re

import pytest

from dptbd.errors import ConfigError
from dptbd.evaluation.compare import spec as compare_spec
from dptbd.evaluation.compare.spec import build_spec
from helpers.refusals import whole


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
    import tomllib
    text = (pathlib.Path(__file__).resolve().parents[3] / "docs" / "compare.md").read_text()
    blocks = re.findall(r"```toml\n(.*?)```", text, re.S)
    assert len(blocks) >= 2
    specs = [build_spec(tomllib.loads(b)) for b in blocks]
    default = build_spec({})
    assert [f.name for f in specs[0].configs] == [f.name for f in default.configs]
    assert len(specs[1].configs) == 1 + 3 + 4 * 2 and specs[1].trials == 2000


_RUN_KEYS = ("['adc_low_sigma', 'adc_span_sigma', 'bootstrap', 'chunk', 'false_alarm_rate', "
             "'frames', 'mu', 'pd_levels', 'pfa', 'radius', 'seed', 'segment_frames', 'segment_stride', "
             "'sigma', 'size', 'snr', 'thresholds', 'tie_rule', 'tolerance_db', 'trials', 'velocity', "
             "'config', 'sweep']")
_LUTS = "('paper', 'plain', 'cosine')"


@pytest.mark.parametrize("mapping, message", [
    # the run's parameters
    ({"frobnicate": 1}, f"unknown parameter(s) ['frobnicate']; allowed: {_RUN_KEYS}"),
    ({"trials": 0}, "trials must be an integer in [1, inf), got 0"),
    ({"trials": 2.5}, "trials must be an integer in [1, inf), got 2.5"),
    ({"seed": True}, "seed must be an integer in [0, inf), got True"),
    ({"snr": []}, "snr must hold at least 2 value(s), got [] (an empty list)"),
    ({"snr": [2.0]}, "snr must hold at least 2 value(s), got [2.0]"),
    ({"snr": [2.0, 1.5]}, "snr must be strictly increasing, but snr[1] = 1.5 <= snr[0] = 2"),
    ({"snr": "2.0"}, "snr must be a list, got '2.0'"),
    ({"snr": [1.0, "x"]}, "snr[1] must be a finite real number in (0, inf), got 'x'"),
    ({"snr": [0.0, 1.0]}, "snr[0] must be a finite real number in (0, inf), got 0.0"),
    ({"sigma": float("nan")}, "sigma must be a finite real number in (0, inf), got nan"),
    ({"sigma": 0}, "sigma must be a finite real number in (0, inf), got 0"),
    ({"size": 2}, "size must be an integer in [3, 4096], got 2"),
    ({"velocity": [1.0]}, "velocity must be a (row, col) pair, got [1.0]"),
    ({"velocity": [1.0, "a"]}, "velocity[1] must be a finite real number in (-inf, inf), got 'a'"),
    ({"mu": float("inf")}, "mu must be a finite real number in (-inf, inf), got inf"),
    ({"segment_stride": 7}, "segment_stride must be an integer in [1, 6], got 7"),
    ({"radius": 3}, "radius must be an integer in [1, 2], got 3"),
    ({"frames": 4}, "frames=4 is shorter than one segment (segment_frames=6)"),
    ({"false_alarm_rate": 1.0}, "false_alarm_rate must be a finite real number in (0, 1), got 1.0"),
    ({"false_alarm_rate": 0}, "false_alarm_rate must be a finite real number in (0, 1), got 0"),
    ({"false_alarm_rate": 0.0001, "size": 16},
     "false_alarm_rate=0.0001 keeps no candidate in a 16x16 image"),
    ({"thresholds": [3.0, 3.0]},
     "thresholds must be strictly increasing, but thresholds[1] = 3 <= thresholds[0] = 3"),
    ({"pd_levels": []}, "pd_levels must not be empty"),
    ({"pfa": []}, "pfa must hold at least one false-alarm probability per pixel in (0, 1)"),
    ({"pfa": 0.01}, "pfa must be a list, got 0.01"),
    ({"pfa": [0.01, 1.0]}, "pfa[1] (false-alarm probability per pixel) must be a finite real number in (0, 1), got 1.0"),
    ({"pfa": [1e-9]}, "pfa[0]=1e-09 needs at least 1000000000 noise-only pixels, 240 trials give 7864320; "
                      "raise trials or pfa"),
    ({"pd_levels": [1.0]}, "pd_levels[0] must be a finite real number in (0, 1), got 1.0"),
    ({"tolerance_db": -0.1}, "tolerance_db must be a finite real number in [0, inf), got -0.1"),
    ({"bootstrap": -1}, "bootstrap must be an integer in [0, 1000000], got -1"),
    ({"chunk": 0}, "chunk must be an integer in [1, inf), got 0"),
    ({"adc_span_sigma": 0.0}, "adc_span_sigma must be a finite real number in (0, inf), got 0.0"),
    ({"tie_rule": "raster"},
     "tie_rule must be one of ('random', 'gateware', 'gateware-bins'), got 'raster'"),
    ({"tie_rule": 1}, "tie_rule must be one of ('random', 'gateware', 'gateware-bins'), got 1"),
    # the [[config]] tables
    ({"config": [3]}, "config[0] must be a table of parameters, got 3"),
    ({"config": [{"segment_frames": 8}]},
     "config[0]: ['segment_frames'] are run-level parameters (every configuration runs on the "
     "same scenes); set them at the top level of the file"),
    ({"config": [{"input_bits": 8, "widht": 3}]},
     "config[0]: unknown configuration key(s) ['widht']; allowed: ['adc_gain', 'adc_offset', "
     "'energy_bits', 'histogram_bits', 'histogram_shift', 'input_bits', 'lut', 'name', "
     "'rounding', 'weight_frac_bits', 'weights']"),
    ({"config": [{"input_bits": 8, "histogram_shift": 11}]},
     "config[0]: histogram_shift must be an integer in [0, 10], got 11"),
    ({"config": [{"lut": "paper", "weights": [[1.0]]}]},
     f"config[0]: give either 'lut' (one of {_LUTS}) or 'weights' (a table), not both"),
    ({"config": [{"lut": 3}]}, f"config[0]: lut must be one of {_LUTS}, got 3"),
    ({"config": [{"lut": "round"}]},
     f"lut must be one of {_LUTS} (or give 'weights' as a table), got 'round'"),
    ({"config": [{"energy_bits": "lots"}]},
     "config[0]: energy_bits must be an integer or \"needed\", got 'lots'"),
    ({"config": [{"input_bits": 17}]}, "config[0]: input_bits must be an integer in [1, 16], got 17"),
    ({"config": [{"input_bits": 8, "energy_bits": 6}]},
     "config[0]: energy_bits must be an integer in [input_bits=8, 32], got 6"),
    ({"config": [{"rounding": "nearest"}]},
     "config[0]: rounding must be one of ('truncate', 'half_up'), got 'nearest'"),
    ({"config": [{"adc_gain": -1.0}]},
     "config[0]: adc_gain must be a finite real number in (0, inf), got -1.0"),
    ({"config": [{"adc_offset": "0"}]},
     "config[0]: adc_offset must be a finite real number in (-inf, inf), got '0'"),
    ({"config": [{"name": " "}]}, "config[0]: name must be a non-empty string, got ' '"),
    ({"config": [{"name": "a"}, {"name": "a"}], "sweep": {}},
     "configuration names must be unique, repeated: ['a']"),
    ({"config": [], "sweep": {}}, "nothing to compare: no [[config]] and an empty sweep"),
    # the [sweep] table
    ({"sweep": 3}, "sweep must be a table (or a list of tables), got 3"),
    ({"sweep": {"bits": [8]}},
     "sweep: unknown key(s) ['bits']; allowed: ['energy_bits', 'energy_headroom', 'input_bits', "
     "'lut', 'rounding', 'weight_frac_bits']"),
    ({"sweep": {"energy_bits": [9], "energy_headroom": [0]}},
     "sweep: give either energy_bits (absolute widths) or energy_headroom (B_E minus the "
     "worst-case width), not both"),
    ({"sweep": {"input_bits": []}}, "sweep.input_bits must not be empty"),
    ({"sweep": {"input_bits": [0]}}, "sweep.input_bits must be an integer in [1, 16], got 0"),
    ({"sweep": {"input_bits": [8], "energy_headroom": [40]}},
     "sweep.energy_headroom must be an integer in [-32, 32], got 40"),
    ({"sweep": {"input_bits": [8], "energy_headroom": [-6]}},
     "sweep point input_bits=8, energy_bits=5: energy_bits must be an integer in [input_bits=8, 32], got 5"),
])
def test_bad_parameters_are_refused_naming_them(mapping, message):
    with pytest.raises(ConfigError, match=whole(message)):
        build_spec(mapping)


def test_tie_rule_is_a_run_parameter_recorded_unless_it_is_the_default():
    # the default rule is left out of the run's parameters (compare_summary.json): a summary
    # without it is a random run, as every run before the option was
    assert compare_spec.TIE_RULES == ("random", "gateware", "gateware-bins")
    assert build_spec({}).tie_rule == "random" and "tie_rule" not in build_spec({}).run_params()
    spec = build_spec({"tie_rule": "gateware"}, tie_rule="gateware-bins")  # the override wins
    assert spec.tie_rule == "gateware-bins" and spec.run_params()["tie_rule"] == "gateware-bins"
    assert build_spec({"tie_rule": "gateware"}).run_params()["tie_rule"] == "gateware"


def test_a_configuration_may_set_its_histogram():
    spec = build_spec({"config": [{"name": "a", "input_bits": 8, "histogram_shift": 3},
                                  {"name": "b", "input_bits": 8, "histogram_bits": 6}],
                       "sweep": {}})
    assert [f.cfg.bin_shift for f in spec.configs] == [3, 5]   # B_E = 11: 11 - 6 = 5
    assert [f.cfg.n_bins for f in spec.configs] == [1024, 64]


def test_unknown_overrides_are_refused():
    with pytest.raises(ConfigError, match=r"^unknown parameter\(s\) \['frobnicate'\]$"):
        build_spec({}, frobnicate=1)


def test_overrides_replace_the_file_and_none_keeps_it():
    spec = build_spec({"trials": 5, "seed": 3}, trials=None, seed=4)
    assert (spec.trials, spec.seed) == (5, 4)
    assert spec.configs[0].name == compare_spec.DEFAULT_CONFIGS[0]["name"]
