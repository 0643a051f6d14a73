"""The AXI4 state store's harness (:mod:`dptbd.sim.formal.harnesses.axi_store`) asserts every
rule it promises, on the small build; its proof runs in ``tests/sim/formal/test_runner.py``."""

import pytest

from helpers.refusals import whole

from dptbd.sim.formal.harnesses.axi_store import STORE_INVARIANTS, AxiStoreHarness, tiny_store
from dptbd.sim.formal.harnesses.prefetcher import (PREFETCHER_INVARIANTS, RING_INVARIANTS,
                                                   PrefetcherHarness)
from dptbd.sim.formal.harnesses.write_behind import (INVARIANTS, STAGED_INVARIANTS,
                                                      WriteBehindHarness)
from dptbd.sim.formal.tasks import ecp5_options


def test_the_small_store_build():
    store = tiny_store()
    cfg = store.frame
    assert (cfg.width, cfg.height, cfg.state_slot_bits) == (5, 4, 16)
    assert (store.data_bits, store.burst_beats, store.burst_bytes, store.outstanding,
            store.address_bits, store.frame_bytes) == (32, 2, 8, 2, 13, 40)


def test_the_ecp5_options_are_the_family_s_but_the_max_tree():
    from dptbd.hw.flow.family import ECP5

    options = ecp5_options()
    assert options == {**ECP5.options_for(tiny_store().frame), "max_tree": "compact"}
    assert options["state_store_style"] == "dp16kd"


def test_the_harness_asserts_the_manager_rules_of_the_axi4_port(messages):
    # asserted on AR, AW, W, states; assumed of the subordinate (R, B) and the pixel source
    channels = ("AR", "AW", "W", "states", "R", "B", "pixels")
    held = {f"{ch}: tvalid dropped before the handshake" for ch in channels}
    stable = {f"{ch}: payload changed while held" for ch in channels}
    bursts = {f"{ch}: {rule}" for ch in ("AR", "AW") for rule in (
        "burst crosses a 4 KB boundary", f"{ch}LEN above burst_beats - 1",
        "not an INCR burst of full beats", "address not aligned to the beat")}
    assert messages(AxiStoreHarness(drop=STORE_INVARIANTS)) == held | stable | bursts | {
        "W: strobe not all ones", "AR: more than 2 reads in flight",
        "W: a beat of a burst whose AW was not offered", "W: WLAST not on beat AWLEN + 1",
        "AW: more than 2 writes in flight", "R: a requested beat not taken at once", "B: BREADY low",
        "a valid in the first cycle after reset",
        "AW, W or states valid before any pixel was accepted",
        "states: more words out than pixels accepted"}


def test_the_induction_invariants_are_the_core_s_and_the_two_components(messages):
    reader = messages(PrefetcherHarness()) - messages(PrefetcherHarness(
        drop=PREFETCHER_INVARIANTS))
    writer = messages(WriteBehindHarness()) - messages(WriteBehindHarness(drop=INVARIANTS))
    core = {"InputCredit: not a thermometer code", "output FIFO level: not a thermometer code",
            "output flags level: not a thermometer code", "credit count != pixels in flight",
            "valid bits in the pipeline + words in the FIFO != pixels in flight",
            "the flags FIFO out of step with the state words'",
            "credit ready != room a cycle earlier",
            "pixels in flight before the first was accepted",
            "a state written before the first pixel"}
    assert messages(AxiStoreHarness()) - messages(AxiStoreHarness(drop=STORE_INVARIANTS)) == (
        core | reader | writer)


def test_the_ecp5_store_s_rules_are_the_same_and_its_invariants_its_components(messages):
    ecp5 = AxiStoreHarness(core_options=ecp5_options())
    rules = messages(AxiStoreHarness(core_options=ecp5_options(), drop=STORE_INVARIANTS))
    assert rules == messages(AxiStoreHarness(drop=STORE_INVARIANTS))
    reader = messages(PrefetcherHarness(style="dp16kd")) - messages(PrefetcherHarness(
        style="dp16kd", drop=RING_INVARIANTS))
    writer = messages(WriteBehindHarness(staged=True)) - messages(WriteBehindHarness(
        staged=True, drop=STAGED_INVARIANTS))
    generic = messages(AxiStoreHarness()) - rules
    core = generic - (messages(PrefetcherHarness()) | messages(WriteBehindHarness()))
    assert messages(ecp5) - rules == core | reader | writer


def test_the_ecp5_store_is_built_with_the_behavioural_dp16kd(cells):
    # the prefetcher's ring: 32 bits in two x18 DP16KDs; no Instance left for Yosys
    assert cells(AxiStoreHarness(core_options=ecp5_options())) == {"DP16KDModel": 2}


def test_an_unknown_invariant_group_is_refused():
    with pytest.raises(ValueError, match=whole("unknown invariant group(s) pipeline; the groups "
                                               "are core, reader, writer")):
        AxiStoreHarness(drop=("pipeline",))
