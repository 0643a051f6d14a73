"""Load a recorded image sequence: ``.npy``, ``.npz`` or a folder of 8/16-bit PNG or TIFF frames.

The result is what the FPGA stage takes (``docs/arithmetic.md`` §1): integer frames
``(T, H, W)``, unsigned, of B_in = 8 bits (``uint8`` data, 8-bit images) or 16 bits
(``uint16`` data, 16-bit images). Nothing is rescaled, clipped or converted from colour:
data that does not fit is refused with a message that names the file and the problem.

* ``.npy`` — one array ``(T, H, W)`` of an integer dtype, values in [0, 65535].
* ``.npz`` — the array named by ``key``; without a key the archive's only array, or the
  one called ``frames``.
* a folder — every ``*.png``, ``*.tif``, ``*.tiff`` file (any case; other files and hidden
  files are ignored), in natural order of their names (``f2.png`` before ``f10.png``);
  grayscale 8-bit (mode ``L``) or 16-bit (``I;16``) single-frame images, all of one size
  and one bit depth.

Refused: a missing path, an unreadable file, an empty sequence, a single 2-D frame, frames
smaller than 3 x 3, float/bool/complex data, negative or > 65535 values, mixed frame
sizes or bit depths, colour or palette images, multi-page TIFF files.
"""

from __future__ import annotations

import dataclasses
import pathlib
import re
import zipfile

import numpy as np

from dptbd.errors import DptbdError

__all__ = ["SequenceError", "LoadedSequence", "load_sequence", "IMAGE_SUFFIXES"]

IMAGE_SUFFIXES = (".png", ".tif", ".tiff")
_MODES_8 = ("L",)
_MODES_16 = ("I;16", "I;16L", "I;16B", "I;16N")


class SequenceError(DptbdError):
    """The sequence cannot be used; the message names the file and the reason."""


@dataclasses.dataclass(frozen=True)
class LoadedSequence:
    """A loaded sequence.

    Attributes
    ----------
    frames : numpy.ndarray
        ``(T, H, W)`` ``uint8`` or ``uint16``.
    input_bits : int
        8 or 16: the B_in the frames are given to the DP with.
    source : str
        What was read (path, key or number of files).
    files : tuple of str
        The frame files of a folder, in order (empty for arrays).
    """

    frames: np.ndarray
    input_bits: int
    source: str
    files: tuple[str, ...] = ()


def _natural_key(name: str) -> list:
    return [int(part) if part.isdigit() else part.lower() for part in re.split(r"(\d+)", name)]


def _check_array(arr: np.ndarray, where: str) -> tuple[np.ndarray, int]:
    """Integer ``(T, H, W)`` in [0, 65535] -> ``uint8``/``uint16`` and B_in."""
    if arr.dtype.kind not in "iu":
        hint = (" (quantise float frames to integers first, e.g. with "
                "dptbd.scenes.synthetic.quantise)") if arr.dtype.kind == "f" else ""
        raise SequenceError(f"{where}: frames must be integers, got dtype {arr.dtype}{hint}")
    if arr.ndim == 2:
        raise SequenceError(f"{where}: one frame of shape {arr.shape}; a sequence needs shape "
                            f"(frames, height, width)")
    if arr.ndim != 3:
        raise SequenceError(f"{where}: a sequence must have shape (frames, height, width), got "
                            f"shape {arr.shape}")
    if arr.shape[0] == 0:
        raise SequenceError(f"{where}: the sequence is empty (0 frames)")
    if arr.shape[1] < 3 or arr.shape[2] < 3:
        raise SequenceError(f"{where}: frames are {arr.shape[1]} x {arr.shape[2]} (H x W); the "
                            f"DP needs at least 3 x 3")
    lo, hi = int(arr.min()), int(arr.max())
    if lo < 0 or hi > 65535:
        raise SequenceError(f"{where}: pixel values must be in [0, 65535] (8 or 16 bits), found "
                            f"[{lo}, {hi}]")
    if arr.dtype.itemsize == 1:
        return arr.astype(np.uint8, copy=False), 8
    return arr.astype(np.uint16, copy=False), 16


_NPY_MAGIC = b"\x93NUMPY"


def _load_npy(path: pathlib.Path) -> np.ndarray:
    # np.load takes any file without the .npy magic string for a pickle and, with pickles
    # refused, says "contains pickled (object) data": check the magic first
    try:
        with open(path, "rb") as fh:
            magic = fh.read(len(_NPY_MAGIC))
    except OSError as exc:
        raise SequenceError(f"cannot read {path}: {exc.strerror or exc}") from exc
    if magic != _NPY_MAGIC:
        raise SequenceError(f"cannot read {path} as a .npy array: it is not a NumPy .npy file "
                            f"(it does not start with the .npy header; save frames with "
                            f"numpy.save)")
    try:
        return np.load(path, allow_pickle=False)
    except ValueError as exc:
        if "Object arrays" in str(exc) or "pickle" in str(exc):
            raise SequenceError(f"cannot read {path} as a .npy array: it holds Python objects "
                                f"(pickled data), not integer frames; pickles are never "
                                f"loaded") from exc
        raise SequenceError(f"cannot read {path} as a .npy array: the file is damaged or "
                            f"truncated ({exc})") from exc
    except (OSError, EOFError) as exc:
        raise SequenceError(f"cannot read {path} as a .npy array: the file is damaged or "
                            f"truncated ({exc})") from exc


