"""The verification campaign's cases (:mod:`dptbd.sim.campaign`): :class:`Case` (a parameter
set, a top level, its runs and faults), the default campaign's cases (:func:`default_cases`,
the AXI top level's :func:`axi_cases`) and the 4-state store checks' (:func:`x_store_cases`)."""

from __future__ import annotations

import dataclasses

from dptbd.config import DPConfig, EnergyWidthWarning

__all__ = ["FAULTS", "Case", "default_cases", "wide_cases", "axi_cases", "store_cases",
           "family_cases", "x_store_cases"]

#: Fault classes a case may draw from (see :func:`dptbd.sim.campaign.draw.make_run`).
FAULTS = ("reset", "misaligned_first", "short_frame", "long_frame", "lut", "store_garbage",
          "settings")

@dataclasses.dataclass(frozen=True)
class Case:
    """A parameter set, a top level and what its runs may contain.

    Attributes
    ----------
    name : str
    config : dict
        :class:`~dptbd.config.DPConfig` fields (JSON-able, so a case pickles cheaply).
    design : str
        ``"dp"``, ``"core"``, ``"segmenter"`` or ``"axi"`` (:data:`dptbd.sim.verilator.DESIGNS`;
        an ``"axi"`` case draws its runs with :mod:`dptbd.sim.axi.runs`, its own faults), or
        ``"dp_axi"`` (``dptbd_dp --state-store axi``, runs of :mod:`dptbd.sim.campaign.store`)
        or ``"axi_store"`` (``dptbd_axi --state-store axi``: an ``"axi"`` case's runs with
        resets on the store build, :func:`dptbd.sim.campaign.store.axi_store.check_axi_store_run`).
    frames : int
        Frames per run (before faults cut or lengthen them).
    runs : int
        Seeded runs in a full campaign.
    faults : tuple of str
        Fault classes (:data:`FAULTS`) each run may draw.
    random_lut : bool
        The run starts by writing a random LUT (codes in [0, 2**F]).
    store : dict or None
        ``design="dp_axi"`` or ``"axi_store"`` (:mod:`dptbd.sim.campaign.store`):
        the :class:`~dptbd.config.AxiStoreConfig` fields (:meth:`DPConfig.axi_store`).
    family : str or None
        The FPGA family whose implementation options the build has (``dptbd verilog
        --family``; ``build(..., family=…)`` of :mod:`dptbd.sim.verilator`), ``None`` for
        DPCore's defaults. Designs ``"dp"``, ``"core"``, ``"segmenter"``, ``"axi"``,
        ``"dp_axi"`` (not its error case, which runs in the Amaranth simulator) and
        ``"axi_store"``.
    """

    name: str
    config: dict
    design: str
    frames: int
    runs: int
    faults: tuple[str, ...] = ()
    random_lut: bool = False
    store: dict | None = None
    family: str | None = None

    @property
    def cfg(self) -> DPConfig:
        import warnings
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", EnergyWidthWarning)
            return DPConfig(**self.config)

    @property
    def words_per_run(self) -> int:
        return self.frames * self.config["width"] * self.config["height"]


def default_cases() -> list[Case]:
    """The campaign's parameter sets (``docs/gateware.md``, "Verification campaign")."""
    every = ("reset", "misaligned_first", "short_frame", "long_frame", "lut", "settings")
    p001 = dict(width=128, height=128, segment_frames=8, input_bits=12, energy_bits=16,
                weight_frac_bits=8)
    cases = [
        Case("001-128x128-k8-in12-e16", p001, "dp", 48, 32, every),
        Case("37x23-k3-in8-e12-f4", dict(width=37, height=23, segment_frames=3, input_bits=8,
                                        energy_bits=12, weight_frac_bits=4), "dp", 400, 20,
             every),
        Case("narrow-24x16-in8-e9-sat", dict(width=24, height=16, segment_frames=6,
                                            input_bits=8, energy_bits=9), "dp", 600, 16, every),
        Case("f0-64x48-k4", dict(width=64, height=48, segment_frames=4, weight_frac_bits=0),
             "dp", 300, 16, every),
        Case("f8-half-up-64x48-k5", dict(width=64, height=48, segment_frames=5,
                                         weight_frac_bits=8, rounding="half_up"),
             "dp", 300, 16, every),
        Case("r2-40x30-f6-k4", dict(width=40, height=30, segment_frames=4, radius=2,
                                    weight_frac_bits=6), "dp", 600, 16, every),
        Case("random-lut-48x32-f5", dict(width=48, height=32, segment_frames=4,
                                         weight_frac_bits=5), "dp", 500, 16, every, True),
        Case("core-96x64-garbage-store", dict(width=96, height=64, segment_frames=4),
             "core", 200, 16, every + ("store_garbage",)),
        Case("segmenter-128x128-k4", dict(width=128, height=128, segment_frames=4,
                                          input_bits=12, energy_bits=16), "segmenter", 48, 8,
             every),
        Case("segmenter-33x17-k2-n3", dict(width=33, height=17, segment_frames=2,
                                           candidate_count=3, histogram_bits=6),
             "segmenter", 400, 8, every),
        *wide_cases(every),
        *axi_cases(),
        *store_cases(),
    ]
    return cases + family_cases(cases, "ecp5", FAMILY_CASES)


