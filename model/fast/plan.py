"""The host side of :mod:`dptbd.model.fast`: the per-configuration constants of its kernels,
in the types the kernels expect, and the choice of kernel (:func:`kernel_path`).
"""

from __future__ import annotations

import dataclasses
import functools

import numpy as np

from dptbd.config import DPConfig

__all__ = ["kernel_path"]


# ==== host side: the per-configuration constants ==========================================

@dataclasses.dataclass(frozen=True)
class _Plan:
    """Constants of one configuration, in the types the kernels expect."""

    radius: int
    n_moves: int
    binary: bool           # every weight code is 0 or 2**F
    key_shift: np.uint32   # s: width of the move-index field of a key
    key_low: np.uint32     # 2**s - 1
    key_limit: int         # the binary kernel needs every E < key_limit (E << s fits 32 bits)
    padded_width: int      # W + 2r: row stride of the binary kernel's zero-margined planes
    tags: tuple            # uint32 2**s - 1 - m per move
    fulls: tuple           # uint32 (~0 << s) | tag_m per move
    bits: tuple            # uint32 column masks: bit p of bits[m] <=> code[p, m] != 0
    offsets_flat: np.ndarray  # general kernel: uint64 flat offset of move m's predecessor,
    #                           -dy * W - dx (mod 2**64)
    dys: np.ndarray        # general kernel: int64 dy per move
    dxs: np.ndarray        # general kernel: int64 dx per move
    tags64: np.ndarray     # general kernel: the tags as uint64
    start_onehot: np.uint32
    lut_t: np.ndarray      # int64 (M, M + 1): the codes transposed, [move, predecessor d]
    frac_bits: int
    half: int              # rounding constant added before >> F
    e_max: np.uint32
    start_code: int


@functools.lru_cache(maxsize=64)
def _plan(cfg: DPConfig) -> _Plan:
    cfg.require_paper001_datapath("dptbd.model.fast")
    n_moves = cfg.n_moves
    codes = cfg.weight_codes.astype(np.int64)
    frac = cfg.weight_frac_bits
    s = (n_moves - 1).bit_length()
    moves = cfg.moves
    tags = [(1 << s) - 1 - m for m in range(n_moves)]
    return _Plan(
        radius=cfg.radius, n_moves=n_moves,
        binary=bool(np.all((codes == 0) | (codes == 1 << frac))),
        key_shift=np.uint32(s), key_low=np.uint32((1 << s) - 1), key_limit=1 << (32 - s),
        padded_width=cfg.width + 2 * cfg.radius,
        tags=tuple(np.uint32(t) for t in tags),
        fulls=tuple(np.uint32(((0xFFFFFFFF << s) & 0xFFFFFFFF) | t) for t in tags),
        offsets_flat=(-moves[:, 0] * cfg.width - moves[:, 1]).astype(np.uint64),
        dys=np.ascontiguousarray(moves[:, 0]), dxs=np.ascontiguousarray(moves[:, 1]),
        tags64=np.array(tags, dtype=np.uint64),
        bits=tuple(np.uint32(sum(1 << p for p in range(n_moves + 1) if codes[p, m]))
                   for m in range(n_moves)),
        start_onehot=np.uint32(1 << n_moves),
        lut_t=np.ascontiguousarray(codes.T), frac_bits=frac,
        half=(1 << (frac - 1)) if (cfg.rounding == "half_up" and frac > 0) else 0,
        e_max=np.uint32(cfg.e_max), start_code=cfg.start_code)


def kernel_path(cfg: DPConfig) -> str:
    """The kernel :func:`~dptbd.model.fast.run_fixed_fast` uses for ``cfg``: ``"binary"`` or
    ``"general"``."""
    plan = _plan(cfg)
    return "binary" if plan.binary and cfg.e_max < plan.key_limit else "general"
