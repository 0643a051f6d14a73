"""The harnesses of the flow control: the DP core's output path (:class:`CreditFifoHarness`:
the input credit, a pipeline and the thermometer FIFO; conservation, no overflow or
underflow, order) and the whole DP pipeline (:class:`PipelineHarness`: the states stream,
pixels in against words out)."""

from __future__ import annotations

from amaranth.hdl import Array, Assert, Cover, Mux, Signal

from dptbd.config import DPConfig
from dptbd.hw.dp_pipeline import DPPipeline
from dptbd.hw.input_credit import InputCredit
from dptbd.hw.thermometer_fifo import ThermometerFIFO
from dptbd.sim.formal.harness import Elaborated, Harness
from dptbd.sim.formal.harnesses.tiny import tiny_config
from dptbd.sim.formal.properties import axis_manager, axis_subordinate

__all__ = ["CreditFifoHarness", "ORDER_INVARIANTS", "PipelineHarness", "PIPELINE_INVARIANTS",
           "pipeline_valid_bits", "dp_core_invariants"]

#: The invariants of :class:`CreditFifoHarness`'s order proof, each a switch (``drop``) and
#: each needed: without any one its induction step fails
#: (``tests/sim/formal/test_runner.py``).
ORDER_INVARIANTS = ("sequence", "pointers", "rows")

#: The invariant groups of the DP core's flow control (:func:`dp_core_invariants`), each a
#: switch of :class:`PipelineHarness` (``drop``) and each needed by its proof.
PIPELINE_INVARIANTS = ("credit", "pipeline", "fifos", "flags", "idle")


def _count(flags):
    """Number of 1 bits of a thermometer code (its count)."""
    total = 0
    for bit in flags:
        total = total + bit
    return total


def _thermometer(m, flags, name: str) -> None:
    """Assert that ``flags`` is a thermometer code (``flags[k]`` implies ``flags[k - 1]``)."""
    for k in range(1, len(flags)):
        with m.If(flags[k]):
            m.d.comb += Assert(flags[k - 1], f"{name}: not a thermometer code")


