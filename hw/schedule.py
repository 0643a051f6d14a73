"""The cycle schedule of the DP pipeline, and which configurations the gateware accepts.

Everything downstream of the input handshake advances every clock cycle, so the cycle on
which each stage holds a pixel's data is a fixed offset from the cycle on which that pixel
was accepted. :class:`PipelineSchedule` computes those offsets from a
:class:`~dptbd.config.DPConfig`; the gateware is built from them, and the documentation
(``docs/gateware.md``), the Verilog manifest and the tests quote them.

Cycle 0 is the cycle in which a pixel is accepted (``pixels.valid`` and ``pixels.ready``
both high at the rising edge that ends it). "Stage at cycle n" means: the registers holding
that pixel's data at this stage are visible during cycle n.
"""

from __future__ import annotations

import dataclasses

from amaranth.utils import ceil_log2

from dptbd.config import DPConfig
from dptbd.errors import ConfigError
from dptbd.hw.family_blocks import FamilyBlocks, forgetting_leaves

__all__ = ["MAX_TREE_STAGES", "PipelineSchedule", "read_ahead_distance", "check_supported",
           "MERIT_LUT_MAX_INPUT_BITS"]

#: The largest B_in for which the gateware builds a merit LUT (2**12 entries of at most
#: B_E + 1 bits: 135 kbit at B_E = 32, within an ECP5-25k's 1008 kbit of block RAM).
MERIT_LUT_MAX_INPUT_BITS = 12

#: ``DPCore(max_tree=…)``: register stages per tree level (MaxTree 1, SplitMaxTree 2).
MAX_TREE_STAGES = {"compact": 1, "split": 2}


@dataclasses.dataclass(frozen=True)
class PipelineSchedule:
    """Cycle offsets of the pipeline stages, relative to the accepting cycle 0.

    Attributes
    ----------
    fetch : int
        Previous state (from the state store and the line buffers) and the pixel's position
        are available: 1.
    window : int
        The (2r+1) x (2r+1) window and its edge flags are registered: 2.
    code : int
        The M weight codes are out of the LUT: 3.
    multiplier_levels : int
        Register levels of each weight multiplier's adder tree:
        ``ceil(log2(F + 2))`` for F >= 1 (F + 1 partial products plus the rounding
        constant), 1 for F = 0.
    weighted : int
        The M weighted candidates C are registered: ``code + multiplier_levels``.
    penalty_levels : int
        Register levels of the penalty subtractors (``docs/arithmetic.md`` §8.3): 1 when
        the penalty LUT is built (:class:`~dptbd.hw.family_blocks.FamilyBlocks`), else 0.
    penalised : int
        The M candidates V = C - Qc enter the max tree: ``weighted + penalty_levels``.
    tree_levels : int
        Register stages of the max/argmax tree: ``ceil(log2(M))``, twice that with
        ``max_tree="split"`` (:class:`~dptbd.hw.pipelined_max.SplitMaxTree`).
    best : int
        The best candidate and its move index are registered: ``penalised + tree_levels``.
    forgetting_levels : int
        Register levels of the forgetting multiplier (§8.4) when it is built:
        ``max(1, ceil(log2(n)))``, n = the set bits of the code a plus 1 for ``half_up``
        rounding (G >= 1); else 0.
    faded : int
        A = round_G(V_best * a) (or V_best) enters the accumulator: ``best + forgetting_levels``.
    state : int
        The new (E, d) is registered and presented to the state store's write port and to
        the output FIFO: ``faded + 1``. This is also the *write latency*.
    fifo : int
        Cycles through the output FIFO (:class:`~dptbd.hw.thermometer_fifo.ThermometerFIFO`,
        cycle for cycle ``SyncFIFOBuffered``): 2.
    latency : int
        Cycles from accepting a pixel to its result being valid on ``states`` when the
        output is not back-pressured: ``state + fifo`` = ``6 + ceil(log2(F + 2)) +
        ceil(log2(M)) + penalty_levels + forgetting_levels`` for F >= 1 (``7 + …`` for
        F = 0).
    """

    fetch: int
    window: int
    code: int
    multiplier_levels: int
    weighted: int
    tree_levels: int
    best: int
    state: int
    fifo: int
    latency: int
    # paper 000's family (docs/arithmetic.md §8); equal to weighted / best when not built
    penalty_levels: int = 0
    penalised: int = 0
    forgetting_levels: int = 0
    faded: int = 0

    @classmethod
    def from_config(cls, cfg: DPConfig, *, max_tree: str = "compact") -> "PipelineSchedule":
        """The schedule of the pipeline built for ``cfg`` (and ``DPCore(max_tree=…)``:
        ``"compact"``, one register stage per tree level, or ``"split"``, two)."""
        if max_tree not in MAX_TREE_STAGES:
            raise ValueError(f"max_tree must be one of {tuple(MAX_TREE_STAGES)}, "
                             f"got {max_tree!r}")
        frac = cfg.weight_frac_bits
        rows = frac + 1 + (1 if frac >= 1 else 0)  # partial products + rounding constant
        multiplier_levels = max(1, ceil_log2(rows))
        # = max_tree.tree_levels(M) stages per level (SplitMaxTree: 2)
        tree_levels = MAX_TREE_STAGES[max_tree] * ceil_log2(cfg.n_moves)
        fetch, window, code = 1, 2, 3
        weighted = code + multiplier_levels
        # ---- paper 000's family (docs/arithmetic.md §8): stages exist only when built ----
        blocks = FamilyBlocks.from_config(cfg)
        penalty_levels = 1 if blocks.penalty_lut else 0
        penalised = weighted + penalty_levels
        best = penalised + tree_levels
        forgetting_levels = (max(1, ceil_log2(len(forgetting_leaves(cfg))))
                             if blocks.forgetting else 0)
        faded = best + forgetting_levels
        # ---- end of paper 000's family --------------------------------------------------
        state = faded + 1
        fifo = 2
        return cls(fetch=fetch, window=window, code=code, multiplier_levels=multiplier_levels,
                   weighted=weighted, tree_levels=tree_levels, best=best, state=state,
                   fifo=fifo, latency=state + fifo, penalty_levels=penalty_levels,
                   penalised=penalised, forgetting_levels=forgetting_levels, faded=faded)

    @property
    def write_latency(self) -> int:
        """Cycles from accepting a pixel to the cycle its new state is written: ``state``."""
        return self.state


