"""Paper 000's family in Verilog: every variant converts, its ports are the 001 ports plus
the merit / penalty write ports of the LUTs it builds, and the default build is unchanged."""

import shutil
import warnings

import numpy as np
import pytest

from dptbd.config import DPConfig, EnergyWidthWarning
from dptbd.hw.dp_core import DPCore
from dptbd.hw.schedule import PipelineSchedule
from dptbd.hw.dp_segmenter_top import DPSegmenter
from dptbd.hw.flow.verilog import generate_verilog
from family_harness import VARIANTS, family_reference_states, likelihood_merit, variant
from hw_harness import assert_states_equal, assert_verilator_lints_clean, refused

pytestmark = pytest.mark.filterwarnings("ignore::dptbd.config.EnergyWidthWarning")

PAPER001_PORTS = {"clk", "rst", "pixels__payload", "pixels__valid", "pixels__ready",
                  "states__payload", "states__valid", "states__ready", "lut_addr", "lut_data",
                  "lut_we", "segment_frames", "segment_begin", "events"}


def make_config(**kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        return DPConfig(**kw)


def ports_of(info):
    return {p["name"]: (p["direction"], p["width"]) for p in info["ports"]}


@pytest.mark.parametrize("name", VARIANTS)
def test_every_variant_converts_with_its_write_ports(name):
    cfg = make_config(**variant(name)[0])
    text, info = generate_verilog(cfg)
    ports = ports_of(info)
    extra = {}
    if "merit_codes" in cfg.family_fields_in_use:
        extra.update({"merit_addr": ("input", cfg.input_bits),
                      "merit_data": ("input", cfg.merit_width), "merit_we": ("input", 1)})
    if "penalty_codes" in cfg.family_fields_in_use:
        extra.update({"penalty_addr": ("input", (cfg.lut_entries - 1).bit_length()),
                      "penalty_data": ("input", cfg.penalty_width), "penalty_we": ("input", 1)})
    assert set(ports) == PAPER001_PORTS | set(extra)
    assert {k: ports[k] for k in extra} == extra
    assert info["latency"] == PipelineSchedule.from_config(cfg).latency
    assert "module dptbd_dp(" in text


@pytest.mark.skipif(shutil.which("verilator") is None, reason="verilator not installed")
def test_all_family_blocks_lint_clean(tmp_path):
    """Merit LUT, penalty LUT (r = 2, block RAM), signed tree, forgetting, recursion."""
    cfg = make_config(**{**variant("recursive-r2-truncate")[0],
                         "merit_codes": np.arange(256) - 100, "energy_bits": 12})
    assert len(cfg.family_fields_in_use) == 4
    text, _ = generate_verilog(cfg)
    path = tmp_path / "dptbd_dp.v"
    path.write_text(text)
    assert_verilator_lints_clean(path, "dptbd_dp")


@pytest.mark.parametrize("external", [False, True])
def test_the_paper001_build_is_unchanged_by_default_valued_family_fields(external):
    """§8 fields set to values that do not change the arithmetic build the §4-§5 pipeline:
    byte-identical Verilog, the 001 ports, the 001 latency."""
    base = DPConfig(width=8, height=8)
    explicit = base.replace(merit_codes=np.arange(256), penalty_codes=np.zeros((10, 9), int),
                            forgetting=1.0, forgetting_bits=5)
    assert explicit.is_paper001_datapath
    text, info = generate_verilog(base, external_state_store=external)
    assert generate_verilog(explicit, external_state_store=external)[0] == text
    assert {"merit_we", "penalty_we"}.isdisjoint(ports_of(info))
    if not external:
        assert set(ports_of(info)) == PAPER001_PORTS
    assert info["latency"] == 14 and info["schedule"]["faded"] == info["schedule"]["best"]


def test_the_segmenter_top_refuses_a_family_configuration():
    cfg = make_config(width=8, height=8, recursive=True)
    with refused(Exception, match=(
            r"^the segmenter top \(dptbd\.hw\.dp_segmenter_top\) implements paper 001's "
            r"datapath only \(docs/arithmetic\.md §4-§5\), but this configuration sets paper "
            r"000's family field\(s\) recursive \(§8\): use "
            r"dptbd\.model\.family\.run_family_fixed$")):
        DPSegmenter(cfg)
    DPCore(cfg)._MustUse__silence = True   # the DP core itself builds it


@pytest.mark.skipif(shutil.which("iverilog") is None, reason="iverilog not installed")
def test_icarus_runs_the_family_verilog_bit_exact(tmp_path):
    """The generated Verilog of a variant with every block (merit LUT, penalty LUT, signed
    tree, forgetting, recursion) in a 4-state simulator, with random gaps and back-pressure
    (``test_verilog``'s testbench, the write ports held idle), against the golden model."""
    from test_verilog import icarus_states

    cfg = make_config(**{**variant("recursive-r1")[0], "merit_codes": likelihood_merit()})
    assert len(cfg.family_fields_in_use) == 4
    text, info = generate_verilog(cfg)
    (tmp_path / "dptbd_dp.v").write_text(text)
    frames = np.random.default_rng(5).integers(0, 256, size=(5, cfg.height, cfg.width))
    outputs = icarus_states(cfg, frames, info, tmp_path / "dptbd_dp.v", tmp_path, timeout=300,
                            idle_inputs=("merit_addr", "merit_data", "merit_we",
                                         "penalty_addr", "penalty_data", "penalty_we"))
    assert_states_equal(outputs, family_reference_states(cfg, frames))
