"""Fixtures shared by the tests, and the order the suite runs in."""

import shutil

import pytest

# The default suite's heaviest files (Sphinx, YoWASP Yosys and SBY, Verilator and FuseSoC
# builds, long Amaranth simulations), measured with --durations on an empty-cache run. With
# ``--dist loadfile`` (pyproject.toml) each file goes whole to one xdist worker, in collection
# order: these go first, heaviest first, so the run does not end with one worker still in a
# long file while the other is idle. The rest keeps pytest's order.
HEAVY_FIRST = (
    "tests/commands/test_verify.py",
    "tests/docs/test_site.py",
    "tests/hw/axi_store/test_pipeline.py",
    "tests/commands/verilog/test_pixels_per_clock.py",
    "tests/commands/verilog/test_outputs.py",
    "tests/commands/verilog/test_state_store.py",
    "tests/hw/flow/test_axi_package.py",
    "tests/hw/wide/test_init.py",
    "tests/hw/wide/test_options.py",
    "tests/commands/run/test_rtl.py",
    "tests/commands/run/test_outputs.py",
    "tests/hw/flow/test_verilog.py",
    "tests/hw/flow/test_synth.py",
    "tests/commands/test_sim.py",
    "tests/sim/campaign/test_store.py",
    "tests/sim/mutation/slices/axi/test_registers.py",
    "tests/sim/mutation/slices/axi/test_timing.py",
    "tests/sim/mutation/slices/axi/test_init.py",
    "tests/sim/benches/test_dp.py",
    "tests/sim/coverage/test_real_run.py",
    "tests/sim/benches/test_axi.py",
    "tests/sim/campaign/test_campaign.py",
    "tests/hw/axi_store/test_top.py",
    "tests/sim/benches/test_axi_store.py",
)


def pytest_collection_modifyitems(config, items):
    """Runs the files of :data:`HEAVY_FIRST` first, in that order (a stable sort)."""
    rank = {path: i for i, path in enumerate(HEAVY_FIRST)}
    items.sort(key=lambda item: rank.get(item.nodeid.split("::", 1)[0], len(rank)))


@pytest.fixture
def no_verilator(monkeypatch):
    """``shutil.which`` finds no ``verilator``; ``check_tools``' cache cleared around it."""
    from dptbd.sim import verilator

    real = shutil.which
    monkeypatch.setattr(shutil, "which",
                        lambda name, *a, **k: None if name == "verilator" else real(name, *a, **k))
    verilator.check_tools.cache_clear()
    yield
    verilator.check_tools.cache_clear()