class CreditFifoHarness(Harness):
    """The DP core's output path: :class:`~dptbd.hw.input_credit.InputCredit` in front of a
    pipeline of ``latency`` cycles (no stall) into a
    :class:`~dptbd.hw.thermometer_fifo.ThermometerFIFO` of ``depth`` words, as in
    :class:`~dptbd.hw.dp_core.DPCore` (depth = latency + 2 by default), the consumer's
    ``ready`` free. Each accepted word carries its sequence number.

    Asserted: a word leaving the pipeline always finds room (no overflow); the FIFO never
    offers a word it does not hold (no underflow); words accepted − words handed out ==
    words in flight <= depth; after a reset nothing is offered before a word is accepted;
    with ``order``: words come out in order (their sequence numbers), with the invariants
    that make it k-inductive (:meth:`order_invariants`) less those named in ``drop``
    (:data:`ORDER_INVARIANTS`; for the test that each is needed).
    """

    def __init__(self, latency: int = 2, depth: int | None = None, order: bool = False,
                 drop: tuple = ()):
        super().__init__()
        self.latency = latency
        self.depth = depth if depth is not None else latency + 2
        self.order = order
        unknown = sorted(set(drop) - set(ORDER_INVARIANTS))
        if unknown:
            raise ValueError(f"unknown order invariant(s) {', '.join(unknown)}; the "
                             f"invariants are {', '.join(ORDER_INVARIANTS)}")
        self.drop = tuple(drop)

    def check(self, m, past):
        seq_bits = 4
        credit = Elaborated(InputCredit(self.depth))
        fifo = Elaborated(ThermometerFIFO(seq_bits, self.depth))
        m.submodules.credit, m.submodules.fifo = credit.fragment, fifo.fragment
        c, f = credit.component, fifo.component
        valid, ready = self.free(1, "in_valid"), self.free(1, "out_ready")
        accept = valid & c.ready
        hand_out = f.r.valid & ready
        pipe_valid = [accept]
        seq_in, seq_out = Signal(seq_bits), Signal(seq_bits)
        pipe_data = [seq_in]
        for stage in range(self.latency):
            v, d = Signal(name=f"pipe{stage}_valid"), Signal(seq_bits, name=f"pipe{stage}_seq")
            m.d.sync += [v.eq(pipe_valid[-1]), d.eq(pipe_data[-1])]
            pipe_valid.append(v)
            pipe_data.append(d)
        with m.If(accept):
            m.d.sync += seq_in.eq(seq_in + 1)
        with m.If(hand_out):
            m.d.sync += seq_out.eq(seq_out + 1)
        m.d.comb += [f.w.valid.eq(pipe_valid[-1]), f.w.payload.eq(pipe_data[-1]),
                     f.r.ready.eq(ready), c.accept.eq(accept), c.handed_out.eq(hand_out)]
        # conservation
        in_flight = Signal(range(2 * self.depth + 2))
        m.d.sync += in_flight.eq(in_flight + accept - hand_out)
        stored = Signal(range(2 * self.depth + 2))       # written to the FIFO, not handed out
        m.d.sync += stored.eq(stored + (f.w.valid & f.w.ready) - hand_out)
        piped = _count(pipe_valid[1:])
        started = Signal()                               # a word accepted since the reset
        with m.If(accept):
            m.d.sync += started.eq(1)
        with m.If(f.w.valid):
            m.d.comb += Assert(f.w.ready, "FIFO overflow: a word left the pipeline without room")
        with m.If(f.r.valid):
            m.d.comb += Assert(stored != 0, "FIFO underflow: a word offered that it does not hold")
        with m.If(~started):
            m.d.comb += Assert(~f.r.valid, "an output word before any input was accepted")
        m.d.comb += [
            Assert(in_flight == piped + stored, "accepted - handed out != words in flight"),
            Assert(in_flight <= self.depth, "more words in flight than the FIFO holds"),
        ]
        if self.order:
            with m.If(f.r.valid):
                m.d.comb += Assert(f.r.payload == seq_out, "FIFO output out of order")
            self.order_invariants(m, fifo, seq_in, seq_out, in_flight)
        # invariants of the thermometer counters (what k-induction needs)
        committed = credit.sub("committed").component.at_least
        level = fifo.sub("level").component.at_least
        _thermometer(m, committed, "InputCredit")
        _thermometer(m, level, "ThermometerFIFO level")
        m.d.comb += [
            Assert(_count(committed) == in_flight, "credit count != words in flight"),
            Assert(_count(level) + f.r.valid == stored, "FIFO level != words stored"),
            Assert(c.ready == (past(_count(committed) < self.depth - 1, "past_room") & ~past.rst),
                   "credit ready != room a cycle earlier"),
        ]
        m.d.comb += [
            Cover(in_flight == self.depth),
            Cover(hand_out & (seq_out == 3)),
            Cover(valid & ~c.ready & started),
        ]

    def order_invariants(self, m, fifo: Elaborated, seq_in, seq_out, in_flight) -> None:
        """Assert where each word in flight is in the sequence, less the groups in ``drop``
        (the pipeline's stages need none: a word in them at the start of an induction of
        length 4 has left them, in order, by its last step):

        - ``sequence``: the next number in − the next number out = words in flight;
        - ``pointers``: the FIFO's pointers are within its memory, the write pointer = the
          read pointer + the memory's level (modulo its words);
        - ``rows``: the memory's i-th word from the read pointer, i < its level, holds the
          next number out + ``r.valid`` + i.
        """
        bits = len(seq_in)
        f = fifo.component
        words = self.depth - 1
        level = _count(fifo.sub("level").component.at_least)
        produce, consume = fifo.signal("produce"), fifo.signal("consume")
        asserts = []
        if "sequence" not in self.drop:
            asserts.append(Assert((seq_in - seq_out)[:bits] == in_flight,
                                  "sequence numbers in - out != words in flight"))
        if "pointers" not in self.drop:
            wrapped = Mux(consume + level >= words, consume + level - words, consume + level)
            asserts.append(Assert((produce < words) & (consume < words) & (produce == wrapped),
                                  "FIFO pointers outside its memory or != read + level"))
        if "rows" not in self.drop:
            rows = fifo.rows("storage")
            for i in range(words):
                at = Mux(consume + i >= words, consume + i - words, consume + i)
                with m.If(i < level):
                    m.d.comb += Assert(Array(rows)[at] == (seq_out + f.r.valid + i)[:bits],
                                       f"FIFO word {i} from the read pointer out of sequence")
        m.d.comb += asserts


