"""The prefetcher's harness (:mod:`dptbd.sim.formal.harnesses.prefetcher`) asserts the read
channels' rules and the invariants of its induction; its proof, and the failing proofs
without each invariant, run in ``tests/sim/formal/test_runner.py``."""

import pytest

from helpers.refusals import whole

from dptbd.sim.formal.harnesses.prefetcher import (PREFETCHER_INVARIANTS, RING_INVARIANTS,
                                                   PrefetcherHarness)

RULES = {f"{ch}: {rule}" for ch in ("AR", "R")           # R's rules assumed of the subordinate
         for rule in ("tvalid dropped before the handshake", "payload changed while held")} | {
    "AR: burst crosses a 4 KB boundary", "AR: ARLEN above burst_beats - 1",
    "AR: not an INCR burst of full beats", "AR: address not aligned to the beat",
    "AR: more than 2 reads in flight", "R: a requested beat not taken at once",
    "a valid in the first cycle after reset"}


def test_the_harness_asserts_the_read_rules_and_the_invariants(messages):
    assert messages(PrefetcherHarness()) == RULES | {
        "in_flight != reads in flight", "reads in flight + the AR held above outstanding",
        "read 0 in flight longer than a burst", "read 1 in flight longer than a burst",
        "beats received with no read in flight",
        "beats received beyond the head burst's length",
        "fifo: pointers disagree with the level", "reserved != beats requested and not popped",
        "reserved above the FIFO's depth", "next_beat beyond the frame",
        "next_beat not a block's start", "length != the next burst's beats"}


def test_without_every_invariant_only_the_rules_are_left(messages):
    assert messages(PrefetcherHarness(drop=PREFETCHER_INVARIANTS)) == RULES


def test_the_dp16kd_harness_asserts_its_ring_queue_and_registered_issue(messages):
    assert messages(PrefetcherHarness(style="dp16kd")) == RULES | {
        "available != available_next a cycle earlier",
        "in_flight != reads in flight", "reads in flight + the AR held above outstanding",
        "read 0 in flight longer than a burst", "read 1 in flight longer than a burst",
        "beats received with no read in flight",
        "beats received beyond the head burst's length",
        "reserved != beats requested and not popped", "reserved above the FIFO's depth",
        "next_beat beyond the frame", "next_beat not a block's start",
        "length != the next burst's beats",
        "ring: pointers disagree with the count", "ring: not empty != count != 0",
        "ring: not full != count != depth", "queue: pointers disagree with the level",
        "queue: head beat != level != 0",
        "queue: credit + beats on their way + level != its beats",
        "queue: credit left != credit != 0", "fresh != no stale beat",
        "length_less != length - 1", "following_beat != the beat after the next burst"}
    assert messages(PrefetcherHarness(style="dp16kd", drop=RING_INVARIANTS)) == RULES | {
        "available != available_next a cycle earlier"}


def test_an_unknown_invariant_is_refused():
    message = (f"unknown prefetcher invariant(s) nope; the invariants are "
               f"{', '.join(PREFETCHER_INVARIANTS)}")
    with pytest.raises(ValueError, match=whole(message)):
        PrefetcherHarness(drop=("nope",))


def test_an_unknown_dp16kd_invariant_is_refused():
    message = (f"unknown prefetcher invariant(s) fifo; the invariants are "
               f"{', '.join(RING_INVARIANTS)}")
    with pytest.raises(ValueError, match=whole(message)):
        PrefetcherHarness(style="dp16kd", drop=("fifo",))
