"""What the ``states`` stream must carry, and the comparison that reports the first mismatch.

Plain numpy and Python (no cocotb import), so that pytest can unit-test the comparison and
the report without a simulator. Every word is packed and unpacked with
:func:`dptbd.hw.layouts.pack_states` and :func:`~dptbd.hw.layouts.unpack_state`, never with
hand-written bit positions.

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
        The configuration, with the LUT the gateware uses (see :meth:`~dptbd.config.DPConfig.with_weight_codes`).
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
        first = self.fields[0]
        return (f"first mismatch at output {self.index}: frame {self.frame}, row {self.row}, "
                f"col {self.col}, field {first}: expected {self.expected[first]}, got "
                f"{self.got[first]} (differing fields {list(self.fields)}; expected "
                f"{self.expected}, got {self.got})")


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
    differing = tuple(name for name in want_f if got_f[name] != want_f[name])
    if not differing:  # bits outside every field: cannot happen with a correct width
        differing = ("payload",)
        got_f["payload"], want_f["payload"] = int(got), int(expected)
    if position is None:
        frame, rest = divmod(index, cfg.width * cfg.height)
        row, col = divmod(rest, cfg.width)
    else:
        frame, row, col = (int(v) for v in position)
    return Mismatch(index, frame, row, col, differing, got_f, want_f)


class Scoreboard:
    """Compares the output stream word by word with the model's; stops at the first mismatch.

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

    def __init__(self, cfg: DPConfig, expected: np.ndarray,
                 on_frame: Callable[[int], None] | None = None,
                 positions: np.ndarray | None = None):
        self.cfg = cfg
        self._words = np.asarray(expected, dtype=np.uint64).ravel()
        self._positions = None if positions is None else np.asarray(positions)
        self._frame_words = cfg.width * cfg.height
        self._on_frame = on_frame
        self.count = 0
        self.mismatch: Mismatch | None = None
        self.extra = 0             # words beyond the expected stream

    @property
    def total(self) -> int:
        """Number of words expected."""
        return len(self._words)

    @property
    def done(self) -> bool:
        """Every expected word arrived and matched."""
        return self.mismatch is None and self.count == self.total and self.extra == 0

    @property
    def failed(self) -> bool:
        """A word differed or came beyond the end of the expected stream."""
        return self.mismatch is not None or self.extra > 0

    def receive(self, word: int) -> bool:
        """Check the next output word; False once anything went wrong."""
        if self.failed:
            return False
        if self.count >= self.total:
            self.extra += 1
            return False
        self.mismatch = compare_word(self.cfg, self.count, word, int(self._words[self.count]),
                                     self._position(self.count))
        if self.mismatch is not None:
            return False
        self.count += 1
        if self._on_frame is not None and self.count % self._frame_words == 0:
            self._on_frame(self.count // self._frame_words - 1)
        return True

    def _position(self, index: int):
        return None if self._positions is None else tuple(self._positions[index])

    def receive_array(self, words: np.ndarray) -> bool:
        """Check a block of consecutive output words at once (numpy; same outcome as
        calling :meth:`receive` on each): stops at the first mismatch or extra word."""
        if self.failed:
            return False
        got = np.asarray(words, dtype=np.uint64).ravel()
        take = min(len(got), self.total - self.count)
        want = self._words[self.count:self.count + take]
        bad = np.flatnonzero(got[:take] != want)
        good = take if bad.size == 0 else int(bad[0])
        before = self.count
        self.count += good
        if self._on_frame is not None:
            for done in range(before // self._frame_words, self.count // self._frame_words):
                self._on_frame(done)
        if bad.size:
            return self.receive(int(got[good]))
        if len(got) > take:
            self.extra += 1          # receive() stops at the first extra word
            return False
        return True

    def report(self) -> str:
        """One line: bit-exact, incomplete, or the first mismatch."""
        if self.mismatch is not None:
            return str(self.mismatch)
        if self.extra:
            return (f"{self.extra} output word(s) beyond the {self.total} expected "
                    f"({self.total // self._frame_words} frames)")
        if self.count < self.total:
            return f"incomplete: {self.count} of {self.total} words received, all bit-exact"
        return f"bit-exact: {self.count} words ({self.count // self._frame_words} frames)"
