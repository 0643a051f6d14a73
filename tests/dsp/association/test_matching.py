"""The matching of the tracker (``dptbd.dsp.association.matching``): heading cost, link gate."""

from dptbd.dsp.association import ONE
from helpers.candidate_lists import cand, records, tracker


def test_heading_agreement_picks_the_candidate_moving_like_the_track():
    """Two candidates equally far from the prediction: the one heading the same way wins;
    with ``reject_reversed`` one heading backwards is never taken (001 §2: targets do not
    retreat), by default it only costs more (001 §3 ranks by heading, it does not gate)."""
    tr = tracker()
    for s in range(3):
        tr.step(records([cand(30, 10 + 6 * s, row0=30, col0=10 + 6 * s - 5)]))
    # predicted (30, 28): candidates 2 px above and below it, one moving right, one left
    tr.step(records([cand(28, 28, row0=28, col0=33), cand(32, 28, row0=32, col0=23)]))
    rec = tr.tracks[tr.tracks["id"] == 1][0]
    assert rec["p_row"][1] == 32 * ONE
    for reject, hits in ((True, 3), (False, 4)):
        tr2 = tracker(reject_reversed=reject)
        for s in range(3):
            tr2.step(records([cand(30, 10 + 6 * s, row0=30, col0=10 + 6 * s - 5)]))
        tr2.step(records([cand(30, 28, row0=30, col0=33)]))   # on the prediction but reversed
        rec2 = tr2.tracks[tr2.tracks["id"] == 1][0]
        assert rec2["hits"] == hits and rec2["misses"] == (1 if reject else 0)


def test_link_gate_follows_a_turn_the_prediction_missed():
    """Off by default; with ``link_gate`` a candidate outside the prediction gate whose DP
    path starts at the track's newest point (the target turned) extends the track."""
    def run(**kw):
        tr = tracker(**kw)
        for s in range(4):
            tr.step(records([cand(30, 10 + 6 * s, row0=30, col0=10 + 6 * s - 5)]))
        # predicted (30, 34); the target turned down: path from (30, 28) to (36, 31)
        tr.step(records([cand(36, 31, row0=30, col0=28)]))
        return tr.tracks[tr.tracks["id"] == 1][0]

    assert run()["misses"] == 1
    rec = run(link_gate=2.0)
    assert rec["misses"] == 0 and rec["hits"] == 5 and rec["p_row"][1] == 36 * ONE
