"""Helpers shared by the tests (``pythonpath = ["tests"]`` in ``pyproject.toml``: imported as
``helpers.<module>``; the test files themselves are imported with ``--import-mode=importlib``
and import nothing from one another).

Modules:

- ``refusals``: :func:`~helpers.refusals.whole`, the regex of a whole refusal message, and
  :func:`~helpers.refusals.not_integer`, the refusal of an integer parameter out of range.
- ``luts``: weight LUTs for the configuration's tests.
- ``candidate_lists``: synthetic candidate lists and a tracker for the association tests.
- ``hw_harness``: the Amaranth-simulator harness of the gateware tests (streams, golden-model
  states, bit-exact comparison, Verilator lint, Icarus run of generated Verilog).
- ``seg_harness``: the Amaranth-simulator harness of the segmentation gateware.
- ``axil_harness``: an AXI4-Lite manager for Amaranth-simulator testbenches.
- ``family_harness``: golden-model reference for paper 000's family on the gateware.
- ``max_tree_bench``: vectors, references and bench shared by the max-tree tests.
- ``model_strategies``: Hypothesis settings, configurations and frames of the golden model.
- ``family_strategies``: Hypothesis strategies for paper 000's DP family.
- ``cocotb_harness``: configurations, builds and pauses of the cocotb + Icarus tests.
- ``verilator_harness``: configurations and builds of the compiled-simulation tests.
- ``compare_spec``: a small ``dptbd compare`` specification for the RTL-in-the-loop tests.
- ``dask_processes``: Dask clusters of separate processes for the execution-layer tests.
- ``verilog_ports``: the ports a generated Verilog module declares, read from its text.
"""
