"""The AXI4 state store's harness (:mod:`dptbd.sim.formal.harnesses.axi_store`) asserts every
rule it promises, on the small build; its proof runs in ``tests/sim/formal/test_runner.py``."""

from dptbd.sim.formal.harnesses.axi_store import AxiStoreHarness, tiny_store


def test_the_small_store_build():
    store = tiny_store()
    cfg = store.frame
    assert (cfg.width, cfg.height, cfg.state_slot_bits) == (5, 4, 16)
    assert (store.data_bits, store.burst_beats, store.burst_bytes, store.outstanding,
            store.address_bits, store.frame_bytes) == (32, 2, 8, 2, 13, 40)


def test_the_harness_asserts_the_manager_rules_of_the_axi4_port(messages):
    # asserted on AR, AW, W, states; assumed of the subordinate (R, B) and the pixel source
    channels = ("AR", "AW", "W", "states", "R", "B", "pixels")
    held = {f"{ch}: tvalid dropped before the handshake" for ch in channels}
    stable = {f"{ch}: payload changed while held" for ch in channels}
    bursts = {f"{ch}: {rule}" for ch in ("AR", "AW") for rule in (
        "burst crosses a 4 KB boundary", f"{ch}LEN above burst_beats - 1",
        "not an INCR burst of full beats", "address not aligned to the beat")}
    assert messages(AxiStoreHarness()) == held | stable | bursts | {
        "W: strobe not all ones", "AR: more than 2 reads in flight",
        "W: a beat of a burst whose AW was not offered", "W: WLAST not on beat AWLEN + 1",
        "AW: more than 2 writes in flight", "R: a requested beat not taken at once", "B: BREADY low",
        "a valid in the first cycle after reset",
        "AW, W or states valid before any pixel was accepted",
        "states: more words out than pixels accepted"}
