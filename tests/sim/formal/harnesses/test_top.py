"""The ``dptbd_axi`` harness (:mod:`dptbd.sim.formal.harnesses.top`) converts and asserts every
port's rules and the top's own; its bounded proof runs with ``pytest -m formal``."""

from dptbd.sim.formal.harnesses.top import AXITopHarness


def test_the_top_harness_asserts_every_port(messages):
    got = messages(AXITopHarness())
    assert {m for m in got if not m.startswith("s_axil")} == {
        f"{port}: {what}" for port in ("s_axis_video", "m_axis_cand", "m_axis_state")
        for what in ("tvalid dropped before the handshake", "payload changed while held")} | {
        "m_axis_cand: soft reset of the core with a packet open",
        "m_axis_state: soft reset of the core with a packet open",
        "m_axis_cand: tuser[0] not on exactly a list's first word",
        "an output word after aresetn before any pixel was accepted",
        "m_axis_state: a word without an accepted pixel"}
    assert "s_axil: write response without both AW and W accepted" in got
