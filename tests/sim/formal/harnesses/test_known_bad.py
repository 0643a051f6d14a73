"""The known-bad harnesses (:mod:`dptbd.sim.formal.harnesses.known_bad`) carry the checks of the
good ones; ``tests/sim/formal/test_runner.py`` shows their proofs FAIL at the violation."""

from dptbd.sim.formal.harnesses.known_bad import (DroppingCandidatesHarness,
                                                  EagerAXILiteHarness)
from dptbd.sim.formal.harnesses.registers import RegistersHarness
from dptbd.sim.formal.harnesses.streams import CandidatesHarness


def test_the_known_bad_harnesses_keep_the_good_ones_checks(messages):
    # the dropping adapter has no list_start of its own: no invariant on it
    assert messages(DroppingCandidatesHarness()) == messages(CandidatesHarness()) - {
        "CandidatesToAxis: list_start disagrees with the open list"}
    assert messages(EagerAXILiteHarness()) == {
        m for m in messages(RegistersHarness()) if m.startswith("s_axil")}
