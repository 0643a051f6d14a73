"""The association firmware (``dptbd/dsp/firmware/``, C99) driven from Python.

:class:`CTracker` has the constructor, :meth:`~CTracker.step` and read-out of
:class:`dptbd.dsp.association.Tracker` (it is a subclass: the parameter checks, the integer
codes and the host-side read-out — :meth:`~dptbd.dsp.association.Tracker.confirmed_tracks`,
:meth:`~dptbd.dsp.association.Tracker.active` — are the Python model's), but each segment is
associated by ``dptbd_track_step`` in C. After every step the whole C context (records,
histories, archive, input buffer, scratch, counters) is copied into the same numpy arrays
the Python model keeps, so the two can be compared field by field
(``tests/dsp/c_tracker/``) and ``dptbd.evaluation.chain`` can use either:
:func:`tracker_class` (``"python"`` or ``"c"``).

The library is built on first use with the capacities of the :class:`AssociationConfig`
(compile-time constants of the firmware; :mod:`dptbd.dsp.firmware`), and cached.
"""

from __future__ import annotations

import ctypes
import functools

import numpy as np

from dptbd.dsp.association import (CANDIDATE_DTYPE, AssociationConfig, AssociationError,
                                     Tracker, check_candidate_list)
from dptbd.dsp.firmware import build_shared_library, capacity_defines

__all__ = ["DSP_IMPLEMENTATIONS", "CTracker", "FirmwareError", "tracker_class", "load_firmware",
           "params_codes", "backtrack_starts", "trim_to_count", "PARAM_NAMES", "STATUS"]

#: Names :func:`tracker_class` accepts.
DSP_IMPLEMENTATIONS = ("python", "c")

#: The firmware's status codes (``dptbd_track.h``).
STATUS = {0: "DPTBD_OK", 1: "DPTBD_W_CLIPPED", 2: "DPTBD_W_REJECTED",
          3: "DPTBD_W_CLIPPED|DPTBD_W_REJECTED", -1: "DPTBD_E_NULL", -2: "DPTBD_E_PARAMS",
          -3: "DPTBD_E_NOT_INITIALISED", -4: "DPTBD_E_SEGMENTS", -5: "DPTBD_E_MAPS"}

_STATS = ("segments", "candidates", "suppressed", "matched", "started", "confirmed", "deleted",
          "left_image", "dropped_candidates", "dropped_outputs", "history_wrapped", "duplicates",
          "peak_active", "wake_suppressed")
_INPUT_COUNTERS = ("clipped_candidates", "rejected_candidates")
#: Fields of ``dptbd_params``, in the struct's order.
PARAM_NAMES = ("segment_frames", "segment_stride", "height", "width", "radius", "merge_radius",
               "duplicate_radius", "seed_gate", "gate_base", "gate_growth", "gate_miss",
               "gate_max", "gate_growth_segments", "manoeuvre", "link_gate", "heading_min",
               "heading_weight", "reject_reversed", "confirm_ratio", "predict_ratio",
               "delete_ratio", "confirm_hits", "predict_hits", "max_misses", "confirm_gap",
               "wake_radius", "wake_points")


class FirmwareError(RuntimeError):
    """The firmware refused a call with an error status (the message names it)."""


def tracker_class(name: str) -> type:
    """The association implementation ``name``: ``"python"`` (the reference model,
    :class:`~dptbd.dsp.association.Tracker`) or ``"c"`` (:class:`CTracker`)."""
    if name == "python":
        return Tracker
    if name == "c":
        return CTracker
    raise ValueError(f"dsp must be one of {', '.join(DSP_IMPLEMENTATIONS)}, got {name!r}")


class _Candidate(ctypes.Structure):
    _fields_ = [("energy", ctypes.c_uint32), ("row", ctypes.c_uint16), ("col", ctypes.c_uint16),
                ("row0", ctypes.c_uint16), ("col0", ctypes.c_uint16),
                ("direction", ctypes.c_uint8), ("path", ctypes.c_uint8)]


