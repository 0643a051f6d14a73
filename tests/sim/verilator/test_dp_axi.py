"""dptbd.sim.verilator.dp_axi: the --state-store axi build on Verilator with the C++ AXI4
memory model, bit-exact with the golden model under random latency and stalls; SLVERR and
DECERR responses each pulse the design's error output once per error beat / response."""

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.sim.verilator import dp_axi as V
from helpers.refusals import whole
from helpers.verilator_harness import needs_verilator

CFG = DPConfig(width=16, height=12, segment_frames=3).build_config()
FRAMES = np.random.default_rng(1).integers(0, 256, size=(6, 12, 16))


@pytest.fixture(scope="module")
def deep():
    """64-bit, bursts of 4, 16 in flight: a prefetch deep enough to run into the
    read-after-write rule."""
    return V.build(CFG.axi_store(data_bits=64, burst_beats=4, outstanding=16))


@needs_verilator
def test_zero_latency_is_one_pixel_per_cycle(deep):
    run = V.run(deep, FRAMES)
    assert run.bit_exact and run.result["violations"] == 0
    assert run.cycles_per_pixel == 1.0
    assert run.result["status"] == "done"


@needs_verilator
@pytest.mark.parametrize("kw", [
    dict(latency=(0, 500), axi_ready=0.6, axi_valid=0.6, valid_gap=0.2, ready_pause=0.2,
         seed=3),
    dict(latency=(0, 0), write_latency=(150, 400), seed=4),   # slow writes, immediate reads
    dict(latency=(500, 600), axi_ready=0.9, seed=5),
])
def test_random_latency_and_stalls_change_no_bit(deep, kw):
    run = V.run(deep, FRAMES, **kw)
    assert run.result["violations"] == 0, run.result["first_violation"]
    assert run.bit_exact, f"first mismatch at output {run.first_mismatch}"
    assert run.result["read_errors"] == run.result["write_errors"] == 0


@needs_verilator
def test_a_32_bit_port_with_short_bursts():
    sim = V.build(CFG.axi_store(data_bits=32, burst_beats=2, outstanding=2))
    run = V.run(sim, FRAMES, latency=(0, 100), axi_ready=0.5, axi_valid=0.5, seed=6)
    assert run.bit_exact and run.result["violations"] == 0


@needs_verilator
def test_a_128_bit_port():
    sim = V.build(CFG.axi_store(data_bits=128, burst_beats=2, outstanding=2))
    run = V.run(sim, FRAMES, latency=(0, 100), axi_ready=0.5, axi_valid=0.5, seed=7)
    assert run.bit_exact and run.result["violations"] == 0


# ---- P = 2 and 4 pixels per clock: store words of P states over the same port ----------
@pytest.fixture(scope="module", params=[2, pytest.param(4, marks=pytest.mark.slow)])
def wide(request):
    """P = 2 / 4 at 16 x 12, bursts of 4, 16 in flight. P = 2: the build's 14-bit states
    (31-bit output beats) on a 64-bit port; P = 4 (``-m slow``; the default suite's P = 4
    store runs: ``dptbd_dp`` on ``AxiRam``, ``tests/sim/benches/test_dp_axi.py``, and
    ``dptbd_axi`` on Verilator, ``test_axi_store.py``): 20-bit states, so 83-bit output
    beats (two uint64 words each in the harness's files) and 32-bit slots on a 128-bit
    port."""
    p = request.param
    if p == 2:
        cfg = DPConfig(width=16, height=12, segment_frames=3, pixels_per_clock=2).build_config()
        return V.build(cfg.axi_store(data_bits=64, burst_beats=4, outstanding=16))
    cfg = DPConfig(width=16, height=12, segment_frames=3, pixels_per_clock=4)
    return V.build(cfg.axi_store(data_bits=128, burst_beats=4, outstanding=16))


@needs_verilator
def test_p_pixels_at_zero_latency_take_one_beat_per_cycle(wide):
    run = V.run(wide, FRAMES)
    assert run.bit_exact and run.result["violations"] == 0
    assert run.result["status"] == "done"
    p = wide.store.frame.pixels_per_clock
    assert run.cycles_per_pixel == 1 / p                     # one beat of P pixels per cycle
    assert len(run.accept_cycles) == FRAMES.size // p
    widths = {port["name"]: port["width"] for port in wide.manifest["ports"]}
    assert widths["states__payload"] == {2: 2 * 14 + 3, 4: 4 * 20 + 3}[p]


