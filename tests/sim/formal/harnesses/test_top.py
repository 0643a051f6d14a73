"""The ``dptbd_axi`` harness (:mod:`dptbd.sim.formal.harnesses.top`) converts and asserts every
port's rules and the top's own, and the invariants of its induction; its proof, and the
failing proofs without each invariant, run in ``tests/sim/formal/test_runner.py``."""

import pytest

from helpers.refusals import whole

from dptbd.sim.formal.harnesses.top import TOP_INVARIANTS, AXITopHarness

RULES = {f"{port}: {what}" for port in ("s_axis_video", "m_axis_cand", "m_axis_state")
         for what in ("tvalid dropped before the handshake", "payload changed while held")} | {
    "m_axis_cand: soft reset of the core with a packet open",
    "m_axis_state: soft reset of the core with a packet open",
    "m_axis_cand: tuser[0] not on exactly a list's first word",
    "an output word after aresetn before any pixel was accepted",
    "m_axis_state: a word without an accepted pixel"}


def test_the_top_harness_asserts_every_port(messages):
    got = messages(AXITopHarness(drop=TOP_INVARIANTS))
    assert {m for m in got if not m.startswith("s_axil")} == RULES
    assert "s_axil: write response without both AW and W accepted" in got


def test_the_top_harness_asserts_the_invariants_of_its_induction(messages):
    got = messages(AXITopHarness()) - messages(AXITopHarness(drop=TOP_INVARIANTS))
    assert {"AW outstanding != held", "busy != bvalid | rvalid | the read being answered",
            "CandidatesToAxis: list_start disagrees with the open list",
            "StatesToAxis: line_open disagrees with the open line",
            "a word past the DP pipeline before the first pixel",
            "an output packet open before the first pixel",
            "pixels accepted - state words != DP words in flight + the one held",
            "DP: more words out than pixels accepted",
            "credit count != pixels in flight"} <= got


def test_an_unknown_invariant_group_is_refused():
    message = (f"unknown dptbd_axi invariant group(s) nope; the groups are "
               f"{', '.join(TOP_INVARIANTS)}")
    with pytest.raises(ValueError, match=whole(message)):
        AXITopHarness(drop=("nope",))
