"""dptbd: fixed-point model, gateware and verification harness for DP track-before-detect.

Sub-packages: ``dptbd.model`` (numpy scenes and models), ``dptbd.hw`` (Amaranth gateware),
``dptbd.sim`` (cocotb testbenches). ``dptbd.config.DPConfig`` is shared by all of them.
"""

from dptbd.config import ConfigError, DPConfig, EnergyWidthWarning

__all__ = ["DPConfig", "ConfigError", "EnergyWidthWarning"]
__version__ = "0.1.0"