#: The cases run again on the ECP5 family's build (``dptbd verilog --family ecp5``: the
#: registered control, the output queue one-hot, the state store and the histogram in
#: DP16KDs, which Verilator simulates with :mod:`dptbd.sim.cell_models`' model; with the
#: state in external memory, the store's prefetch FIFO in DP16KDs and its staged
#: write-behind), one per top level, P = 2's AXI top and both tops with the AXI4 store.
FAMILY_CASES = ("37x23-k3-in8-e12-f4", "core-96x64-garbage-store", "segmenter-33x17-k2-n3",
                "axi-24x16-f0-k2", "axi-p2-48x16-f0-k2", "dp-axi-64x48-k4-d32-b8-o4",
                "axi-store-24x16-f0-k2")


def family_cases(cases: list[Case], family: str, names: tuple[str, ...]) -> list[Case]:
    """The cases of ``names`` (among ``cases``) on ``family``'s build, named
    ``<name>-<family>``, with half their runs (at least one)."""
    by_name = {case.name: case for case in cases}
    return [dataclasses.replace(by_name[name], name=f"{name}-{family}", family=family,
                                runs=max(1, by_name[name].runs // 2)) for name in names]


def wide_cases(faults: tuple[str, ...]) -> list[Case]:
    """``dptbd_seg`` and ``dptbd_axi`` at P = 2 and 4 pixels per clock (``docs/gateware.md``,
    "P pixels per clock"). ``dptbd_seg``: ``faults`` (those of P = 1) at beat boundaries
    (``make_stream_run``), n small against the frame so lists overflow, and (K - 1)
    frames of beats shorter than the scan at P = 4 so the scan stalls the input.
    ``dptbd_axi``: the AXI cases' faults, drawn in beats (:func:`dptbd.sim.axi.runs.draw_run`),
    a binary-LUT case at P = 2 and an r = 2 fractional one at P = 4."""
    from dptbd.sim.axi.runs import AXI_FAULTS

    return [
        Case("axi-p2-48x16-f0-k2", dict(width=48, height=16, segment_frames=2,
                                        max_segment_frames=4, weight_frac_bits=0,
                                        energy_bits=9, candidate_count=3, candidate_capacity=6,
                                        histogram_bits=6, histogram_shift=2,
                                        pixels_per_clock=2), "axi", 80, 8, AXI_FAULTS),
        Case("axi-p4-48x23-r2-f4-k3", dict(width=48, height=23, segment_frames=3,
                                           max_segment_frames=5, radius=2, weight_frac_bits=4,
                                           candidate_count=4, candidate_capacity=8,
                                           histogram_bits=6, pixels_per_clock=4),
             "axi", 60, 8, AXI_FAULTS),
        Case("segmenter-p2-64x24-k3-e9-sat", dict(width=64, height=24, segment_frames=3,
                                                  energy_bits=9, candidate_count=6,
                                                  histogram_bits=6, pixels_per_clock=2),
             "segmenter", 120, 8, faults),
        Case("segmenter-p4-48x17-k2-n3", dict(width=48, height=17, segment_frames=2,
                                              candidate_count=3, histogram_bits=8,
                                              pixels_per_clock=4), "segmenter", 200, 8, faults),
    ]


def store_cases() -> list[Case]:
    """The ``"dp_axi"`` cases (:func:`dptbd.sim.campaign.store.cases.store_cases`) and the
    ``"axi_store"`` ones (:func:`dptbd.sim.campaign.store.cases.axi_store_cases`)."""
    from dptbd.sim.campaign.store.cases import axi_store_cases, store_cases as cases
    return cases() + axi_store_cases()


def axi_cases() -> list[Case]:
    """The AXI top level's cases (:mod:`dptbd.sim.axi.runs`): 001's setting, a small r = 2
    one with a fractional LUT, a small binary-LUT one with B_E = 9 (bright frames saturate);
    K_max above K and small C, so that run-time K, lists at capacity and overflowing lists
    occur."""
    from dptbd.sim.axi.runs import AXI_FAULTS

    p001 = dict(width=128, height=128, segment_frames=8, input_bits=12, energy_bits=16,
                weight_frac_bits=8)
    return [
        Case("axi-001-128x128-k8", p001, "axi", 16, 4, AXI_FAULTS),
        Case("axi-37x23-r2-f4-k3", dict(width=37, height=23, segment_frames=3,
                                        max_segment_frames=5, radius=2, weight_frac_bits=4,
                                        candidate_count=4, candidate_capacity=8,
                                        histogram_bits=6), "axi", 80, 8, AXI_FAULTS),
        Case("axi-24x16-f0-k2", dict(width=24, height=16, segment_frames=2,
                                     max_segment_frames=4, weight_frac_bits=0,
                                     energy_bits=9, candidate_count=3, candidate_capacity=6,
                                     histogram_bits=6, histogram_shift=2),
             "axi", 160, 8, AXI_FAULTS),
    ]


def x_store_cases() -> list[tuple[str, dict, str]]:
    """(name, config, store init) of the Icarus X-freedom checks of DPCore's external store."""
    small = dict(width=16, height=12, segment_frames=3)
    r2 = dict(width=14, height=11, segment_frames=2, radius=2, weight_frac_bits=6)
    return [("x-store-16x12", small, "x"), ("garbage-store-16x12", small, "random"),
            ("x-store-r2-14x11", r2, "x"), ("garbage-store-r2-14x11", r2, "random")]
