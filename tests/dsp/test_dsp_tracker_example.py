"""examples/dsp_tracker: built by one ``make``, it prints what the Python model confirms on
recorded scenes, and refuses corrupt files with one named reason — all under
-fsanitize=address,undefined."""

import importlib.util
import pathlib
import struct
import subprocess
import sys

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.dsp.association import AssociationConfig

ROOT = pathlib.Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "dsp_tracker"
SANITIZE = "-O1 -g -fsanitize=address,undefined -fno-sanitize-recover=all"
KW = dict(segment_frames=6, segment_stride=6, height=128, width=128, radius=1)


@pytest.fixture(scope="module")
def ex():
    spec = importlib.util.spec_from_file_location("write_candidates", EXAMPLE / "write_candidates.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.fixture(scope="module")
def program(tmp_path_factory):
    """``make -C examples/dsp_tracker`` with the sanitizers, into a temporary folder."""
    out = tmp_path_factory.mktemp("example") / "dsp_tracker"
    subprocess.run(["make", "-s", "-C", str(EXAMPLE), f"OUT={out}", f"CFLAGS={SANITIZE}"],
                   check=True, capture_output=True)
    return out


def run(program, data: bytes, tmp_path):
    path = tmp_path / "lists.dptbd"
    path.write_bytes(data)
    res = subprocess.run([str(program), str(path)], capture_output=True, text=True)
    return res.returncode, res.stdout, res.stderr.replace(str(path), "FILE")


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_prints_the_models_tracks_on_recorded_scenes(seed, ex, program, tmp_path):
    cfg, assoc, kwargs, lists = ex.scene_lists(seed)
    rc, out, err = run(program, ex.candidate_file_bytes(cfg, assoc, kwargs, lists), tmp_path)
    assert (rc, err) == (0, "")
    assert out == ex.python_output(assoc, kwargs, lists)
    assert "confirmed tracks: 0\n" not in out


def _lists(n_seg=6, n=5, height=128):
    rng = np.random.default_rng(3)
    from dptbd.dsp.association import CANDIDATE_DTYPE
    out = []
    for s in range(n_seg):
        items = [(20 + 2 * s, 30 + s, 900, 4, 20 + 2 * s, 30 + s, 1)]
        items += [(int(r), int(c), int(e), 4, int(r), int(c), 1) for r, c, e in
                  zip(rng.integers(0, height, n - 1), rng.integers(0, 128, n - 1),
                      rng.integers(100, 500, n - 1))]
        out.append(np.array(items, dtype=CANDIDATE_DTYPE))
    return out


def test_a_list_longer_than_the_capacity_is_clipped(ex, program, tmp_path):
    lists = _lists(n=128 + 5)          # the example is built with DPTBD_MAX_CANDIDATES = 128
    rc, out, err = run(program, ex.candidate_file_bytes(DPConfig(), AssociationConfig(
        max_candidates=128), KW, lists), tmp_path)
    assert (rc, err) == (0, "")
    expect = ex.python_output(AssociationConfig(), KW, [c[:128] for c in lists])
    assert out == expect.replace("clipped 0,", f"clipped {5 * len(lists)},", 1)


def test_candidates_outside_the_frame_are_rejected(ex, program, tmp_path):
    lists, kw = _lists(n=20), {**KW, "height": 100}
    rc, out, err = run(program, ex.candidate_file_bytes(DPConfig(), AssociationConfig(), kw,
                                                        lists), tmp_path)
    bad = sum(int(np.count_nonzero(c["row"] >= 100)) for c in lists)
    assert (rc, err) == (0, "") and bad > 0
    expect = ex.python_output(AssociationConfig(), kw, [c[c["row"] < 100] for c in lists])
    assert out == expect.replace("rejected 0", f"rejected {bad}", 1)


def _corrupt(ex):
    good = ex.candidate_file_bytes(DPConfig(), AssociationConfig(), KW, _lists())
    head = 8 + 4 + 36 + 16 + 108            # magic, version, layout, capacities, parameters
    first = head + 4 + 4                     # the first record's payload word
    trailer = struct.pack("<Q", 1 << 34)
    return {
        "not a candidate file (magic DPTBDCL1 missing) (at byte 0)": b"DPTBDXX1" + good[8:],
        "version is not 2 (at byte 12)": good[:8] + struct.pack("<I", 1) + good[12:],
        "record layout differs from dptbd_candidate_record.h (at byte 20)":
            good[:16] + struct.pack("<I", 8) + good[20:],
        "capacities differ from this build's DPTBD_* constants (at byte 52)":
            good[:48] + struct.pack("<I", 65) + good[52:],
        "truncated in the parameters (at byte 100)": good[:100],
        "truncated before the segment count (at byte 172)": good[:head],
        "truncated at a list length (at byte 178)": good[:head + 6],
        "truncated inside a list (at byte 192)": good[:head + 20],
        "a word that is not a candidate record (at byte 180)": good[:first] + trailer + good[first + 8:],
        "bytes after the last segment (at byte %d)" % (len(good) + 1): good + b"\0",
    }


def test_corrupt_files_are_refused_with_the_reason(ex, program, tmp_path):
    for reason, data in _corrupt(ex).items():
        rc, out, err = run(program, data, tmp_path)
        assert (rc, out, err) == (2, "", f"dsp_tracker: FILE: corrupt file: {reason}\n"), reason


def test_parameters_the_firmware_refuses(ex, program, tmp_path):
    data = ex.candidate_file_bytes(DPConfig(), AssociationConfig(), {**KW, "segment_stride": 2000},
                                   _lists())
    assert run(program, data, tmp_path) == (
        3, "", "dsp_tracker: FILE: the firmware refuses the parameters\n")


def test_usage_and_missing_file(program, tmp_path):
    res = subprocess.run([str(program)], capture_output=True, text=True)
    assert (res.returncode, res.stderr) == (
        1, "usage: dsp_tracker FILE   (FILE: write_candidates.py's output)\n")
    res = subprocess.run([str(program), str(tmp_path / "none")], capture_output=True, text=True)
    assert (res.returncode, res.stderr) == (1, f"dsp_tracker: cannot open {tmp_path / 'none'}\n")


def test_write_candidates_script(tmp_path):
    out, expect = tmp_path / "s.dptbd", tmp_path / "s.txt"
    res = subprocess.run([sys.executable, str(EXAMPLE / "write_candidates.py"), "--seed", "4",
                          "--out", str(out), "--expect", str(expect)],
                         capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    assert res.stderr.startswith(f"wrote {out}: 16 segments, ")
    assert out.read_bytes()[:8] == b"DPTBDCL1" and expect.read_text().startswith("segments 16,")
