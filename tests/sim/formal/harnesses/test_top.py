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


def test_the_ecp5_top_runs_the_dp16kd_histogram_through_the_behavioural_model(cells,
                                                                               messages):
    from dptbd.sim.formal.harnesses.tiny import tiny_config
    from dptbd.sim.formal.tasks import ecp5_options

    options = ecp5_options(tiny_config())
    assert options["histogram_style"] == "dp16kd"
    harness = AXITopHarness(core_options=options)
    # one DP16KD for the on-chip state store, one for the histogram
    assert cells(harness) == {"DP16KDModel": 2}
    generic_histogram = AXITopHarness(core_options={**options, "histogram_style": "memory"})
    assert cells(generic_histogram) == {"DP16KDModel": 1}
    assert cells(AXITopHarness(core_options={"control_style": "registered"})) == {}
    # the checks of dptbd_axi_registered (the ECP5 control and register read)
    registered = {"control_style": "registered", "register_read": "two_level"}
    assert messages(harness) == messages(AXITopHarness(core_options=registered))


def test_an_unknown_invariant_group_is_refused():
    message = (f"unknown dptbd_axi invariant group(s) nope; the groups are "
               f"{', '.join(TOP_INVARIANTS)}")
    with pytest.raises(ValueError, match=whole(message)):
        AXITopHarness(drop=("nope",))


def test_the_list_cover_harness_has_the_one_cover_and_its_environment():
    """``list_cover=True``: the three covers of the default run give way to the whole list's,
    and six assumptions more (reset only first, no AXI4-Lite request, both ``tready``, a
    pixel in every cycle, ``tuser`` and ``tlast`` at their places); the proof's assertions
    stay. (Its cover run: the ``dptbd_axi_list`` task, ``pytest -m formal``.)"""
    from amaranth.back import rtlil
    from amaranth.hdl import Fragment

    from dptbd.sim.formal.harnesses.tiny import tiny_config

    def flavors(harness):
        il = rtlil.convert(Fragment.get(harness, None), name="top", ports=harness.ports())
        return {kind: il.count(f'FLAVOR "{kind}"') for kind in ("assert", "assume", "cover")}

    plain = flavors(AXITopHarness(tiny_config(segment_frames=1)))
    listed = flavors(AXITopHarness(tiny_config(segment_frames=1), list_cover=True))
    assert plain["cover"] == 3 and listed["cover"] == 1
    assert listed["assume"] == plain["assume"] + 6 and listed["assert"] == plain["assert"]


@pytest.mark.parametrize("segment_frames, empty, record, trailer", [(2, 58, 78, 98),
                                                                    (1, 38, 43, 64)])
def test_a_whole_list_takes_two_segments(segment_frames, empty, record, trailer):
    """Why the cover run reaches no whole candidate list on ``m_axis_cand``: on the harness's
    5 x 4 build a run's first list is never primed (empty: a lone trailer), so the first
    list with a record ends after the second segment. ``aresetn`` low in cycle 0, a pixel
    offered in every cycle from 1 (1 at (0, 0) of each frame, else 0), both ``tready`` high: the
    cycles of the first lists' beats, exact, at K = 2 and on a K = 1 build."""
    from dptbd.hw.axi_top import AXITop
    from dptbd.sim.formal.harnesses.tiny import tiny_config
    from helpers.axil_harness import simulate_top

    cfg = tiny_config(segment_frames=segment_frames)
    top = AXITop(cfg, state_output=True)
    beats = []

    async def bench(ctx):
        ctx.set(top.m_axis_cand_tready, 1)
        ctx.set(top.m_axis_state_tready, 1)
        pixel = 0
        for cycle in range(trailer + 1):
            ctx.set(top.aresetn, cycle >= 1)
            first = pixel % (cfg.width * cfg.height) == 0
            ctx.set(top.s_axis_video_tvalid, cycle >= 1)
            ctx.set(top.s_axis_video_tdata, first)
            ctx.set(top.s_axis_video_tuser, first)
            ctx.set(top.s_axis_video_tlast, pixel % cfg.width == cfg.width - 1)
            if ctx.get(top.m_axis_cand_tvalid):
                beats.append((cycle, ctx.get(top.m_axis_cand_tuser),
                              ctx.get(top.m_axis_cand_tlast)))
            pixel += cycle >= 1 and ctx.get(top.s_axis_video_tready)
            await ctx.tick("sync")

    simulate_top(top, bench)
    assert beats == [(empty, 1, 1), (record, 1, 0), (trailer, 0, 1)]
