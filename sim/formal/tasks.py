"""The formal tasks that ``dptbd verify --formal`` runs: one harness each
(:mod:`dptbd.sim.formal.harnesses`), its proof mode and depth, its cover depth.

``fast`` tasks run in the default test suite (seconds each); the others only with
``pytest -m formal`` and in ``dptbd verify --formal``. ``expect`` is the proof's verdict
that counts as a success: ``"FAIL"`` for the known-bad harness, which shows that the checks
detect the violation they are written for.
"""

from __future__ import annotations

import dataclasses
from typing import Callable

from dptbd.config import DPConfig
from dptbd.sim.formal.harness import Harness
from dptbd.sim.formal.harnesses.axi_store import AxiStoreHarness
from dptbd.sim.formal.harnesses.flow import CreditFifoHarness, PipelineHarness
from dptbd.sim.formal.harnesses.prefetcher import PrefetcherHarness
from dptbd.sim.formal.harnesses.known_bad import (DoubleQueuedWriteBehindHarness,
                                                   DroppingCandidatesHarness, EagerAXILiteHarness)
from dptbd.sim.formal.harnesses.registers import RegistersHarness
from dptbd.sim.formal.harnesses.streams import CandidatesHarness, StatesHarness
from dptbd.sim.formal.harnesses.tiny import tiny_config
from dptbd.sim.formal.harnesses.top import AXITopHarness
from dptbd.sim.formal.harnesses.write_behind import WriteBehindHarness

__all__ = ["FormalTask", "TASKS", "task", "ecp5_options"]


def ecp5_options(cfg: DPConfig | None = None) -> dict:
    """The ECP5 family's implementation options for a proof's build ``cfg`` (default: the
    store proofs' frame, :func:`~dptbd.sim.formal.harnesses.axi_store.tiny_store`'s;
    :meth:`~dptbd.hw.flow.family.Family.options_for`) but its max/argmax tree, which stays
    ``"compact"``: the ``"split"`` tree's cycle more of write latency does not fit the
    5 x 4 frame's read-ahead (a refusal of the schedule), and the tree has no part in the
    flow control."""
    from dptbd.hw.flow.family import ECP5
    from dptbd.sim.formal.harnesses.axi_store import tiny_store

    return {**ECP5.options_for(cfg or tiny_store().frame), "max_tree": "compact"}


@dataclasses.dataclass(frozen=True)
class FormalTask:
    """One proof: ``mode`` ``"prove"`` (k-induction of length ``depth``, which also checks
    the base case to that depth) or ``"bmc"`` (every state reachable in ``depth`` steps from
    reset); ``cover_depth`` 0 runs no cover; ``cover_syn`` runs the cover on the gate-level
    netlist (:func:`~dptbd.sim.formal.runner.sby_text`)."""

    name: str
    description: str
    build: Callable[[], Harness]
    mode: str
    depth: int
    cover_depth: int
    fast: bool = True
    expect: str = "PASS"
    cover_syn: bool = False