class _Track(ctypes.Structure):
    _fields_ = [("id", ctypes.c_uint32), ("first_seg", ctypes.c_int32),
                ("confirm_seg", ctypes.c_int32), ("p_seg", ctypes.c_int32 * 2),
                ("p_row", ctypes.c_int32 * 2), ("p_col", ctypes.c_int32 * 2),
                ("v_row", ctypes.c_int32), ("v_col", ctypes.c_int32),
                ("pred_row", ctypes.c_int32), ("pred_col", ctypes.c_int32),
                ("count_seg", ctypes.c_int32),
                ("n_points", ctypes.c_uint32), ("length", ctypes.c_uint16),
                ("hits", ctypes.c_uint16), ("gate", ctypes.c_uint16),
                ("counted", ctypes.c_uint16), ("state", ctypes.c_uint8),
                ("misses", ctypes.c_uint8)]


class _Point(ctypes.Structure):
    _fields_ = [("seg", ctypes.c_int32), ("energy", ctypes.c_uint32), ("row", ctypes.c_uint16),
                ("col", ctypes.c_uint16), ("row0", ctypes.c_uint16), ("col0", ctypes.c_uint16),
                ("path", ctypes.c_uint8)]


class _Params(ctypes.Structure):
    _fields_ = [(name, ctypes.c_int32) for name in PARAM_NAMES]


class _Stats(ctypes.Structure):
    _fields_ = [(name, ctypes.c_uint64) for name in _STATS + _INPUT_COUNTERS]


class _Work(ctypes.Structure):
    _fields_ = [(name, ctypes.c_uint32) for name in
                ("suppression_tests", "sort_compares", "cost_evaluations", "duplicate_tests",
                 "wake_tests", "free_probes")]


@functools.lru_cache(maxsize=None)
def _numpy_dtype(record: type) -> np.dtype:
    """numpy dtype with the C layout (offsets, padding) of a ctypes record."""
    names, formats, offsets = [], [], []
    for name, ctype in record._fields_:
        field = getattr(record, name)
        names.append(name)
        offsets.append(field.offset)
        if issubclass(ctype, ctypes.Array):
            formats.append((np.dtype(ctype._type_), (ctype._length_,)))
        else:
            formats.append(np.dtype(ctype))
    return np.dtype({"names": names, "formats": formats, "offsets": offsets,
                     "itemsize": ctypes.sizeof(record)})


@functools.lru_cache(maxsize=None)
def _context_type(capacity: int, max_candidates: int, max_points: int,
                  output_capacity: int) -> type:
    """ctypes mirror of ``dptbd_tracker`` for these capacities (``dptbd_track.h``)."""
    c, n, p, a = capacity, max_candidates, max_points, max(output_capacity, 1)
    return type("_Context", (ctypes.Structure,), {"_fields_": [
        ("magic", ctypes.c_uint32), ("p", _Params), ("segment", ctypes.c_int32),
        ("next_id", ctypes.c_uint32), ("n_archived", ctypes.c_uint32),
        ("n_in", ctypes.c_uint32), ("stats", _Stats),
        ("tracks", _Track * c), ("history", (_Point * p) * c), ("archive", _Track * a),
        ("archive_history", (_Point * p) * a), ("inbuf", _Candidate * n),
        ("head_row", ctypes.c_int32 * n), ("head_col", ctypes.c_int32 * n),
        ("order", ctypes.c_uint16 * n), ("keep", ctypes.c_uint8 * n),
        ("claimed", ctypes.c_uint8 * n), ("match", ctypes.c_int32 * c),
        ("order_tracks", ctypes.c_uint16 * c), ("cls", ctypes.c_uint8 * c)]})