class PipelineHarness(Harness):
    """:class:`~dptbd.hw.dp_pipeline.DPPipeline` on the tiny build: any pixel stream (the
    stream rules assumed), any consumer, any run-time K; no LUT write (the flow control
    does not depend on the weights; their writes only make the solver slower).

    Asserted: the ``states`` stream keeps the stream rules; never more state words out than
    pixels accepted; pixels accepted − state words out <= the output FIFO's depth (the
    credit); nothing offered after a reset before a pixel is accepted; and the invariants
    of the DP core's flow control (:func:`dp_core_invariants`) that make it k-inductive,
    less those named in ``drop`` (:data:`PIPELINE_INVARIANTS`; for the test that each is
    needed).
    """

    def __init__(self, cfg: DPConfig | None = None, drop: tuple = ()):
        super().__init__()
        self.cfg = cfg or tiny_config()
        unknown = sorted(set(drop) - set(PIPELINE_INVARIANTS))
        if unknown:
            raise ValueError(f"unknown pipeline invariant(s) {', '.join(unknown)}; the "
                             f"invariants are {', '.join(PIPELINE_INVARIANTS)}")
        self.drop = tuple(drop)

    def check(self, m, past):
        top = Elaborated(DPPipeline(self.cfg))
        m.submodules.dut = top.fragment
        dut = top.component
        self.free_inputs(m, dut, "dut", skip=("lut_addr", "lut_data", "lut_we"))
        src, out = dut.pixels, dut.states
        axis_subordinate(m, past, tvalid=src.valid, tready=src.ready,
                         payload=[src.payload.as_value()], name="pixels")
        axis_manager(m, past, tvalid=out.valid, tready=out.ready,
                     payload=[out.payload.as_value()], name="states")
        accepted = src.valid & src.ready
        taken = out.valid & out.ready
        in_flight = Signal(range(-4, 2 * dut.output_fifo_depth + 4))
        m.d.sync += in_flight.eq(in_flight + accepted - taken)
        started = Signal()
        with m.If(accepted):
            m.d.sync += started.eq(1)
        m.d.comb += [
            Assert(in_flight >= 0, "states: more words out than pixels accepted"),
            Assert(in_flight <= dut.output_fifo_depth,
                   "states: more pixels in flight than the output FIFO holds"),
        ]
        with m.If(~started):
            m.d.comb += Assert(~out.valid, "states: a word before any pixel was accepted")
        with m.If(taken):
            m.d.comb += Assert(in_flight > 0, "states: a word without an accepted pixel")
        dp_core_invariants(m, past, top.sub("core"), in_flight, started, drop=self.drop)
        m.d.comb += [Cover(taken & (in_flight == 1) & started),
                     Cover(in_flight == dut.output_fifo_depth)]


def pipeline_valid_bits(core: Elaborated) -> list:
    """The valid bits of a pixel on its way through :class:`~dptbd.hw.dp_core.DPCore`
    (``core``, elaborated), from the controller's (the cycle after its acceptance) through
    the side-band's registers (bit 0 of each, or the valid bit's own registers when the rest
    of the side-band is delayed in memory: ``sideband_delay="memory"``) to the state stage's,
    whose word enters the output FIFO."""
    chain = [core.sub("controller").signal("valid")]
    try:
        core.signal("sideband_valid_d1")
        base = "sideband_valid"
    except KeyError:
        base = "sideband"
    stage = 1
    while True:
        try:
            chain.append(core.signal(f"{base}_d{stage}")[0])
        except KeyError:
            break
        stage += 1
    chain.append(core.signal("sideband_state_d1")[0])
    return chain


def dp_core_invariants(m, past, core: Elaborated, in_flight, started, drop: tuple = (),
                       was_reset=None) -> None:
    """Assert what :class:`~dptbd.hw.dp_core.DPCore`'s flow control holds (``core``,
    elaborated), in terms of the harness's pixels accepted − words taken (``in_flight``) and
    "a pixel accepted since the reset" (``started``), as :class:`CreditFifoHarness` proves
    them on the output path alone, less the groups named in ``drop``
    (:data:`PIPELINE_INVARIANTS`):

    - ``credit``: the input credit counts ``in_flight`` and is a thermometer code;
    - ``pipeline``: the valid bits of the pipeline (the controller's, the side-band's
      registers, the state stage's) plus the output FIFO's words are ``in_flight``;
    - ``fifos``: the output FIFO's level is a thermometer code;
    - ``flags``: the flags' FIFO holds as many words as the state words' (its level a
      thermometer code, its ``r.valid`` the same);
    - ``idle``: nothing is in flight before the first pixel.

    Always asserted, though no induction here needs it: the credit's ``ready`` is its room
    of the cycle before, unless that cycle reset the core (``was_reset``: by default the
    harness's reset, ``past.rst``)."""
    depth = core.component.output_fifo_depth
    was_reset = past.rst if was_reset is None else was_reset
    chain = pipeline_valid_bits(core)
    committed = core.sub("input_credit").sub("committed").component.at_least
    fifo, flags = core.sub("output_fifo"), core.sub("output_flags")
    level = fifo.sub("level").component.at_least
    flag_level = flags.sub("level").component.at_least
    stored = _count(level) + fifo.component.r.valid
    if "credit" not in drop:
        _thermometer(m, committed, "InputCredit")
        m.d.comb += Assert(_count(committed) == in_flight, "credit count != pixels in flight")
    m.d.comb += Assert(core.component.pixels.ready == (past(_count(committed) < depth - 1,
                                                            "past_room") & ~was_reset),
                       "credit ready != room a cycle earlier")
    if "pipeline" not in drop:
        m.d.comb += Assert(_count(chain) + stored == in_flight,
                           "valid bits in the pipeline + words in the FIFO != pixels in flight")
    if "fifos" not in drop:
        _thermometer(m, level, "output FIFO level")
    if "flags" not in drop:
        _thermometer(m, flag_level, "output flags level")
        m.d.comb += Assert((_count(flag_level) == _count(level))
                           & (flags.component.r.valid == fifo.component.r.valid),
                           "the flags FIFO out of step with the state words'")
    if "idle" not in drop:
        with m.If(~started):
            m.d.comb += Assert(in_flight == 0, "pixels in flight before the first was accepted")
