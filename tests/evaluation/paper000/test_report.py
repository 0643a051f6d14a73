"""``dptbd.evaluation.paper000.report``: compare's paired statistics on 000's job."""

from __future__ import annotations

import numpy as np

from dptbd.evaluation.compare.report import paired_difference
from dptbd.evaluation.paper000.experiment import Paper000Spec, run_paper000
from dptbd.evaluation.paper000.report import markdown, summarise


def test_summary_is_compares_paired_difference_per_scene_and_the_tables_show_it():
    spec = Paper000Spec(engine="model", cases=("5.1 eq (15)",), seeds=4, gain=("DP eq (15)",),
                        gain_snrs_db=(6.0, 9.0), gain_trials=5, noise_trials=3, frames=5)
    res = run_paper000(spec, workers=1)
    s = summarise(res)
    fx, fl = (res.cases["5.1 eq (15)"][k]["noise_max"] for k in ("fixed", "float"))
    d = s["cases"]["5.1 eq (15)"]["noise_max"]
    assert (d["delta"], d["lo"], d["hi"]) == paired_difference(fx, fl, np.ones(4))
    row = s["gain"]["DP eq (15)"]["rows"][1]
    g = res.gain["DP eq (15)"]
    assert row["pd_fixed"] == g["fixed"][1].mean() and row["pd_float"] == g["float"][1].mean()
    assert row["delta"]["delta"] == paired_difference(g["fixed"][1].astype(float),
                                                      g["float"][1].astype(float), np.ones(5))[0]
    assert [l["level"] for l in s["gain"]["DP eq (15)"]["losses"]] == [0.5, 0.9]
    assert set(s["verdict"]) == {"5.1 eq (15)", "DP eq (15)"}
    text = markdown(s)
    assert "| 5.1 eq (15) | noise_max |" in text and "DP eq (15), 5 scenes per SNR:" in text
    assert s["rtl"] == {} and "state words compared" not in text