@functools.lru_cache(maxsize=None)
def load_firmware(capacity: int = 64, max_candidates: int = 128, max_points: int = 64,
                  output_capacity: int = 64, compiler: str | None = None) -> ctypes.CDLL:
    """The firmware library for these capacities (built on first use, then cached), its
    functions typed, its record sizes checked against the ctypes mirrors."""
    path = build_shared_library(capacity_defines(capacity, max_candidates, max_points,
                                                 output_capacity), compiler=compiler)
    lib = ctypes.CDLL(str(path))
    lib.dptbd_track_init.argtypes = [ctypes.c_void_p, ctypes.POINTER(_Params)]
    lib.dptbd_track_step.argtypes = [ctypes.c_void_p, ctypes.POINTER(_Candidate), ctypes.c_uint32,
                                     ctypes.POINTER(_Work)]
    lib.dptbd_track_active.argtypes = [ctypes.c_void_p]
    lib.dptbd_track_build_info.argtypes = [ctypes.c_int]
    lib.dptbd_backtrack_list.argtypes = [ctypes.c_void_p, ctypes.c_int32, ctypes.c_int32,
                                         ctypes.c_int32, ctypes.c_int32,
                                         ctypes.POINTER(_Candidate), ctypes.c_uint32]
    lib.dptbd_backtrack_list.restype = ctypes.c_uint32
    lib.dptbd_trim_to_count.argtypes = [ctypes.POINTER(_Candidate), ctypes.c_uint32,
                                        ctypes.c_uint32]
    lib.dptbd_trim_to_count.restype = ctypes.c_uint32
    for f in (lib.dptbd_track_init, lib.dptbd_track_step):
        f.restype = ctypes.c_int
    for f in (lib.dptbd_track_active, lib.dptbd_track_context_bytes, lib.dptbd_track_build_info):
        f.restype = ctypes.c_uint32
    ctx = _context_type(capacity, max_candidates, max_points, output_capacity)
    want = (capacity, max_candidates, max_points, output_capacity, ctypes.sizeof(_Candidate),
            ctypes.sizeof(_Track), ctypes.sizeof(_Point), ctypes.sizeof(_Stats))
    got = tuple(lib.dptbd_track_build_info(i) for i in range(8))
    if got != want or lib.dptbd_track_context_bytes() != ctypes.sizeof(ctx):
        raise FirmwareError(f"firmware {path} does not match its ctypes mirror: build info "
                            f"{got} != {want} or context {lib.dptbd_track_context_bytes()} != "
                            f"{ctypes.sizeof(ctx)} bytes")
    return lib


def _to_c(candidates: np.ndarray) -> np.ndarray:
    buf = np.zeros(max(len(candidates), 1), dtype=_numpy_dtype(_Candidate))
    for name in CANDIDATE_DTYPE.names:
        buf[name][:len(candidates)] = candidates[name]
    return buf


def _from_c(buf: np.ndarray, n: int) -> np.ndarray:
    out = np.zeros(n, dtype=CANDIDATE_DTYPE)
    for name in CANDIDATE_DTYPE.names:
        out[name] = buf[name][:n]
    return out


def trim_to_count(candidates: np.ndarray, count: int, lib: ctypes.CDLL | None = None
                  ) -> np.ndarray:
    """``dptbd_trim_to_count`` in C on :data:`CANDIDATE_DTYPE` records
    (:func:`dptbd.dsp.association.trim_to_count`'s rule)."""
    lib = load_firmware() if lib is None else lib
    buf = _to_c(candidates)
    n = lib.dptbd_trim_to_count(buf.ctypes.data_as(ctypes.POINTER(_Candidate)),
                                len(candidates), int(count))
    return _from_c(buf, int(n))