TASKS = (
    FormalTask("m_axis_cand", "CandidatesToAxis: AXI4-Stream manager, lists end with tlast, "
               "soft reset", CandidatesHarness, "prove", 4, 12),
    FormalTask("m_axis_state", "StatesToAxis: AXI4-Stream manager, lines closed before the "
               "core's soft reset", StatesHarness, "prove", 4, 12),
    FormalTask("credit_fifo", "InputCredit + pipeline + ThermometerFIFO: conservation, no "
               "overflow or underflow", CreditFifoHarness, "prove", 4, 12),
    FormalTask("credit_fifo_order", "the same: words leave in order",
               lambda: CreditFifoHarness(order=True), "prove", 4, 0),
    FormalTask("s_axil_registers", "AXI4-Lite subordinate, refused writes, W1C bits",
               RegistersHarness, "prove", 4, 12),
    FormalTask("s_axil_registers_bytes", "the same with the range check by bytes and the "
               "refusal registered (the ECP5 build's, bounds_registered, refusal_registered)",
               lambda: RegistersHarness(bounds_registered=True), "prove", 4, 0),
    FormalTask("dp_pipeline", "DPPipeline 5x4: states stream, pixels in - words out",
               PipelineHarness, "prove", 4, 20, fast=False),
    FormalTask("dp_pipeline_short", "the same proof without its cover run (the default "
               "suite's)", PipelineHarness, "prove", 4, 0),
    FormalTask("dptbd_axi", "dptbd_axi 5x4 with m_axis_state: every port, soft reset over "
               "AXI4-Lite", AXITopHarness, "prove", 4, 18, fast=False),
    FormalTask("dptbd_axi_short", "the same proof without its cover run (the default "
               "suite's)", AXITopHarness, "prove", 4, 0),
    FormalTask("dptbd_axi_list", "dptbd_axi 5x4, K = 1, whole frames in: a whole candidate "
               "list out of m_axis_cand", lambda: AXITopHarness(tiny_config(segment_frames=1),
                                                                 list_cover=True),
               "prove", 4, 68, fast=False, cover_syn=True),
    FormalTask("dptbd_axi_registered", "the same with control_style='registered' and "
               "register_read='two_level' (the ECP5 build's input and segmenter control, its "
               "register read)",
               lambda: AXITopHarness(core_options={"control_style": "registered",
                                                   "register_read": "two_level"}), "prove", 4,
               0),
    FormalTask("dptbd_axi_ecp5", "the same with the ECP5 family's options but the max tree "
               "(its histogram: histogram_style='dp16kd', the behavioural DP16KD)",
               lambda: AXITopHarness(core_options=ecp5_options(tiny_config())), "prove", 4, 0),
    FormalTask("m_axi_state", "DPPipelineAxi 5x4, 32-bit bus, 2-beat bursts, 2 in flight: "
               "the AXI4 manager port (dptbd_dp --state-store axi)", AxiStoreHarness,
               "prove", 4, 32, fast=False),
    FormalTask("m_axi_state_short", "the same proof without its cover run (the default "
               "suite's)", AxiStoreHarness, "prove", 4, 0),
    FormalTask("m_axi_state_ecp5", "the same with the ECP5 family's options (its store: the "
               "staged write-behind, the DP16KD prefetcher, the registered gate)",
               lambda: AxiStoreHarness(core_options=ecp5_options()), "prove", 4, 36,
               fast=False),
    FormalTask("m_axi_state_ecp5_short", "the same proof without its cover run",
               lambda: AxiStoreHarness(core_options=ecp5_options()), "prove", 4, 0),
    FormalTask("axi_write_behind", "AxiWriteBehind of that build alone: AW, W, B",
               WriteBehindHarness, "prove", 4, 14),
    FormalTask("axi_prefetcher", "AxiReadPrefetcher of that build alone: AR, R",
               PrefetcherHarness, "prove", 4, 16),
    FormalTask("axi_prefetcher_dp16kd", "the ECP5 build's AxiReadPrefetcher (style='dp16kd': "
               "the DP16KD ring, the behavioural DP16KD) alone: AR, R",
               lambda: PrefetcherHarness(style="dp16kd"), "prove", 4, 12),
    FormalTask("axi_write_behind_staged", "the ECP5 build's AxiWriteBehind (staged=True) "
               "alone: AW, W, B", lambda: WriteBehindHarness(staged=True), "prove", 4, 14),
    # the same proofs on the default build (128 x 128, C = 66): k-induction does not depend
    # on the counters' widths; the covers (lines of 128 words) run on the small build above
    FormalTask("m_axis_cand_128", "m_axis_cand on the default 128x128 build",
               lambda: CandidatesHarness(DPConfig()), "prove", 4, 0),
    FormalTask("m_axis_state_128", "m_axis_state on the default 128x128 build",
               lambda: StatesHarness(DPConfig()), "prove", 4, 0),
    FormalTask("s_axil_registers_128", "the registers of the default 128x128 build",
               lambda: RegistersHarness(DPConfig()), "prove", 4, 0),
    FormalTask("known_bad_m_axis_cand", "a soft reset that drops an offered m_axis_cand word: "
               "must FAIL", DroppingCandidatesHarness, "prove", 4, 0, expect="FAIL"),
    FormalTask("known_bad_s_axil", "an AXI4-Lite write answered before its W: must FAIL",
               EagerAXILiteHarness, "prove", 4, 0, expect="FAIL"),
    FormalTask("known_bad_write_behind_staged", "a staged write-behind that queues the burst "
               "it loads into its W registers as well: must FAIL",
               DoubleQueuedWriteBehindHarness, "bmc", 16, 0, expect="FAIL"),
)


def task(name: str) -> FormalTask:
    """The task called ``name``."""
    for t in TASKS:
        if t.name == name:
            return t
    raise ValueError(f"unknown formal task {name!r}; the tasks are "
                     f"{', '.join(t.name for t in TASKS)}")
