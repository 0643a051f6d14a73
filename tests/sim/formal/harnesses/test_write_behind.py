"""The write-behind's harness (:mod:`dptbd.sim.formal.harnesses.write_behind`) asserts the
write channels' rules and the invariants of its induction; its proof, and the failing
proofs without each invariant, run in ``tests/sim/formal/test_runner.py``."""

import pytest

from helpers.refusals import whole

from dptbd.sim.formal.harnesses.write_behind import (INVARIANTS, STAGED_INVARIANTS,
                                                      WriteBehindHarness)

RULES = {f"{ch}: {rule}" for ch in ("AW", "W", "B")       # B's rules assumed of the subordinate
         for rule in ("tvalid dropped before the handshake", "payload changed while held")} | {
    "AW: burst crosses a 4 KB boundary", "AW: AWLEN above burst_beats - 1",
    "AW: not an INCR burst of full beats", "AW: address not aligned to the beat",
    "W: strobe not all ones", "W: a beat of a burst whose AW was not offered",
    "W: WLAST not on beat AWLEN + 1", "AW: more than 2 writes in flight", "B: BREADY low",
    "a valid in the first cycle after reset", "AW or W valid before any write"}

FIFOS = {f"{fifo}: pointers disagree with the level"
         for fifo in ("w_fifo", "bursts", "lengths", "uptos")}


def test_the_harness_asserts_the_write_rules_and_the_invariants(messages):
    bursts = {f"bursts row {i} crosses its burst" for i in range(12)}  # the FIFO's 12 rows
    assert messages(WriteBehindHarness()) == RULES | FIFOS | bursts | {
        "in_flight != writes + AW held", "in_flight above outstanding",
        "a W burst done early without an AW held, or behind an open one",
        "lengths level != bursts with W open", "lengths row 0 != AWLEN of open burst 0",
        "lengths row 1 != AWLEN of open burst 1", "lengths row != the held AWLEN",
        "sent != the W beats of the open burst", "sent != 0 with no burst queued",
        "sent above the head's length", "writes != complete + AW with W open",
        "uptos level != in_flight", "bursts head crosses its burst",
        "open run reaches its burst's end", "open run does not end before the expected beat",
        "work queued before the first write"}


def test_without_every_invariant_only_the_rules_are_left(messages):
    assert messages(WriteBehindHarness(drop=INVARIANTS)) == RULES


def test_the_staged_harness_asserts_its_own_registers_meaning(messages):
    bursts = {f"bursts row {i} crosses its burst" for i in range(12)}
    assert messages(WriteBehindHarness(staged=True)) == RULES | bursts | {
        "room != room_next a cycle earlier",
        "lengths: pointers disagree with the level", "uptos: pointers disagree with the level",
        "bursts: pointers disagree with the level", "bursts: not a thermometer code",
        "in_flight != writes + AW held", "in_flight above outstanding",
        "a W burst done early without an AW held, or behind an open one",
        "lengths level != bursts with W open",
        "lengths row 0 != the AWLEN behind the burst under way",
        "lengths row 1 != the AWLEN behind the burst under way",
        "left + beats sent != the length of the burst under way",
        "WLAST register != no beat left", "beats sent with no burst under way",
        "writes != complete + AW with W open", "uptos level != in_flight",
        "bursts head crosses its burst", "staged descriptor crosses its burst",
        "open run reaches its burst's end", "open run does not end before the expected beat",
        "work queued before the first write"}
    assert messages(WriteBehindHarness(staged=True, drop=STAGED_INVARIANTS)) == RULES | {
        "room != room_next a cycle earlier"}


def test_an_unknown_invariant_is_refused():
    message = (f"unknown write-behind invariant(s) nope, zz; the invariants are "
               f"{', '.join(INVARIANTS)}")
    with pytest.raises(ValueError, match=whole(message)):
        WriteBehindHarness(drop=("zz", "nope"))


def test_an_unknown_staged_invariant_is_refused():
    message = (f"unknown write-behind invariant(s) sent; the invariants are "
               f"{', '.join(STAGED_INVARIANTS)}")
    with pytest.raises(ValueError, match=whole(message)):
        WriteBehindHarness(staged=True, drop=("sent",))