def backtrack_starts(candidates: np.ndarray, maps: np.ndarray, radius: int,
                     lib: ctypes.CDLL | None = None) -> tuple[np.ndarray, int]:
    """``dptbd_backtrack_list`` in C: each candidate's path start through one segment's maps.

    Parameters
    ----------
    candidates : numpy.ndarray
        :data:`CANDIDATE_DTYPE` records (``row0``, ``col0``, ``path`` are ignored).
    maps : numpy.ndarray
        ``uint8`` ``(K, H, W)`` direction maps of the segment
        (:func:`dptbd.dsp.backtrack.segment_direction_maps`).
    radius : int
        DP search radius r.

    Returns
    -------
    (numpy.ndarray, int)
        The records with ``row0``, ``col0``, ``path`` filled (what
        :func:`~dptbd.dsp.association.make_candidates` gives with
        :func:`~dptbd.dsp.backtrack.candidate_paths`), and how many could not be
        backtracked (corrupt maps: ``path`` = 0, ``row0, col0`` = ``row, col``).
    """
    lib = load_firmware() if lib is None else lib
    maps = np.ascontiguousarray(maps, dtype=np.uint8)
    if maps.ndim != 3:
        raise ValueError(f"maps must be (K, H, W), got shape {maps.shape}")
    buf = _to_c(candidates)
    k, h, w = maps.shape
    failed = lib.dptbd_backtrack_list(maps.ctypes.data, k, h, w, int(radius),
                                      buf.ctypes.data_as(ctypes.POINTER(_Candidate)),
                                      len(candidates))
    return _from_c(buf, len(candidates)), int(failed)


def params_codes(tracker: Tracker, radius: int) -> dict[str, int]:
    """The integer codes the firmware takes (``dptbd_params``, in :data:`PARAM_NAMES`
    order), from a Python tracker's codes and the DP search radius it was built with."""
    cfg = tracker.cfg
    return {"segment_frames": tracker.k, "segment_stride": tracker.stride,
            "height": tracker.height, "width": tracker.width,
            "radius": int(radius),
            "merge_radius": cfg.merge_radius, "duplicate_radius": cfg.duplicate_radius,
            "seed_gate": tracker.seed_gate, "gate_base": tracker.gate_base,
            "gate_growth": tracker.gate_growth, "gate_miss": tracker.gate_miss,
            "gate_max": tracker.gate_max, "gate_growth_segments": cfg.gate_growth_segments,
            "manoeuvre": tracker.manoeuvre, "link_gate": tracker.link_gate,
            "heading_min": tracker.heading_min, "heading_weight": tracker.heading_weight,
            "reject_reversed": int(cfg.reject_reversed),
            "confirm_ratio": tracker.confirm_ratio, "predict_ratio": tracker.predict_ratio,
            "delete_ratio": tracker.delete_ratio, "confirm_hits": cfg.confirm_hits,
            "predict_hits": cfg.predict_hits, "max_misses": cfg.max_misses,
            "confirm_gap": tracker.confirm_gap, "wake_radius": cfg.wake_radius,
            "wake_points": cfg.wake_points}


#: Limits of the firmware beyond AssociationConfig's (``dptbd_params`` in dptbd_track.h).
_C_LIMITS = {"segment_stride": (1, 1024), "height": (1, 65536), "width": (1, 65536),
             "radius": (0, 255)}


