"""dptbd: fixed-point model, gateware and verification harness for DP track-before-detect.

Sub-packages: ``dptbd.scenes`` (synthetic, range-Doppler and recorded scenes),
``dptbd.model`` (numpy golden model and float reference), ``dptbd.hw`` (Amaranth gateware),
``dptbd.sim`` (RTL simulation and testbenches), ``dptbd.dsp`` (track association, the
FPGA -> DSP chain, track metrics), ``dptbd.evaluation`` (the jobs: the run job, Table 1,
fixed vs float, the other papers' detectors), ``dptbd.commands`` (the thin CLI).
``dptbd.config.DPConfig`` is shared by all of them; ``dptbd.errors`` holds the one error
family and its parameter checks.
"""

from dptbd.config import DPConfig, EnergyWidthWarning
from dptbd.errors import ConfigError, DptbdError

__all__ = ["DPConfig", "ConfigError", "DptbdError", "EnergyWidthWarning"]
__version__ = "0.1.0"
