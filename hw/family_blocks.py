"""Which of paper 000's family blocks (``docs/arithmetic.md`` §8) the gateware builds.

Every §8 block is built only when the configuration uses it
(:attr:`~dptbd.config.DPConfig.family_fields_in_use`), so a paper-001 configuration builds
exactly the §4–§5 pipeline: same ports, same latency, same cells.
"""

from __future__ import annotations

import dataclasses

from dptbd.config import DPConfig

__all__ = ["FamilyBlocks", "forgetting_leaves"]


def forgetting_leaves(cfg: DPConfig) -> list[int]:
    """The shift-and-add leaves of the forgetting multiplier (§8.4): one shift ``k`` per set
    bit of the constant code ``a`` (``V << k``), plus ``-1`` for the ``half_up`` rounding
    constant ``2**(G-1)`` when G >= 1."""
    code = cfg.forgetting_code
    leaves = [k for k in range(cfg.forgetting_bits + 1) if (code >> k) & 1]
    if cfg.rounding == "half_up" and cfg.forgetting_bits >= 1:
        leaves.append(-1)
    return leaves


@dataclasses.dataclass(frozen=True)
class FamilyBlocks:
    """The §8 blocks built for one configuration.

    Attributes
    ----------
    merit_lut : bool
        ``merit_codes`` in use (not the identity): the merit LUT on the input pixel (§8.1)
        and its write port ``merit_addr`` / ``merit_data`` / ``merit_we``. Without it the
        merit is the pixel itself.
    penalty_lut : bool
        ``penalty_codes`` in use (not all 0): the penalty LUT, one penalty subtractor per
        move (§8.2–§8.3), the write port ``penalty_addr`` / ``penalty_data`` /
        ``penalty_we`` and a *signed* max tree. Without it every candidate is >= 0.
    forgetting : bool
        The forgetting code a is below ``2**G`` (§8.4): the forgetting multiplier after
        the max tree.
    clamped_accumulator : bool
        Any §8 field in use: the accumulator forms ``A + P`` signed and clamps it to
        ``[0, E_max]`` (§8.5) instead of §4.5's ``min(E_best + x, E_max)``.
    recursive : bool
        Only the first frame after reset (or a resynchronisation) is a start frame (§8.6).
    """

    merit_lut: bool
    penalty_lut: bool
    forgetting: bool
    clamped_accumulator: bool
    recursive: bool

    @classmethod
    def from_config(cls, cfg: DPConfig) -> "FamilyBlocks":
        """The blocks ``cfg`` needs."""
        used = cfg.family_fields_in_use
        return cls(merit_lut="merit_codes" in used, penalty_lut="penalty_codes" in used,
                   forgetting="forgetting" in used, clamped_accumulator=bool(used),
                   recursive="recursive" in used)

    @property
    def signed_candidates(self) -> bool:
        """Candidates are signed ``B_E + 1``-bit values (a penalty can make them negative)."""
        return self.penalty_lut
