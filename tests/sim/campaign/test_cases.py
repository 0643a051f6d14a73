"""The campaign's cases (:mod:`dptbd.sim.campaign.cases`): the parameter sets, top levels and
faults the campaign promises (``docs/gateware.md``, "Verification campaign")."""

from __future__ import annotations

import collections
import pathlib
import re

from dptbd.sim.axi.runs import AXI_FAULTS
from dptbd.sim.campaign.cases import default_cases, x_store_cases


def test_default_cases_cover_what_the_campaign_promises():
    cases = default_cases()
    assert len({c.name for c in cases}) == len(cases) >= 8
    cfgs = [c.cfg for c in cases]
    assert any((c.width, c.height) == (128, 128) and c.segment_frames == 8 and c.input_bits == 12
               for c in cfgs)                                        # 001's setting
    assert any(c.width & (c.width - 1) and c.height & (c.height - 1) for c in cfgs)
    assert any(c.energy_bits < c.energy_bits_needed for c in cfgs)  # saturates
    assert {0, 8} <= {c.weight_frac_bits for c in cfgs}
    assert any(c.radius == 2 for c in cfgs)
    assert any(c.random_lut for c in cases)
    assert {"dp", "core", "segmenter", "axi", "dp_axi", "axi_store"} <= {c.design for c in cases}
    assert all(set(c.faults) >= {"reset", "misaligned_first", "short_frame", "long_frame", "lut",
                                 "settings"} for c in cases if c.design in ("dp", "core",
                                                                             "segmenter"))
    axi = [c for c in cases if c.design == "axi"]
    assert all(set(c.faults) == set(AXI_FAULTS) for c in axi)
    assert any((c.cfg.width, c.cfg.height, c.cfg.segment_frames) == (128, 128, 8) for c in axi)
    assert {1, 2} <= {c.cfg.radius for c in axi} and 0 in {c.cfg.weight_frac_bits for c in axi}
    assert any(0 < c.cfg.weight_frac_bits < 8 for c in axi)
    assert all(c.cfg.k_max > c.cfg.segment_frames for c in axi if c.cfg.width < 128)
    assert any("store_garbage" in c.faults for c in cases)
    assert sum(c.runs * c.words_per_run for c in cases if c.design != "segmenter") >= 10**8
    # dptbd_seg and dptbd_axi at P = 2 and 4 with the faults of P = 1; at P = 4 the
    # segmenter's scan stalls the input
    wide = {(c.design, c.cfg.pixels_per_clock): c for c in cases if c.cfg.pixels_per_clock > 1}
    assert set(wide) == {(d, p) for d in ("segmenter", "axi") for p in (2, 4)}
    assert all(set(c.faults) == set(cases[1].faults) for (d, _), c in wide.items()
               if d == "segmenter")
    assert all(set(c.faults) == set(AXI_FAULTS) for (d, _), c in wide.items() if d == "axi")
    four = wide["segmenter", 4].cfg
    assert (four.segment_frames - 1) * four.frame_beats < four.n_bins + 4


def test_the_store_checks_cover_both_inits_on_two_builds():
    cases = x_store_cases()
    assert len({n for n, _, _ in cases}) == len(cases) == 4
    assert {(c["radius"] if "radius" in c else 1, init) for _, c, init in cases} == {
        (1, "x"), (1, "random"), (2, "x"), (2, "random")}


_WORDS = ("zero one two three four five six seven eight nine ten eleven twelve thirteen "
          "fourteen fifteen sixteen seventeen eighteen nineteen twenty twenty-one twenty-two "
          "twenty-three twenty-four twenty-five twenty-six twenty-seven twenty-eight twenty-nine "
          "thirty").split()
_ROOT = pathlib.Path(__file__).resolve().parents[3]


def test_the_docs_state_the_campaigns_true_case_counts():
    """README.md and docs/gateware.md ("Verification campaign") state how many parameter
    sets ``dptbd verify`` runs, of which designs, and how many 4-state store checks: the
    numbers of :mod:`dptbd.sim.campaign.cases`; the table lists every case once; no other
    count of parameter sets is stated there (it would go stale)."""
    cases = default_cases()
    n = collections.Counter(c.design for c in cases)
    readme = (_ROOT / "README.md").read_text()
    gateware = (_ROOT / "docs" / "gateware.md").read_text()
    assert (f"{_WORDS[len(cases)]} parameter sets ({_WORDS[n['axi']]} of them the drop-in "
            f"`dptbd_axi`") in readme
    assert (f"{_WORDS[n['dp_axi']]} `dptbd_dp` and {_WORDS[n['axi_store']]} `dptbd_axi` with "
            f"the state store on AXI4") in readme
    assert f"runs {_WORDS[len(cases)]} parameter sets" in " ".join(gateware.split())
    assert f"Icarus' {_WORDS[len(x_store_cases())]} 4-state store" in gateware
    counts = re.compile(r"\b(" + "|".join(_WORDS) + r"|\d+) parameter sets")
    assert len(counts.findall(readme)) == 1 and len(counts.findall(gateware)) == 1
    section = gateware.split("### Verification campaign")[1].split("\n\n")
    table = next(block for block in section if block.startswith("| case |"))
    names = re.findall(r"^\| `([^`]+)`", table, flags=re.M)
    assert names[:-1] == [c.name for c in cases]      # the last row: the 4-state checks
