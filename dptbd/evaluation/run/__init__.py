"""The main job, ``dptbd run``: one scene (or recorded data) through the FPGA stage and the
DSP stage, against ground truth.

* :mod:`~dptbd.evaluation.run.scenario` — the scenario file (TOML): scene or data, ADC, DP,
  thresholds, association;
* :mod:`~dptbd.evaluation.run.job` — ``run_job(scenario) -> RunResult``, the job as a
  library call (the chain itself is :mod:`dptbd.evaluation.chain`);
* :mod:`~dptbd.evaluation.run.rtl` — its ``--rtl`` check, the generated Verilog against the
  golden model;
* :mod:`~dptbd.evaluation.run.report`, :mod:`~dptbd.evaluation.run.figures` — the output
  folder: tables, ``summary.json``, figures.
"""
