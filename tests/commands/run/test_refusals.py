"""``dptbd run``: bad input refused with a clear message (exit 2) and nothing left in the
output folder; an earlier run replaced only with ``--force``, a folder it did not write never."""

import json

import numpy as np
from PIL import Image

from dptbd.evaluation.run import figures as run_figures
from dptbd.cli import main
from helpers.run_command import SMALL, leftovers


def test_refuses_to_overwrite_unless_forced(tmp_path, small, capsys):
    out = tmp_path / "r"
    args = ["run", "--no-progress", "--scenario", str(small), "--out", str(out)]
    assert main(args) == 0
    before = (out / "summary.json").read_bytes()
    capsys.readouterr()
    assert main(args) == 2
    assert capsys.readouterr().err == (f"dptbd run: error: --out {out} exists; pass --force to "
                                       f"replace it, or choose another folder\n")
    assert (out / "summary.json").read_bytes() == before
    assert main(args + ["--seed", "9", "--force"]) == 0
    assert json.loads((out / "summary.json").read_text())["scenario"]["scene"]["seed"] == 9
    assert leftovers(tmp_path) == ["r"]
    # --force never deletes a folder that dptbd run did not write
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "notes.txt").write_text("keep")
    assert main(["run", "--no-progress", "--scenario", str(small), "--out", str(mine),
                 "--force"]) == 2
    assert capsys.readouterr().err == (
        f"dptbd run: error: --out {mine} is not the folder of an earlier dptbd run (no "
        f"summary.json from it); --force will not replace it\n")
    assert (mine / "notes.txt").read_text() == "keep"


def _bad_inputs(inputs):
    """name -> (extra arguments, message fragment)."""
    rng = np.random.default_rng(0)
    cases = {}
    cases["missing file"] = (["--input", str(inputs / "nope.npy")], "does not exist")
    (inputs / "broken.npy").write_bytes(b"\x93NUMPY garbage")
    cases["unreadable file"] = (["--input", str(inputs / "broken.npy")], "damaged or truncated")
    (inputs / "text.npy").write_bytes(b"these are not frames\n")
    cases["not a .npy file"] = (["--input", str(inputs / "text.npy")],
                                "is not a NumPy .npy file")
    np.save(inputs / "objects.npy", np.array([{"a": 1}], dtype=object), allow_pickle=True)
    cases["object array"] = (["--input", str(inputs / "objects.npy")], "holds Python objects")
    snr = "(001's SNR = (target mean - noise mean) / sigma) must be a finite real number in (0, inf)"
    cases["negative --snr"] = (["--snr", "-1"], f"--snr {snr}, got -1.0\n")
    cases["zero --snr"] = (["--snr", "0"], f"--snr {snr}, got 0.0\n")
    cases["nan --snr"] = (["--snr", "nan"], f"--snr {snr}, got nan\n")
    cases["inf --snr"] = (["--snr", "inf"], f"--snr {snr}, got inf\n")
    cases["negative target SNR"] = (["--target", "20,4,0.2,0.9,-2"],
                                    f"--target '20,4,0.2,0.9,-2': SNR {snr}, got -2.0\n")
    (inputs / "snr.toml").write_text(SMALL.replace("snr = 5.0", "snr = -5.0"))
    cases["negative TOML snr"] = (["--scenario", str(inputs / "snr.toml")],
                                  "[scene] snr must be a finite real number in (0, inf), got -5.0\n")
    np.save(inputs / "empty.npy", np.zeros((0, 16, 16), np.uint8))
    cases["empty sequence"] = (["--input", str(inputs / "empty.npy")], "empty")
    np.save(inputs / "short.npy", rng.integers(0, 255, (3, 16, 16)).astype(np.uint8))
    cases["shorter than a segment"] = (["--input", str(inputs / "short.npy")],
                                       "shorter than one segment")
    np.save(inputs / "float.npy", rng.random((8, 16, 16)))
    cases["float data"] = (["--input", str(inputs / "float.npy")], "must be integers")
    sizes = inputs / "sizes"
    sizes.mkdir()
    Image.fromarray(np.zeros((16, 16), np.uint8)).save(sizes / "f0.png")
    Image.fromarray(np.zeros((16, 18), np.uint8)).save(sizes / "f1.png")
    cases["mixed sizes"] = (["--input", str(sizes)], "mixed sizes")
    depths = inputs / "depths"
    depths.mkdir()
    Image.fromarray(np.zeros((16, 16), np.uint8)).save(depths / "f0.png")
    Image.fromarray(np.zeros((16, 16), np.uint16)).save(depths / "f1.png")
    cases["mixed dtypes"] = (["--input", str(depths)], "mixed bit depths")
    (inputs / "nothing").mkdir()
    cases["empty folder"] = (["--input", str(inputs / "nothing")], "empty")
    (inputs / "unknown.toml").write_text(SMALL.replace("seed = 3", "seed = 3\ncolour = 1"))
    cases["unknown TOML key"] = (["--scenario", str(inputs / "unknown.toml")],
                                 "unknown key(s) ['colour'] in [scene]")
    (inputs / "assoc.toml").write_text(SMALL + "[association]\ngatee = 3\n")
    cases["unknown association key"] = (["--scenario", str(inputs / "assoc.toml")],
                                        "unknown key(s) ['gatee'] in [association]")
    (inputs / "range.toml").write_text(SMALL + "[association]\nmax_misses = 300\n")
    cases["value out of range"] = (["--scenario", str(inputs / "range.toml")],
                                   "max_misses must be an integer in [0, 255]")
    cases["seed with recorded data"] = (["--input", str(inputs / "short.npy"), "--seed", "1"],
                                        "--seed applies to a simulated scene")
    return cases


def test_bad_input_is_refused_by_name_and_leaves_nothing(tmp_path, capsys):
    inputs = tmp_path / "inputs"
    inputs.mkdir()
    for name, (extra, message) in _bad_inputs(inputs).items():
        out = tmp_path / "out"
        assert main(["run", "--no-progress", "--out", str(out)] + extra) == 2, name
        err = capsys.readouterr().err
        assert err.startswith("dptbd run: error:") and message in err, (name, err)
        assert "Traceback" not in err
        assert "pickled" not in err or name == "object array", (name, err)
        assert leftovers(tmp_path) == [], name


def test_a_failure_while_writing_leaves_no_folder(tmp_path, small, capsys, monkeypatch):
    def disk_full(*args, **kwargs):
        raise OSError(28, "No space left on device", str(tmp_path / "x.png"))

    monkeypatch.setattr(run_figures, "figure_tracks", disk_full)
    out = tmp_path / "r"
    assert main(["run", "--no-progress", "--scenario", str(small), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "No space left on device" in err and "Traceback" not in err
    assert leftovers(tmp_path) == []
    # and an existing run folder survives a failed --force run untouched
    monkeypatch.undo()
    assert main(["run", "--no-progress", "--scenario", str(small), "--out", str(out)]) == 0
    before = sorted(p.name for p in out.iterdir())
    monkeypatch.setattr(run_figures, "figure_tracks", disk_full)
    assert main(["run", "--no-progress", "--scenario", str(small), "--out", str(out),
                 "--force"]) == 2
    assert sorted(p.name for p in out.iterdir()) == before and leftovers(tmp_path) == ["r"]
