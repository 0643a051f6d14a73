"""Functional coverage of the verification campaign: every bin, defined in this package and
only here.

A bin is a named count of something a run exercised. The counts of one run come from the
stimulus it offered (the input words, the stall densities, the cycle each word was accepted
and each output left, the resets, LUT and settings writes, the injected faults) and from the
golden model's outputs, which the RTL matched bit for bit: a run that failed fills no bin.
:func:`stream_bins` reads a compiled run of ``dp``, ``core`` or ``segmenter``
(:func:`dptbd.sim.campaign.check_run`), :func:`axi_bins` a run of ``dptbd_axi``
(:func:`dptbd.sim.axi.runs.check_run`): the inputs of
:func:`dptbd.sim.verilator.axi.check_axi` (the ``Beats``, the ``steps`` and the stall
densities) and the cycle each beat was accepted and each register operation done.

The bins are plain ``{name: hits}`` dicts: a run declares every bin its design and its
case's faults can fill (with 0 hits), so merging runs is addition (:func:`merge`) and a bin
still at 0 after the campaign is empty (:func:`empty_bins`); bins of a design that is not in
the campaign are never declared, never empty.

Why a package of our own rather than cocotb-coverage: cocotb-coverage samples transactions
one by one into a process-global database (``coverage_db``) and merges the databases of
several processes through exported XML/YAML files; the campaign's runs are scored in
worker processes and the bins here are computed array-wise from whole runs, so a dict of
counts that pickles and adds is all that is needed.

The bin groups and what a hit is (``docs/gateware.md``, "Verification campaign"):

* ``stall`` (also ``axi``, the positions by the model's counters of each piece between
  resets): input words accepted at a position of the frame (first / last row, first /
  last column, interior, a segment-boundary frame: the first or the last frame of a
  segment, by the model's counters) in runs whose input gap density (``valid_gap``) and
  output back-pressure density (``ready_pause``) fall in a band each: none (0), light
  (0 < p < 0.35), heavy (p >= 0.35).
* ``reset``: resets whose rise found k words in the pipeline, k = 0 … L (L the DP
  pipeline's latency of the run's build), or more than L (words waiting in the output
  FIFO under back-pressure). ``dp`` / ``core``: the words accepted since the previous reset
  minus the outputs transferred since then, before the reset's cycle (every accepted word
  leaves as one output). ``segmenter`` (one output per list, not per word): the words
  accepted in the L cycles before the reset (the DP pipeline never stalls on a list).
* ``soft reset`` (``axi``): soft resets (CONTROL.soft_reset) that found k words in flight,
  k = 0 … L (L the AXI top's latency, the build's ``latency``: from a beat accepted on
  ``s_axis_video`` to its state word, the DP pipeline's and the video input's): the beats
  accepted in the L cycles before the cycle the soft reset's AXI4-Lite
  write began (the harness offers no beat while an operation is under way; the register
  block answers a write in its :data:`AXIL_WRITE_CYCLES`-th cycle, so the write began
  that many cycles before its recorded response, less one). A soft reset after the step's
  settle (``soft_reset: True``) finds 0; ``soft_reset: "now"`` is measured this way.
* ``aresetn`` (``axi``): ``aresetn`` pulses with 0 words in flight, from the plan: those
  ``check_axi`` holds low after the step's settle (more than L idle cycles; those with
  words in flight, ``aresetn_wait``, are not counted here).
* ``fault``: injected faults of each class (:data:`dptbd.sim.campaign.FAULTS`,
  :data:`dptbd.sim.axi.stimulus.FAULT_KINDS`) followed by a clean segment: a whole segment
  (K complete frames from the counters' frame 0) that starts at or after the fault, with no
  fault, LUT or settings write inside it, all of whose outputs matched (the run passed).
* ``LUT``: whole-table writes by the stage of the frame they come before (between frames:
  before a frame's first word or after the stream; in the first row; a middle row; the last
  row), and written entries holding code 0, 2**F - 1 and 2**F (the largest code, weight 1).
* ``saturation``: model state words at E = 2**B_E - 1.
* ``lists`` (``segmenter``, ``axi``): candidate lists (all of whose words came out) with 0
  records, exactly n records (0 < n < C, n the list's run-time candidate count), C records,
  and with the overflow flag (more than C pixels reached the threshold).
* ``ties``: lists whose scored frame has two or more pixels in the list's threshold bin T
  (T < 2**b): a tie at the threshold, every one of them selected.
* ``store`` (``dp_axi``, ``dptbd_dp --state-store axi``, and ``axi_store``, ``dptbd_axi
  --state-store axi``: :mod:`dptbd.sim.campaign.store`):
  read bursts by the class of the read latency range their run drew (0; 1 … 99; 100 … 499;
  500 or more cycles); each AXI4 channel stalled by the memory (AR, AW, W ready or R, B
  valid driven low at random; every burst of that direction in such a run); each error
  response (SLVERR, DECERR) on a read and on a write, flagged once and recovered from
  (the run's later segments exact); read and write bursts ending at a 4 KB boundary (one
  per multiple of 4096 in (base, base + frame bytes] per frame: the port moves every slot
  once a frame in bursts aligned to the burst size).
* ``register`` (``axi``, ``axi_store``): AXI4-Lite accesses refused (SLVERR) for each
  reason of ``docs/registers.md``, judged on the build's register map (a store build's
  adds ``STATE_BASE`` and the store's registers): a value out of range per setting
  register and for the LUT window, a value in range that is not aligned (``STATE_BASE``: a
  multiple of the burst size),
  a LUT write without wstrb = 1111, a LUT read, a write to a constant, counter or status
  register, unaligned and unmapped reads and writes. ``check_axi``'s ``steps`` express the
  range refusals of the setting registers, ``lut_writes`` and ``bus`` the LUT's and the
  raw accesses (``bus`` of :func:`axi_bins` adds more); a write of a setting with some
  strobes refuses the value it would make (the strobed bytes of the data over the
  register's value held then).

Modules: ``groups`` (the groups, bands, positions and bin names), ``view`` (the model's view
of a whole run and the bins every kind of run counts from it), ``stream`` (the runs of
``dp``, ``core`` and ``segmenter``), ``axi`` (the runs of ``dptbd_axi``), ``registers``
(the register accesses of an AXI run and why one is refused), ``store`` (the runs of
``dptbd_dp --state-store axi``), ``table`` (the campaign's
bins: merge, table, empty-bin verdict). The public names are importable from this package.
"""