def read_ahead_distance(cfg: DPConfig) -> int:
    """How far ahead of the accepted pixel the state store is read: ``r * (W + 1)``."""
    return cfg.radius * (cfg.width + 1)


def check_supported(cfg: DPConfig, *, max_tree: str = "compact") -> PipelineSchedule:
    """Refuse configurations the gateware does not implement; return the schedule otherwise
    (for ``DPCore(max_tree=…)``, see :meth:`PipelineSchedule.from_config`).

    Raises
    ------
    dptbd.errors.ConfigError
        * ``segment_stride != segment_frames``: overlapping segments need one state store
          per live segment; the gateware has one.
        * ``W * H - r * (W + 1) <= write_latency``: the frame is too small for the
          read-ahead. The state of position q is read for the next frame
          ``W*H - r*(W+1)`` accepted pixels after q itself was accepted, and must have been
          written by then (``docs/gateware.md``, "Read-ahead").
        * a merit LUT (``docs/arithmetic.md`` §8.1) with ``input_bits`` above
          :data:`MERIT_LUT_MAX_INPUT_BITS`: its ``2**input_bits`` entries would not fit
          the target FPGAs' block RAM. Every other §8 configuration is built
          (:class:`~dptbd.hw.family_blocks.FamilyBlocks`).
        * ``pixels_per_clock`` above 1: the blocks that call this take one pixel per clock;
          :mod:`dptbd.hw.wide` builds P = 2 and 4 (it checks its beat configuration,
          P = 1, here).
    """
    if cfg.pixels_per_clock > 1:
        raise ConfigError(
            f"pixels_per_clock={cfg.pixels_per_clock}: this block takes one pixel per clock; "
            f"P = 2 and 4 are built by DPCoreWide and DPPipelineWide (hw/wide/, the dp "
            f"top of dptbd verilog)")
    # ---- paper 000's family (docs/arithmetic.md §8) ------------------------------------
    if FamilyBlocks.from_config(cfg).merit_lut and cfg.input_bits > MERIT_LUT_MAX_INPUT_BITS:
        raise ConfigError(
            f"input_bits must be an integer in [1, {MERIT_LUT_MAX_INPUT_BITS}] for the "
            f"gateware's merit LUT (merit_codes other than the identity: a "
            f"2**input_bits-entry table in block RAM), got {cfg.input_bits}")
    # ---- end of paper 000's family -----------------------------------------------------
    if cfg.segment_stride != cfg.segment_frames:
        raise ConfigError(
            f"segment_stride={cfg.segment_stride} is not supported by the gateware: only "
            f"non-overlapping segments (segment_stride == segment_frames == "
            f"{cfg.segment_frames}) are implemented, with a single state store")
    schedule = PipelineSchedule.from_config(cfg, max_tree=max_tree)
    pixels = cfg.width * cfg.height
    ahead = read_ahead_distance(cfg)
    if pixels - ahead <= schedule.write_latency:
        raise ConfigError(
            f"width={cfg.width} x height={cfg.height} is too small for the read-ahead of "
            f"radius={cfg.radius}: the gateware needs width*height - radius*(width+1) > write "
            f"latency {schedule.write_latency} cycles, but it is {pixels - ahead}; each state "
            f"must be written before the next frame reads it; use a larger frame")
    return schedule
