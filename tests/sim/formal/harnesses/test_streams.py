"""The AXI4-Stream output adapters' harnesses (:mod:`dptbd.sim.formal.harnesses.streams`)
convert and assert what they promise; their proofs run in ``tests/sim/formal/test_runner.py``."""

from dptbd.sim.formal.harnesses.streams import CandidatesHarness, StatesHarness
from dptbd.sim.formal.harnesses.tiny import tiny_config


def test_the_candidates_harness_asserts_lists_and_the_stream_rules(messages):
    assert messages(CandidatesHarness(tiny_config())) == {
        "m_axis_cand: tvalid dropped before the handshake",
        "m_axis_cand: payload changed while held",
        "m_axis_cand: core reset with a list open",
        "m_axis_cand: tuser[0] not on exactly a list's first word",
        "CandidatesToAxis: list_start disagrees with the open list"}


def test_the_states_harness_asserts_lines_and_the_stream_rules(messages):
    assert messages(StatesHarness()) == {
        "m_axis_state: tvalid dropped before the handshake",
        "m_axis_state: payload changed while held",
        "m_axis_state: adapter reset with a line open",
        "m_axis_state: a filler word while not closing",
        "StatesToAxis: line_open disagrees with the open line"}
