"""The flow-control harnesses (:mod:`dptbd.sim.formal.harnesses.flow`) convert and assert what
they promise; their proofs run in ``tests/sim/formal/test_runner.py``."""

import pytest

from helpers.refusals import whole

from dptbd.sim.formal.harnesses.flow import (ORDER_INVARIANTS, PIPELINE_INVARIANTS,
                                             CreditFifoHarness, PipelineHarness)
from dptbd.sim.formal.harnesses.tiny import tiny_config

CREDIT_FIFO = {
    "FIFO overflow: a word left the pipeline without room",
    "FIFO underflow: a word offered that it does not hold",
    "an output word before any input was accepted",
    "accepted - handed out != words in flight", "more words in flight than the FIFO holds",
    "InputCredit: not a thermometer code", "ThermometerFIFO level: not a thermometer code",
    "credit count != words in flight", "FIFO level != words stored",
    "credit ready != room a cycle earlier"}


ORDER = {"FIFO output out of order", "sequence numbers in - out != words in flight",
         "FIFO pointers outside its memory or != read + level",
         "FIFO word 0 from the read pointer out of sequence",
         "FIFO word 1 from the read pointer out of sequence",
         "FIFO word 2 from the read pointer out of sequence"}


def test_the_credit_fifo_harness_asserts_conservation_and_with_order_the_order(messages):
    harness = CreditFifoHarness()
    assert (harness.latency, harness.depth) == (2, 4)
    assert messages(harness) == CREDIT_FIFO
    assert messages(CreditFifoHarness(order=True)) == CREDIT_FIFO | ORDER
    assert messages(CreditFifoHarness(order=True, drop=ORDER_INVARIANTS)) == (
        CREDIT_FIFO | {"FIFO output out of order"})


def test_an_unknown_order_invariant_is_refused():
    message = (f"unknown order invariant(s) nope, zz; the invariants are "
               f"{', '.join(ORDER_INVARIANTS)}")
    with pytest.raises(ValueError, match=whole(message)):
        CreditFifoHarness(order=True, drop=("zz", "nope"))


PIPELINE = {
    "pixels: tvalid dropped before the handshake", "pixels: payload changed while held",
    "states: tvalid dropped before the handshake", "states: payload changed while held",
    "states: more words out than pixels accepted",
    "states: more pixels in flight than the output FIFO holds",
    "states: a word before any pixel was accepted", "states: a word without an accepted pixel",
    "credit ready != room a cycle earlier"}


def test_the_pipeline_harness_asserts_pixels_in_against_words_out_and_the_invariants(messages):
    assert messages(PipelineHarness(drop=PIPELINE_INVARIANTS)) == PIPELINE
    assert messages(PipelineHarness()) == PIPELINE | {
        "InputCredit: not a thermometer code", "credit count != pixels in flight",
        "valid bits in the pipeline + words in the FIFO != pixels in flight",
        "output FIFO level: not a thermometer code", "output flags level: not a thermometer code",
        "the flags FIFO out of step with the state words'",
        "pixels in flight before the first was accepted"}


def test_an_unknown_pipeline_invariant_is_refused():
    message = (f"unknown pipeline invariant(s) zz; the invariants are "
               f"{', '.join(PIPELINE_INVARIANTS)}")
    with pytest.raises(ValueError, match=whole(message)):
        PipelineHarness(drop=("zz",))


@pytest.mark.parametrize("sideband_delay", ["registers", "memory"])
def test_the_pipeline_valid_bits_are_one_a_cycle_from_acceptance_to_the_fifo(sideband_delay):
    from dptbd.hw.dp_core import DPCore
    from dptbd.hw.schedule import check_supported
    from dptbd.sim.formal.harness import Elaborated
    from dptbd.sim.formal.harnesses.flow import pipeline_valid_bits

    cfg = tiny_config(energy_bits=10)
    core = Elaborated(DPCore(cfg, sideband_delay=sideband_delay))
    bits = pipeline_valid_bits(core)
    # the write to the store and the FIFO comes write_latency cycles after the acceptance,
    # one valid register per cycle
    assert len(bits) == check_supported(cfg).write_latency
    assert all(len(b) == 1 for b in bits)
