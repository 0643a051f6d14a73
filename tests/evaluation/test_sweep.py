"""The bit-width sweep of ``dptbd compare`` (:mod:`dptbd.evaluation.sweep`): verdicts, the
smallest configuration within the tolerance, the cached hardware cost."""

from __future__ import annotations

from dptbd.config import DPConfig
from dptbd.evaluation import sweep
from dptbd.evaluation.compare import build_spec
from dptbd.evaluation.snr_loss import LossEstimate


def test_verdicts():
    def e(lo, hi):
        return LossEstimate(0.5, (lo + hi) / 2, lo, hi, 0.0, 0.0, 0.0)
    assert sweep.verdict([e(-0.05, 0.08), e(0.0, 0.1)], 0.1) == "within"
    assert sweep.verdict([e(-0.05, 0.08), e(0.05, 0.2)], 0.1) == "undecided"
    assert sweep.verdict([e(-0.05, 0.08), e(0.11, 0.3)], 0.1) == "beyond"


def test_cost_key_and_choose_the_smallest_configuration_within_the_tolerance():
    spec = build_spec({"trials": 1,
                       "config": [{"name": "tiny", "input_bits": 3, "weight_frac_bits": 0}],
                       "sweep": {"input_bits": [6, 7, 8], "energy_headroom": [0, -1],
                                 "weight_frac_bits": [0]}})
    by = {f.name: f for f in spec.configs}
    assert not by["tiny"].in_sweep
    f = by["7/9/0 truncate paper"]
    assert sweep.cost_key(f) == (9 + 4, 0, 7, 0)               # B_E + B_d (r = 1), LUT4, B_in, F
    assert sweep.cost_key(f, {"lut4": 745}) == (13, 745, 7, 0)
    verdicts = {name: "beyond" for name in by}
    verdicts.update({"tiny": "within",                        # smaller, but not in the sweep
                     "8/10/0 truncate paper": "within", "8/11/0 truncate paper": "within",
                     "7/10/0 truncate paper": "within", "7/9/0 truncate paper": "within",
                     "6/8/0 truncate paper": "undecided"})
    assert sweep.choose(spec.configs, verdicts) == {"within": "7/9/0 truncate paper",
                                                   "not_beyond": "6/8/0 truncate paper"}
    # the state word first: 7/10/0 and 8/10/0 tie at 14 bits; then SB_LUT4 when known, else B_in
    verdicts["7/9/0 truncate paper"] = "beyond"
    verdicts["6/8/0 truncate paper"] = "beyond"
    assert sweep.choose(spec.configs, verdicts)["within"] == "7/10/0 truncate paper"
    hw = {"7/10/0 truncate paper": {"lut4": 800}, "8/10/0 truncate paper": {"lut4": 780}}
    assert sweep.choose(spec.configs, verdicts, hw) == {"within": "8/10/0 truncate paper",
                                                       "not_beyond": "8/10/0 truncate paper"}
    # nothing within: None; no configuration in a sweep: every configuration is a candidate
    assert sweep.choose(spec.configs, {n: "beyond" for n in by}) == {"within": None,
                                                                   "not_beyond": None}
    alone = build_spec({"trials": 1, "sweep": {},
                        "config": [{"name": "a", "input_bits": 8}, {"name": "b", "input_bits": 6}]})
    assert sweep.choose(alone.configs, {"a": "within", "b": "within"})["within"] == "b"


def test_hardware_cost_is_cached(tmp_path):
    calls = []

    class Cells:
        lut4, dff, bram, carry = 100, 50, 3, 20

    class Result:
        cells = Cells()
        fmax_median_mhz = 101.0
        fmaxes_mhz = (99.0, 101.0, 103.0)
        fits = True
        utilisation = {"ICESTORM_LC": (140, 7680)}
        yosys_seconds = verilog_seconds = 1.0
        runs = ()

    def fake(cfg, **kw):
        calls.append((cfg, kw))
        return Result()

    cfg = DPConfig(width=16, height=16)
    a = sweep.hardware_cost(cfg, cache_dir=tmp_path, synthesize=fake, tools={"yosys": "x"})
    b = sweep.hardware_cost(cfg, cache_dir=tmp_path, synthesize=fake, tools={"yosys": "x"})
    c = sweep.hardware_cost(cfg.replace(energy_bits=12), cache_dir=tmp_path, synthesize=fake,
                            tools={"yosys": "x"})
    assert len(calls) == 2 and not a.cached and b.cached and not c.cached
    # a changed gateware source is a different key: synthesised again, then cached
    d = sweep.hardware_cost(cfg, cache_dir=tmp_path, synthesize=fake, tools={"yosys": "x"},
                            gateware="changed")
    assert len(calls) == 3 and not d.cached
    assert sweep.hardware_cost(cfg, cache_dir=tmp_path, synthesize=fake, tools={"yosys": "x"},
                               gateware="changed").cached
    assert len(sweep.gateware_hash()) == 24
    assert (b.lut4, b.ff, b.bram, b.fmax_median_mhz, b.logic_cells) == (100, 50, 3, 101.0, 140)
    assert calls[0][1]["variant"] == "core" and calls[0][1]["device"] == "hx8k"


def test_hardware_key_is_stable_and_covers_every_field():
    # the cache key of a synthesis result: pinned, so that a refactoring of how the
    # configuration is serialised (DPConfig.to_mapping) never invalidates the cache
    cfg = DPConfig(width=16, height=16, candidate_count=3)
    kw = dict(variant="core", device="hx8k", package="ct256", seeds=(1, 2, 3), target_mhz=100.0,
              tools={"yosys": "x"}, gateware="g")
    assert sweep.hardware_key(cfg, **kw) == "829dc66bbdcca1ef2d633d4f"
    assert sweep.hardware_key(cfg.replace(histogram_bits=9), **kw) != "829dc66bbdcca1ef2d633d4f"
    assert sweep.hardware_key(cfg, **dict(kw, gateware="h")) != "829dc66bbdcca1ef2d633d4f"


def test_state_store_bits_is_the_frame_of_state_words():
    cfg = DPConfig(width=16, height=8, energy_bits=12)
    assert sweep.state_store_bits(cfg) == 16 * 8 * (12 + 4) == 16 * 8 * cfg.state_bits
