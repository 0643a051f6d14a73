"""``dptbd run --dsp c``: the DSP stage on the C firmware gives the Python model's tables,
tracks and figures bit for bit; a missing compiler and an unknown ``--dsp`` refused."""

import json
import re

import pytest

from dptbd.cli import main
from helpers.run_command import leftovers


def test_dsp_c_writes_the_same_tables_tracks_and_figures(tmp_path, small, capsys):
    """The C firmware gives the Python model's tracks bit for bit: every file but the
    summary's ``dsp`` key and its time is the same, and so is what is printed."""
    outs = {}
    for dsp in ("python", "c"):
        outs[dsp] = tmp_path / dsp
        assert main(["run", "--no-progress", "--scenario", str(small), "--dsp", dsp,
                     "--out", str(outs[dsp])]) == 0
        outs[dsp + "-printed"] = capsys.readouterr().out
    py, c = outs["python"], outs["c"]
    assert sorted(p.name for p in py.iterdir()) == sorted(p.name for p in c.iterdir())
    for path in py.iterdir():
        if path.name != "summary.json":
            assert path.read_bytes() == (c / path.name).read_bytes(), path.name
    summary_py, summary_c = (json.loads((o / "summary.json").read_text()) for o in (py, c))
    assert "dsp" not in summary_py and summary_c.pop("dsp") == "c"
    for s in (summary_py, summary_c):
        s.pop("seconds")
    assert summary_py == summary_c
    printed_py, printed_c = (re.sub(r"(in |\()\d+\.\d s", r"\1T s", outs[k + "-printed"])
                             .replace(str(outs[k]), "OUT") for k in ("python", "c"))
    assert printed_c == printed_py.replace("  DSP stage:", "  DSP stage (C firmware):")


def test_dsp_c_without_a_compiler_is_refused_before_any_work(tmp_path, small, capsys,
                                                             monkeypatch):
    monkeypatch.setenv("CC", "no-such-cc")
    assert main(["run", "--no-progress", "--scenario", str(small), "--dsp", "c",
                 "--out", str(tmp_path / "r")]) == 2
    captured = capsys.readouterr()
    assert captured.err == (
        "dptbd run: error: --dsp c: no C compiler: 'no-such-cc' ($CC) is not on PATH; the DSP "
        "firmware needs one (Debian: apt-get install gcc, or clang; or set CC to a compiler)\n")
    assert captured.out == "" and leftovers(tmp_path) == []


def test_dsp_value_is_refused_by_the_command_line(tmp_path, small, capsys):
    with pytest.raises(SystemExit) as exc:
        main(["run", "--scenario", str(small), "--dsp", "asm", "--out", str(tmp_path / "r")])
    assert exc.value.code == 2
    assert ("argument --dsp: invalid choice: 'asm' (choose from 'python', 'c')"
            in capsys.readouterr().err)
