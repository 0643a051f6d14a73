"""The penalty LUT: (M+1) x M unsigned B_Q-bit penalty codes Qc, M lookups per clock.

``docs/arithmetic.md`` §8.2 (operator ``lookup_penalty_code``): paper 000's additive
transition term Q = -Qc, indexed exactly like the weight LUT (predecessor direction p = 0 …
M, row M = ``START``, a direction above M reads row M; move m; write address ``p * M + m``,
:meth:`~dptbd.config.DPConfig.lut_address`). It is the weight LUT's storage
(:class:`~dptbd.hw.weight_lut.DirectionTable`) with the penalty codes: the same column
memories, the same ``lut_style``, the same write protocol (a write presented in cycle c
applies to every pixel accepted in cycle c or later), and lookups issued in the same cycle
as the weights', so the penalty code of a move comes out beside its weight code. Every
B_Q-bit code is a valid penalty, so writes are stored as written.
"""

from __future__ import annotations

from dptbd.config import DPConfig
from dptbd.hw.weight_lut import DirectionTable

__all__ = ["PenaltyLUT"]


class PenaltyLUT(DirectionTable):
    """M column memories of penalty codes with a single table-wide write port.

    Parameters
    ----------
    cfg : DPConfig
        M, B_d, B_Q (``penalty_width``) and the initial codes (``penalty_code_array``).
    lut_style : {"auto", "bram", "logic"}
        Storage, as for the weight LUT (:func:`~dptbd.hw.weight_lut.resolve_lut_style`).

    Members
    -------
    direction : In(B_d).array(M)
        Cycle t: the predecessor direction of each move (above M: the ``START`` row).
    code : Out(B_Q).array(M)
        Cycle t+1: ``Qc[min(direction[m], M), m]``.
    write_addr : In(range((M+1)*M))
        Entry ``p * M + m``; addresses >= (M+1)*M are ignored.
    write_data : In(B_Q)
        The new penalty code.
    write_en : In(1)
        Write in this cycle.
    """

    def __init__(self, cfg: DPConfig, *, lut_style: str = "auto"):
        super().__init__(cfg, cfg.penalty_code_array, cfg.penalty_width, None,
                         lut_style=lut_style)
