"""The behavioural DP16KD of the tests: :mod:`dptbd.sim.dp16kd_model` (the formal
harnesses use it too), and a fixture helper that builds every DP16KD as it."""

from dptbd.sim.dp16kd_model import DP16KDModel

__all__ = ["DP16KDModel", "model_dp16kd_cells"]


def model_dp16kd_cells(monkeypatch):
    """Build every ``Instance("DP16KD", …)`` of :mod:`dptbd.hw.dp16kd` as a
    :class:`DP16KDModel` (for whole cores whose DP16KD styles take no cell argument)."""
    import dptbd.hw.dp16kd as dp16kd

    def instance(kind, **ports):
        assert kind == "DP16KD"
        return DP16KDModel(**ports)

    monkeypatch.setattr(dp16kd, "Instance", instance)
