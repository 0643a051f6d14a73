"""``dptbd.hw.flow.synth``: the flow's result, its argument and tool checks, and one small
real Yosys run (and, with ``-m slow``, one real place and route).

The parsers and the tool handling have their own tests: ``test_yosys.py``,
``test_nextpnr.py``, ``test_synth_tools.py``.
"""

import dataclasses
import json
import shutil
import warnings

import pytest

from dptbd.config import DPConfig
from dptbd.hw.flow.synth import (
    CellCounts, PnrRun, SynthResult, ToolNotFoundError, synthesize,
)


needs_yosys = pytest.mark.skipif(shutil.which("yosys") is None, reason="yosys not installed")
needs_nextpnr = pytest.mark.skipif(shutil.which("nextpnr-ice40") is None,
                                   reason="nextpnr-ice40 not installed")


def test_result_median_and_fit():
    def run(seed, fmax, fits=True):
        return PnrRun(seed=seed, fits=fits, fmax_mhz=fmax, target_mhz=100.0,
                      utilisation={"ICESTORM_LC": (10, 20)}, seconds=1.0)
    res = SynthResult(variant="core", device="hx8k", package="ct256", target_mhz=100.0,
                      params={"energy_bits": 16}, cells=CellCounts({"SB_LUT4": 5}),
                      runs=(run(1, 103.0), run(2, 99.0), run(3, 107.0)),
                      yosys_seconds=1.0, verilog_seconds=1.0)
    assert res.fmax_median_mhz == 103.0 and res.fits and res.meets_target
    assert res.used("ICESTORM_LC") == 10 and res.available("ICESTORM_LC") == 20
    assert json.loads(json.dumps(res.to_dict()))["runs"][1]["meets_target"] is False
    no = dataclasses.replace(res, runs=(run(1, None, fits=False),))
    assert no.fits is False and no.fmax_median_mhz is None and no.meets_target is None
    assert dataclasses.replace(res, runs=()).fits is None


# ---- tool handling ---------------------------------------------------------------------


def test_missing_yosys_names_the_debian_package():
    with pytest.raises(ToolNotFoundError, match=(
                 r"^'/nonexistent/yosys' not found on PATH: it is needed for iCE40 synthesis; "
                 r"install the Debian package 'yosys' \(apt-get install yosys\)$")):
        synthesize(DPConfig(width=8, height=6), yosys="/nonexistent/yosys", seeds=())


def test_missing_nextpnr_is_reported_before_any_work(tmp_path):
    with pytest.raises(ToolNotFoundError, match=(
                 r"^'/nonexistent/nextpnr-ice40' not found on PATH: it is needed for iCE40 synthesis; "
                 r"install the Debian package 'nextpnr-ice40' \(apt-get install nextpnr-ice40\)$")):
        synthesize(DPConfig(width=8, height=6), yosys=shutil.which("sh"),
                   nextpnr="/nonexistent/nextpnr-ice40", workdir=tmp_path)
    assert list(tmp_path.iterdir()) == []


def test_bad_arguments():
    with pytest.raises(ValueError, match=r"^variant must be one of \('core', 'top'\), got 'board'$"):
        synthesize(DPConfig(), variant="board")
    with pytest.raises(ValueError, match=(
            r"^device must be one of \('lp384', 'lp1k', 'lp4k', 'lp8k', 'hx1k', 'hx4k', "
            r"'hx8k', 'up3k', 'up5k', 'u1k', 'u2k', 'u4k'\), got 'ecp5'$")):
        synthesize(DPConfig(), device="ecp5")
    with pytest.raises(ValueError, match=r"^lut_style must be one of 'auto', 'bram', 'logic', "
                                         r"got 'distributed'$"):
        synthesize(DPConfig(), lut_style="distributed", yosys="/nonexistent/yosys")


# ---- real tools ------------------------------------------------------------------------

#: The smallest useful pipeline: 8x6, 2-bit pixels, 4-bit energy, F = 0 (about 6 s of CPU
#: in Yosys 0.23, ~600 LUTs).
TINY = DPConfig(width=8, height=6, segment_frames=2, input_bits=2, energy_bits=4,
                weight_frac_bits=0)


@needs_yosys
def test_real_yosys_on_a_tiny_pipeline(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = synthesize(TINY, variant="top", seeds=(), workdir=tmp_path)
    c = res.cells
    assert 100 < c.lut4 < 5000 and 100 < c.dff < 5000 and 0 < c.carry < c.lut4
    assert 1 <= c.bram <= 32
    assert res.runs == () and res.fits is None and res.fmax_median_mhz is None
    assert (tmp_path / "netlist.json").exists() and (tmp_path / "yosys.log").exists()
    assert res.tools["yosys"].startswith("Yosys")


@needs_yosys
def test_lut_style_moves_the_weight_lut_out_of_block_ram(tmp_path):
    """``lut_style="logic"``: the M = 9 column memories (10 x 9 bits) leave block RAM.

    F = 8 as in the real configurations (Yosys keeps TINY's 1-bit columns in logic anyway);
    about 30 s of CPU for the two Yosys runs.
    """
    cfg = dataclasses.replace(TINY, weight_frac_bits=8)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        bram = synthesize(cfg, variant="core", seeds=(), workdir=tmp_path / "bram",
                          lut_style="bram")
        auto = synthesize(cfg, variant="core", seeds=(), workdir=tmp_path / "auto")
    assert bram.params["lut_style"] == "bram" and auto.params["lut_style"] == "logic"
    assert bram.cells.bram - auto.cells.bram == cfg.n_moves
    assert auto.cells.dff > bram.cells.dff
    manifest = json.loads((tmp_path / "auto" / "dptbd_dp.json").read_text())
    assert manifest["lut_style"] == "logic"


@pytest.mark.slow
@needs_yosys
@needs_nextpnr
def test_real_place_and_route_of_a_tiny_pipeline(tmp_path, request):
    # pyproject's addopts deselect ``slow``; should they not, skip unless -m was given.
    if not request.config.getoption("markexpr", ""):
        pytest.skip("nextpnr place and route (~40 s): run with -m slow")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = synthesize(TINY, variant="core", seeds=(1,), workdir=tmp_path)
    assert res.fits is True
    assert 20 < res.fmax_median_mhz < 500
    assert 0 < res.used("ICESTORM_LC") <= res.available("ICESTORM_LC") == 7680
