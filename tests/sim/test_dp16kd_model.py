"""The behavioural DP16KD's substitution (:func:`dptbd.sim.dp16kd_model.modelled_dp16kd`);
the model's behaviour is tested in ``test_cell_models.py``."""

from amaranth.hdl import Instance, Module, Signal

from dptbd.hw.dp16kd import dp16kd_memory
from dptbd.sim.dp16kd_model import DP16KDModel, modelled_dp16kd


def _cells(m):
    addr, data = Signal(4), Signal(20)
    dp16kd_memory(m, "ram", width=20, depth=16, read_addr=addr, read_en=1, out_en=1,
                  write_addr=addr, write_data=data, write_en=1)
    return [m._named_submodules[f"ram_{i}"][0] for i in range(2)]


def test_modelled_dp16kd_builds_models_inside_and_instances_after():
    with modelled_dp16kd():
        inside = _cells(Module())
    after = _cells(Module())
    assert all(isinstance(cell, DP16KDModel) for cell in inside)
    assert all(isinstance(cell, Instance) and cell.type == "DP16KD" for cell in after)
