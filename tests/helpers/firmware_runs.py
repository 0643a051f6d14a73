"""The association firmware (C, :class:`~dptbd.dsp.c_tracker.CTracker`) run beside the Python
:class:`~dptbd.dsp.association.Tracker`, compared field by field: what the tests of
``tests/dsp/c_tracker/`` share."""

import ctypes
import functools
import importlib.util
import pathlib

import numpy as np

from dptbd.dsp.association import CANDIDATE_DTYPE, Tracker
from dptbd.dsp.c_tracker import CTracker
from dptbd.dsp.firmware import build_shared_library, capacity_defines

ROOT = pathlib.Path(__file__).resolve().parents[2]
STATE = ("tracks", "history", "archive", "archive_history", "inbuf", "_head_row", "_head_col",
         "_keep", "_claimed", "_match", "_class", "_order_tracks")
SCALARS = ("segment", "next_id", "n_archived", "n_in", "stats")


def example():
    spec = importlib.util.spec_from_file_location(
        "write_candidates", ROOT / "examples" / "dsp_tracker" / "write_candidates.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def assert_same(py, c, where):
    for name in SCALARS:
        assert getattr(py, name) == getattr(c, name), f"{where}: {name}"
    for name in STATE:
        a, b = getattr(py, name), getattr(c, name)
        if a.dtype.names:
            for field in a.dtype.names:
                assert np.array_equal(a[field], b[field]), f"{where}: {name}.{field}"
        else:
            assert np.array_equal(a, b), f"{where}: {name}"
    assert py.active() == c.active()


@functools.lru_cache(maxsize=None)
def probe(capacity=64, max_candidates=128, max_points=64, output_capacity=64):
    """The firmware's internals (tests/dsp/firmware/probe.c) for these capacities."""
    lib = ctypes.CDLL(str(build_shared_library(
        capacity_defines(capacity, max_candidates, max_points, output_capacity),
        sources=[ROOT / "tests" / "dsp" / "firmware" / "probe.c"])))
    u64, i64 = ctypes.c_uint64, ctypes.c_int64
    for name, res, args in (("probe_isqrt", u64, [u64, u64]),
                            ("probe_mul_div", u64, [u64, u64, u64]),
                            ("probe_div_round", i64, [i64, i64]),
                            ("probe_cost", i64, [ctypes.c_void_p, ctypes.c_int, ctypes.c_uint32])):
        getattr(lib, name).restype, getattr(lib, name).argtypes = res, args
    return lib


def assert_same_costs(py, c, where):
    """Tracker._cost against the firmware's cost_of for every live track and candidate."""
    cfg = py.cfg
    lib = probe(cfg.capacity, cfg.max_candidates, cfg.max_points, cfg.output_capacity)
    for i in np.flatnonzero(py.tracks["state"] != 0):
        for j in range(py.n_in):
            assert py._cost(int(i), j) == lib.probe_cost(ctypes.byref(c._ctx), int(i), j), \
                f"{where}: cost of candidate {j} for track {i}"


def run_both(assoc, kwargs, lists, where="", costs=False):
    """Both trackers over ``lists``; compared after every segment (and every match cost
    if ``costs``); returns them."""
    py, c = Tracker(assoc, **kwargs), CTracker(assoc, **kwargs)
    for s, cands in enumerate(lists):
        py.step(cands)
        c.step(cands)
        assert_same(py, c, f"{where} segment {s}")
        if costs:
            assert_same_costs(py, c, f"{where} segment {s}")
    assert py.confirmed_tracks() == [] or all(
        a.id == b.id and a.alive == b.alive and np.array_equal(a.points, b.points)
        for a, b in zip(py.confirmed_tracks(), c.confirmed_tracks(), strict=True))
    return py, c


KW = dict(segment_frames=6, segment_stride=6, height=128, width=128, radius=1)


def recs(items):
    return np.array(items, dtype=CANDIDATE_DTYPE)
