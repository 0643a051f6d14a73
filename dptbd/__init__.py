"""dptbd: fixed-point model, gateware and verification harness for DP track-before-detect.

Sub-packages: ``dptbd.scenes`` (synthetic, range-Doppler and recorded scenes),
``dptbd.model`` (numpy golden model and float reference), ``dptbd.hw`` (Amaranth gateware),
``dptbd.sim`` (RTL simulation and testbenches), ``dptbd.dsp`` (track association, the
FPGA -> DSP chain, track metrics). ``dptbd.config.DPConfig`` is shared by all of them.
"""

from dptbd.config import ConfigError, DPConfig, EnergyWidthWarning

__all__ = ["DPConfig", "ConfigError", "EnergyWidthWarning"]
__version__ = "0.1.0"