class CTracker(Tracker):
    """:class:`~dptbd.dsp.association.Tracker` with its association in the C firmware.

    Parameters are those of :class:`~dptbd.dsp.association.Tracker`, plus ``compiler``
    (default ``$CC``, else ``cc``). The firmware also requires ``segment_stride <= 1024``,
    ``height, width <= 65536`` and ``radius <= 255`` (refused naming the parameter).

    Attributes
    ----------
    input_counters : dict
        The firmware's bad-input counters: ``clipped_candidates`` (never non-zero through
        :meth:`step`, which refuses a list longer than ``max_candidates`` as the model
        does) and ``rejected_candidates`` (candidates outside the frame, dropped by the
        firmware; the Python model does not check them).
    last_status : int
        Status of the last ``dptbd_track_step`` (:data:`STATUS`).
    last_work : dict
        Work counters of the last step (``dptbd_work``).
    """

    def __init__(self, cfg: AssociationConfig, *, segment_frames: int, segment_stride: int,
                 height: int, width: int, radius: int = 1, compiler: str | None = None) -> None:
        super().__init__(cfg, segment_frames=segment_frames, segment_stride=segment_stride,
                         height=height, width=width, radius=radius)
        codes = params_codes(self, radius)
        for name, (lo, hi) in _C_LIMITS.items():
            if not lo <= codes[name] <= hi:
                raise AssociationError(f"the C firmware needs {name} in [{lo}, {hi}], "
                                       f"got {codes[name]}")
        caps = (cfg.capacity, cfg.max_candidates, cfg.max_points, cfg.output_capacity)
        self._lib = load_firmware(*caps, compiler=compiler)
        self._ctx = _context_type(*caps)()
        self._params = _Params(**codes)
        status = self._lib.dptbd_track_init(ctypes.byref(self._ctx), ctypes.byref(self._params))
        if status != 0:
            raise FirmwareError(f"dptbd_track_init returned {STATUS.get(status, status)} for "
                                f"{codes}")
        self._work = _Work()
        self.last_status = 0
        self.last_work: dict[str, int] = {}
        self.input_counters = dict.fromkeys(_INPUT_COUNTERS, 0)

    def step(self, candidates: np.ndarray) -> None:
        """Associate one segment's candidates in C; refuses what
        :meth:`dptbd.dsp.association.Tracker.step` refuses, with the same messages."""
        check_candidate_list(candidates, self.cfg)
        self.step_raw(candidates)

    def step_raw(self, candidates: np.ndarray) -> int:
        """One ``dptbd_track_step`` on :data:`CANDIDATE_DTYPE` records without the Python
        checks (a list longer than ``max_candidates`` is the firmware's to clip), for
        testing the firmware's own bad-input handling. Returns the status; raises
        :class:`FirmwareError` on a negative one."""
        buf = _to_c(candidates)
        status = self._lib.dptbd_track_step(ctypes.byref(self._ctx),
                                            buf.ctypes.data_as(ctypes.POINTER(_Candidate)),
                                            len(candidates), ctypes.byref(self._work))
        if status < 0:
            raise FirmwareError(f"dptbd_track_step returned {STATUS.get(status, status)}")
        self.last_status = status
        self.last_work = {name: int(getattr(self._work, name)) for name, _ in _Work._fields_}
        self._sync()
        return status

    def _sync(self) -> None:
        """Copy the C context into the model's arrays."""
        ctx = self._ctx
        for dst, src, rec in ((self.tracks, ctx.tracks, _Track),
                              (self.archive, ctx.archive, _Track),
                              (self.history, ctx.history, _Point),
                              (self.archive_history, ctx.archive_history, _Point),
                              (self.inbuf, ctx.inbuf, _Candidate)):
            arr = np.frombuffer(src, dtype=_numpy_dtype(rec)).reshape(-1, *dst.shape[1:])
            for name in dst.dtype.names:
                dst[name] = arr[name][:len(dst)]
        for dst, src in ((self._head_row, ctx.head_row), (self._head_col, ctx.head_col),
                         (self._order, ctx.order), (self._keep, ctx.keep),
                         (self._claimed, ctx.claimed), (self._match, ctx.match),
                         (self._order_tracks, ctx.order_tracks), (self._class, ctx.cls)):
            dst[:] = np.frombuffer(src, dtype=np.dtype(src._type_))
        self.segment, self.next_id = int(ctx.segment), int(ctx.next_id)
        self.n_archived, self.n_in = int(ctx.n_archived), int(ctx.n_in)
        for name in _STATS:
            self.stats[name] = int(getattr(ctx.stats, name))
        for name in _INPUT_COUNTERS:
            self.input_counters[name] = int(getattr(ctx.stats, name))
