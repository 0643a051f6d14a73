"""The coverage build option of :mod:`dptbd.sim.verilator.cache`: a key and a directory of
its own, the plain build's key, flags and text unchanged; the runners refuse a coverage
file for a plain build (before running anything)."""

from __future__ import annotations

import hashlib
import json

import numpy as np
import pytest
from helpers.refusals import whole
from helpers.verilator_harness import HAVE_VERILATOR

from dptbd.config import DPConfig
from dptbd.sim import verilator as V
from dptbd.sim.verilator import cache as B
from dptbd.sim.verilator import toolchain as T

CFG = DPConfig(width=8, height=6, segment_frames=2, candidate_count=2, histogram_bits=4)


@pytest.mark.skipif(not HAVE_VERILATOR, reason="needs Verilator and a C++ compiler")
def test_the_coverage_key_differs_and_the_plain_key_is_unchanged():
    from dptbd.hw.flow.source_hash import gateware_hash

    plain = B._build_key(CFG, "segmenter", "auto", False)
    assert B._build_key(CFG, "segmenter", "auto", False, coverage=False) == plain
    assert B._build_key(CFG, "segmenter", "auto", False, coverage=True) != plain
    # the plain key is the hash of what it hashed before the option existed
    blob = json.dumps({
        "config": CFG.to_mapping(), "design": "segmenter", "lut_style": "auto",
        "waves": False, "gateware": gateware_hash(),
        "harness": hashlib.sha256(b"".join(
            p.read_bytes() for p in T.harness_sources("segmenter"))).hexdigest(),
        "verilator_flags": B.VERILATOR_FLAGS, "cxx_flags": B.CXX_FLAGS,
        "tools": B.check_tools()}, sort_keys=True)
    assert plain == hashlib.sha256(blob.encode()).hexdigest()
    assert not set(B.COVERAGE_FLAGS) & set(B.VERILATOR_FLAGS)
    tools = B.check_tools()
    assert T.runtime_dir(B.default_build_root(), tools, False, True) != \
        T.runtime_dir(B.default_build_root(), tools, False)


def test_the_plain_text_has_no_processes_and_the_coverage_text_has_them():
    text, _ = B._generate(CFG, "segmenter", "auto")
    covered, manifest = B._generate(CFG, "segmenter", "auto", coverage=True)
    assert "always @*" not in text and "(* src" not in text
    assert "always @*" in covered and "dptbd_cases" in covered
    assert manifest == B._generate(CFG, "segmenter", "auto")[1]


def fake(tmp_path, design):
    return V.VerilatorBuild(CFG, design, tmp_path, tmp_path / "missing-executable",
                            {"latency": 14}, "0" * 64, 0.0, True, False)


def test_runners_refuse_a_coverage_file_for_a_plain_build(tmp_path):
    from dptbd.sim.axi.stimulus import Beats
    from dptbd.sim.verilator.axi import run_axi

    message = whole("coverage needs a build made with coverage=True")
    with pytest.raises(ValueError, match=message):
        V.run(fake(tmp_path, "segmenter"), np.zeros(4, dtype=np.uint64),
              coverage=tmp_path / "x.dat")
    beats = Beats(np.zeros(2, dtype=np.int64), np.zeros(2, dtype=bool), np.zeros(2, dtype=bool))
    with pytest.raises(ValueError, match=message):
        run_axi(fake(tmp_path, "axi"), beats, [], coverage=tmp_path / "x.dat")