def _load_npz(path: pathlib.Path, key: str | None) -> tuple[np.ndarray, str]:
    try:
        with np.load(path, allow_pickle=False) as archive:
            names = list(archive.files)
            if key is None:
                if len(names) == 1:
                    key = names[0]
                elif "frames" in names:
                    key = "frames"
                else:
                    raise SequenceError(
                        f"{path} holds {len(names)} arrays {names}; name the one to use "
                        f"(--npz-key, or [input] key)" if names else f"{path} holds no arrays")
            if key not in names:
                raise SequenceError(f"{path} has no array {key!r}; it holds {names}")
            return archive[key], key
    except (ValueError, OSError, EOFError, zipfile.BadZipFile) as exc:
        if isinstance(exc, SequenceError):
            raise
        raise SequenceError(f"cannot read {path} as a .npz archive: {exc}") from exc


def _read_image(path: pathlib.Path) -> np.ndarray:
    from PIL import Image, UnidentifiedImageError

    try:
        with Image.open(path) as img:
            if getattr(img, "n_frames", 1) > 1:
                raise SequenceError(f"{path} holds {img.n_frames} frames (multi-page); give one "
                                    f"frame per file")
            mode = img.mode
            if mode in _MODES_8:
                return np.asarray(img, dtype=np.uint8).copy()
            if mode in _MODES_16:
                return np.asarray(img).astype(np.uint16)
            if mode == "I":
                # Pillow opens some 16-bit PNGs as 32-bit "I"; accept them if they fit 16 bits
                arr = np.asarray(img)
                if arr.size and (int(arr.min()) < 0 or int(arr.max()) > 65535):
                    raise SequenceError(f"{path}: 32-bit integer image with values outside "
                                        f"[0, 65535]; give 8- or 16-bit grayscale frames")
                return arr.astype(np.uint16)
            raise SequenceError(f"{path}: image mode {mode!r} is not 8- or 16-bit grayscale "
                                f"(colour, palette, float and 1-bit images are refused; "
                                f"convert to grayscale L or I;16)")
    except SequenceError:
        raise
    except (UnidentifiedImageError, OSError, ValueError, SyntaxError) as exc:
        raise SequenceError(f"cannot read image {path}: {exc}") from exc


def _load_folder(path: pathlib.Path) -> tuple[np.ndarray, tuple[str, ...]]:
    files = sorted((p for p in path.iterdir()
                    if p.is_file() and not p.name.startswith(".")
                    and p.suffix.lower() in IMAGE_SUFFIXES),
                   key=lambda p: _natural_key(p.name))
    if not files:
        raise SequenceError(f"folder {path} holds no PNG or TIFF frames "
                            f"({', '.join(IMAGE_SUFFIXES)}): the sequence is empty")
    frames = []
    first = None
    for f in files:
        img = _read_image(f)
        if first is None:
            first = (f, img.shape, img.dtype)
        elif img.shape != first[1]:
            raise SequenceError(f"frames of mixed sizes: {first[0].name} is {first[1][1]} x "
                                f"{first[1][0]} (W x H) but {f.name} is {img.shape[1]} x "
                                f"{img.shape[0]}")
        elif img.dtype != first[2]:
            bits = {np.dtype(np.uint8): 8, np.dtype(np.uint16): 16}
            raise SequenceError(f"frames of mixed bit depths: {first[0].name} is "
                                f"{bits[first[2]]}-bit but {f.name} is {bits[img.dtype]}-bit")
        frames.append(img)
    return np.stack(frames), tuple(str(f) for f in files)


def load_sequence(path: str | pathlib.Path, *, key: str | None = None) -> LoadedSequence:
    """Load a recorded sequence (module docstring); raise :class:`SequenceError` or
    ``FileNotFoundError`` with a clear message otherwise."""
    path = pathlib.Path(path).expanduser()
    if not path.exists():
        raise FileNotFoundError(f"input {path} does not exist")
    if path.is_dir():
        if key is not None:
            raise SequenceError(f"an npz key ({key!r}) was given but {path} is a folder")
        arr, files = _load_folder(path)
        frames, bits = _check_array(arr, str(path))
        return LoadedSequence(frames, bits, f"{path} ({len(files)} frames)", files)
    suffix = path.suffix.lower()
    if suffix == ".npy":
        if key is not None:
            raise SequenceError(f"an npz key ({key!r}) was given but {path} is a .npy file")
        frames, bits = _check_array(_load_npy(path), str(path))
        return LoadedSequence(frames, bits, str(path))
    if suffix == ".npz":
        arr, used = _load_npz(path, key)
        frames, bits = _check_array(arr, f"{path}[{used}]")
        return LoadedSequence(frames, bits, f"{path}[{used}]")
    raise SequenceError(f"input {path}: expected a .npy or .npz file or a folder of PNG/TIFF "
                        f"frames, got a {suffix or 'suffix-less'} file")