from __future__ import annotations
from dptbd.sim.coverage.bins.axi import (AXIL_WRITE_CYCLES, axi_bins, declared_axi,
                                         soft_reset_bin)
from dptbd.sim.coverage.bins.groups import (ARESETN, AXI, BANDS, BUS_REASONS, FIFO, GROUPS,
                                            LIST_LABELS, LUT_CODES, LUT_STAGES, POSITIONS,
                                            RANGE, SATURATION, STORE, STREAM, TIES, Group,
                                            band)
from dptbd.sim.coverage.bins.registers import bus_operations
from dptbd.sim.coverage.bins.store import declared_store, store_bins
from dptbd.sim.coverage.bins.stream import declared_stream, stream_bins
from dptbd.sim.coverage.bins.table import empty_bins, empty_message, merge, table
from dptbd.sim.coverage.bins.view import list_ends

__all__ = ["BANDS", "POSITIONS", "Group", "GROUPS", "band", "declared_stream", "declared_axi",
           "stream_bins", "axi_bins", "bus_operations", "soft_reset_bin", "list_ends", "merge",
           "empty_bins", "table", "empty_message", "ARESETN", "AXIL_WRITE_CYCLES",
           "SATURATION", "TIES", "LIST_LABELS", "LUT_STAGES", "LUT_CODES", "STREAM", "AXI",
           "FIFO", "RANGE", "BUS_REASONS", "STORE", "declared_store", "store_bins"]
