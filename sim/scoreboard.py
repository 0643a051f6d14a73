"""What the ``states`` stream must carry, and the comparison that reports the first mismatch.

Plain numpy and Python (no cocotb import), so that pytest can unit-test the comparison and
the report without a simulator. Every word is packed and unpacked with
:func:`dptbd.hw.layouts.pack_states` and :func:`~dptbd.hw.layouts.unpack_state`, never with
hand-written bit positions. :class:`Scoreboard` is the ``states`` stream's
:class:`~dptbd.sim.checker.InOrderChecker`.

The expected stream is computed frame by frame with the golden model
(:mod:`dptbd.model.fixed`): :func:`~dptbd.model.fixed.segment_start` on the first frame of
every segment (frames 0, K, 2K, … counted from the first frame after reset) and
:func:`~dptbd.model.fixed.dp_step` on the others; ``end_of_line`` on column W-1,
``end_of_frame`` on the last pixel of a frame, ``end_of_segment`` on the last pixel of a
segment's last frame (``docs/arithmetic.md`` §5, ``docs/gateware.md``).
"""

from __future__ import annotations

import dataclasses
from typing import Callable, Iterator

import numpy as np

from dptbd.config import DPConfig
from dptbd.hw.layouts import pack_states, unpack_state
from dptbd.model.fixed import dp_step, segment_start
from dptbd.sim.checker import InOrderChecker, describe_field_mismatch, differing_fields

__all__ = [
    "model_frames",
    "expected_words",
    "pack_frame_states",
    "Mismatch",
    "compare_word",
    "Scoreboard",
]


def model_frames(cfg: DPConfig, frames: np.ndarray) -> Iterator[tuple[np.ndarray, np.ndarray]]:
    """The golden model's state (E, d) after every frame of ``frames`` ``(T, H, W)``.

    Segments of K frames start at frame 0 (the first frame after reset); a trailing
    incomplete segment is still processed (the gateware outputs every frame).
    """
    energy = direction = None
    for t, frame in enumerate(frames):
        if t % cfg.segment_frames == 0:
            energy, direction = segment_start(frame, cfg)
        else:
            energy, direction = dp_step(energy, direction, frame, cfg)
        yield energy, direction


def expected_words(cfg: DPConfig, frames: np.ndarray) -> np.ndarray:
    """Every ``states`` word the pipeline must output for ``frames``, in stream order.

    Parameters
    ----------
    cfg : DPConfig
        The configuration, with the LUT the gateware uses (see
        :meth:`~dptbd.config.DPConfig.with_weight_codes`).
    frames : numpy.ndarray
        ``(T, H, W)`` integer pixels.

    Returns
    -------
    numpy.ndarray
        ``(T, H, W)`` ``uint64`` packed payloads.
    """
    frames = np.asarray(frames)
    energy = np.zeros(frames.shape, dtype=np.int64)
    direction = np.zeros(frames.shape, dtype=np.int64)
    for t, (e, d) in enumerate(model_frames(cfg, frames)):
        energy[t], direction[t] = e, d
    return pack_frame_states(cfg, energy, direction)


def pack_frame_states(cfg: DPConfig, energy: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """Pack the states of whole frames ``(T, H, W)``, streamed from reset, with the flags the
    pipeline sets: ``end_of_line`` on column W-1, ``end_of_frame`` on a frame's last pixel,
    ``end_of_segment`` on the last pixel of frames K-1, 2K-1, …

    Returns
    -------
    numpy.ndarray
        ``(T, H, W)`` ``uint64`` payloads.
    """
    shape = np.shape(energy)
    n_frames, k = shape[0], cfg.segment_frames
    eol = np.zeros(shape, dtype=np.int64)
    eol[..., -1] = 1
    eof = np.zeros(shape, dtype=np.int64)
    eof[:, -1, -1] = 1
    eos = eof * (np.arange(n_frames) % k == k - 1)[:, None, None]
    return pack_states(cfg, energy=energy, direction=direction, end_of_line=eol,
                       end_of_frame=eof, end_of_segment=eos)


@dataclasses.dataclass(frozen=True)
class Mismatch:
    """The first output word that differs from the model."""

    index: int                 # position in the output stream (0 = first word)
    frame: int
    row: int
    col: int
    fields: tuple[str, ...]    # the differing fields, layout order
    got: dict                  # every field of the word that came out
    expected: dict             # every field of the model's word

    def __str__(self) -> str:
        return (f"first mismatch at output {self.index}: frame {self.frame}, row {self.row}, "
                f"col {self.col}, " + describe_field_mismatch(self.fields, self.got, self.expected))


def compare_word(cfg: DPConfig, index: int, got: int, expected: int,
                 position: tuple[int, int, int] | None = None) -> Mismatch | None:
    """Compare output word number ``index`` with the model's; ``None`` if equal bit for bit.

    ``index`` counts words from the first output after reset, in raster order frame by
    frame, which locates the frame, row and column unless ``position`` (frame, row, col)
    is given (streams whose frames do not all have W·H words: :mod:`dptbd.sim.stream_model`).
    """
    if int(got) == int(expected):
        return None
    got_f = unpack_state(cfg, got)
    want_f = unpack_state(cfg, expected)
    differing = differing_fields(tuple(want_f), got, expected, got_f, want_f)
    if position is None:
        frame, rest = divmod(index, cfg.width * cfg.height)
        row, col = divmod(rest, cfg.width)
    else:
        frame, row, col = (int(v) for v in position)
    return Mismatch(index, frame, row, col, differing, got_f, want_f)


class Scoreboard(InOrderChecker):
    """Compares the ``states`` stream word by word with the model's; stops at the first
    mismatch, reported by frame, row, column and field (:class:`Mismatch`).

    Parameters
    ----------
    cfg : DPConfig
        The configuration (field layout, frame size).
    expected : numpy.ndarray
        The expected packed words, any shape, consumed in C order (:func:`expected_words`).
    on_frame : callable, optional
        ``on_frame(frame_index)`` after the last word of every frame matched.
    positions : numpy.ndarray, optional
        ``(N, 3)`` frame, row and column of each expected word, for the report (default:
        from the word's index, W·H words a frame).
    """

    unit = "output word"

    def __init__(self, cfg: DPConfig, expected: np.ndarray,
                 on_frame: Callable[[int], None] | None = None,
                 positions: np.ndarray | None = None):
        super().__init__(np.asarray(expected, dtype=np.uint64).ravel())
        self.cfg = cfg
        self._positions = None if positions is None else np.asarray(positions)
        self._frame_words = cfg.width * cfg.height
        self._on_frame = on_frame

    def compare(self, index: int, got: int, want: int) -> Mismatch | None:
        position = None if self._positions is None else tuple(self._positions[index])
        return compare_word(self.cfg, index, got, want, position)

    def matched(self, start: int, stop: int) -> None:
        if self._on_frame is not None:
            for frame in range(start // self._frame_words, stop // self._frame_words):
                self._on_frame(frame)

    def expected_summary(self) -> str:
        return f"{self.total // self._frame_words} frames"

    def exact_summary(self) -> str:
        return f"{self.count} words ({self.count // self._frame_words} frames)"
