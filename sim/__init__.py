"""RTL simulation: generated Verilog on Verilator (compiled, the main simulator) and cocotb 2
on Icarus (4-state protocol checks), scored against the golden model.

Modules (one line each)
-----------------------
- ``axi4_memory``: a strict Python AXI4 memory for the Amaranth simulator (random latency and ready/valid, every AXI4 rule it sees checked), behind the AXI4 state store's tests and bench.
- ``build_dirs``: build-directory names and locking shared by the Verilator and the Icarus builds.
- ``stream_model``: the golden model's output for any accepted stream, by the gateware's counter rule.
- ``checker``: the one in-order checker (expected items, received items, the first mismatch with its position).
- ``scoreboard``: the expected ``states`` words of the golden model, reported by frame, row, column and field.
- ``candidate_scoreboard``: the expected candidate lists, reported by segment, record and field.
- ``sim_job``: the job of ``dptbd sim``: one scene on Verilator or Icarus, its cycle count, speed and verdict.
- ``icarus``: the cocotb + Icarus build of the generated Verilog (``build/sim/<parameter set>/``) and its runs (``simulate``).
- ``x_store``: 4-state (Icarus) check that an X- or garbage-initialised external store never reaches an output.
- ``reset_x``: 4-state (Icarus) check of each top level around reset: ``ready`` and ``valid`` 0 in reset and the cycle after, no X on any output, valid offered in every cycle, bit-exact after.
- ``dp16kd_model``: a behavioural ECP5 ``DP16KD`` in Amaranth (the block RAM read through its output register), for the simulations and formal proofs of the ECP5 builds' DP16KD styles.
- ``cell_models``: the 4-state Verilog models of the vendor cells the family builds instantiate (ECP5 ``DP16KD``, ``sim/dp16kd.v``), found for a generated text.
- ``stimulus``: pixel words and LUT writes, packed with the gateware's layouts.
- ``scenarios``: integer scenes from :mod:`dptbd.scenes.synthetic` (targets, noise, saturation, ties, edges).

Sub-packages: ``verilator`` (:func:`~dptbd.sim.verilator.run` streams an input sequence
through a Verilator build: stalls, resets, LUT writes; ``verilator.cache`` verilates one top
level with the C++ harness ``sim/harness/`` into a cached executable, the build cache;
``verilator.toolchain``, the tools, flags and harness sources of a build and Verilator's
runtime library kept beside the builds;
``verilator.axi``, long runs of the AXI top level ``dptbd_axi`` scored against the golden
model (``verilator.axi.harness``, one run of its harness; ``verilator.axi.steps``, the bench's
steps as harness operations and the fault pulses they imply); ``verilator.dp_axi``, ``dptbd_dp`` built with ``--state-store axi``, its state in the
harness's C++ AXI4 memory model: random latency, every AXI4 rule checked), ``rtl`` (RTL in the loop: ``rtl.check``, one compiled run checked against the model
with the scoreboards; ``rtl.trials``, Monte Carlo trials on the compiled RTL for ``compare
--rtl`` and ``table1 --rtl``), ``benches`` (the cocotb 2.x test modules run on Icarus:
``benches.dp``, ``benches.dp_axi`` (``dptbd_dp`` built with ``--state-store axi``, its state in
cocotbext-axi's ``AxiRam``), ``benches.segmenter`` and ``benches.axi`` with cocotbext-axi,
``benches.axi_store`` (``dptbd_axi`` built with ``--state-store axi`` on ``AxiRam``), their stream
drivers, sinks and monitors ``benches.drivers`` (the cocotbext-axi ones of ``benches.axi`` and
``benches.axi_store``: ``benches.bus_drivers``), and what the soft-reset sweep of
``benches.axi`` checks, ``benches.soft_reset_check``), ``axi`` (the AXI top level ``dptbd_axi``'s runs: the video beats with
frame-sync faults and the frame monitor's fault rule, the campaign's random runs drawn from a
seed, their register traffic, and the scoring of a run's candidate words against the model's
lists across soft resets and ``aresetn``), ``campaign`` (the verification campaign, ``dptbd verify``, its runs on the
Dask execution layer: the cases, what each run draws from its seed, the results),
``coverage`` (the campaign's functional coverage bins, and code coverage of the
RTL: coverage builds' text, Verilator's points mapped to the Amaranth source, register bits
proven constant, exclusions, report; ``dptbd verify --coverage``), ``mutation`` (the
mutation score: Yosys ``mutate``, one mutant build, the verification slice, equivalence
proofs; ``dptbd verify --mutants``), ``formal`` (SymbiYosys proofs of the interfaces and
invariants; ``dptbd verify --formal``).

From the command line: ``dptbd sim`` (one scene, cycle count, verdict), ``dptbd verify``
(the campaign) and ``dptbd verilog`` (Verilog + manifest). Tests: ``pytest tests/sim`` (``-m slow`` for the
long 128 x 128 run). Speed: ``python benchmarks/bench_sim.py``.
"""