@needs_verilator
@pytest.mark.parametrize("kw", [
    dict(latency=(0, 500), axi_ready=0.6, axi_valid=0.6, valid_gap=0.2, ready_pause=0.2,
         seed=3),
    dict(latency=(0, 0), write_latency=(150, 400), seed=4),   # slow writes, immediate reads
    dict(latency=(300, 500), axi_ready=0.8, axi_valid=0.7, valid_gap=0.1, seed=5),
])
def test_p_pixels_random_latency_and_stalls_change_no_bit(wide, kw):
    run = V.run(wide, FRAMES, **kw)
    assert run.result["violations"] == 0, run.result["first_violation"]
    assert run.bit_exact, f"first mismatch at output {run.first_mismatch}"
    assert run.result["read_errors"] == run.result["write_errors"] == 0


@needs_verilator
@pytest.mark.slow
def test_p4_beats_wider_than_64_bits():
    """P = 4 with 20-bit states: 83-bit output beats (two uint64 words each in the
    harness's files), 32-bit slots, two 128-bit beats per burst: a build of its own, so
    ``-m slow`` (the default suite's P = 4 build, ``wide``, has the same beats and slots with
    bursts of four beats, 16 in flight)."""
    cfg = DPConfig(width=16, height=12, segment_frames=3, pixels_per_clock=4)
    sim = V.build(cfg.axi_store(data_bits=128, burst_beats=2, outstanding=4))
    widths = {port["name"]: port["width"] for port in sim.manifest["ports"]}
    assert widths["states__payload"] == 4 * 20 + 3
    run = V.run(sim, FRAMES, latency=(0, 100), axi_ready=0.5, axi_valid=0.5, seed=7)
    assert run.bit_exact and run.result["violations"] == 0


@needs_verilator
@pytest.mark.parametrize("code", ["SLVERR", "DECERR"])
@pytest.mark.parametrize("kind", ["read", "write"])
def test_slverr_and_decerr_pulse_the_error_output_once_per_beat_or_response(deep, kind,
                                                                           code):
    """Every burst of one direction whose address is taken in cycles [300, 400) answered
    with the code: the design pulses read_error once per error beat, write_error once per
    error response (docs/gateware.md, "Errors"), the other never, every pixel still comes
    out and the frames before the window are the model's."""
    run = V.run(deep, FRAMES, latency=(0, 40), seed=8, error_cycles=(300, 400),
                error_response=code, **{f"{kind}_error": 1.0})
    r = run.result
    assert r["status"] == "done" and r["violations"] == 0, r["first_violation"]
    assert len(run.outputs) == FRAMES.size
    sent = {"read": r["read_error_beats"], "write": r["write_error_bursts"]}
    other = {"read": "write", "write": "read"}[kind]
    assert sent[kind] > 0 and sent[other] == 0
    assert (r["read_errors"], r["write_errors"]) == (sent["read"], sent["write"])
    decerrs = {"read": r["read_decerrs"], "write": r["write_decerrs"]}
    assert decerrs[kind] == (sent[kind] if code == "DECERR" else 0)
    assert run.first_mismatch is None or run.first_mismatch >= int(
        np.searchsorted(run.accept_cycles, 300)) - 16 * 12


@needs_verilator
def test_an_unknown_error_response_is_refused(deep):
    with pytest.raises(ValueError, match=whole(
            "error_response 'OKAY': the responses are SLVERR, DECERR")):
        V.run(deep, FRAMES, error_response="OKAY")


def test_a_build_refuses_an_unknown_family(tmp_path):
    with pytest.raises(ValueError, match=whole("family must be one of ('ice40', 'ecp5'), "
                                               "got 'xilinx'")):
        V.build(CFG.axi_store(), root=tmp_path / "builds", family="xilinx")
    assert not (tmp_path / "builds").exists()


@needs_verilator
def test_the_ecp5_build_is_bit_exact_with_its_dp16kds_on_the_model(tmp_path):
    """``family="ecp5"``: the store's prefetch FIFO in DP16KDs (verilated from the model) and
    its staged write-behind, under memory latency and stalls."""
    sim = V.build(CFG.axi_store(), family="ecp5")
    assert sim.directory.name.startswith("dp-axi-store-ecp5-")
    assert "\n  DP16KD #(" in (sim.directory / "dptbd_dp.v").read_text()
    frames = np.random.default_rng(3).integers(0, 256, size=(7, CFG.height, CFG.width))
    run = V.run(sim, frames, latency=(0, 40), axi_ready=0.7, axi_valid=0.8, valid_gap=0.2,
                ready_pause=0.3, seed=5, job_dir=tmp_path)
    assert run.result["violations"] == 0, run.result["first_violation"]
    assert run.bit_exact, f"first mismatch at output {run.first_mismatch}"
    assert run.result["status"] == "done"
