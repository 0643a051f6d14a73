"""Evaluation: the jobs that turn scenes, the golden model, the gateware and the DSP stage
into figures. One package per job, the modules they share beside them.

* :mod:`~dptbd.evaluation.run` — the main job ``dptbd run``: scenario file, the job as a
  library call, its ``--rtl`` check, report and figures;
* :mod:`~dptbd.evaluation.table1` — paper 001's Table 1 (Monte Carlo, first-level Pd);
* :mod:`~dptbd.evaluation.compare` (spec, plan, selection, runner, report, figures, job),
  with :mod:`~dptbd.evaluation.snr_loss` and :mod:`~dptbd.evaluation.sweep` — fixed point vs
  float;
* :mod:`~dptbd.evaluation.detectors` — papers 000 and 004's detectors, CA-CFAR and their
  comparison;
* :mod:`~dptbd.evaluation.paper000` — paper 000's experiments in fixed point (golden model
  or gateware) against float;
* :mod:`~dptbd.evaluation.family` — K-frame segments against paper 000's recursive DP;

shared:

* :mod:`~dptbd.evaluation.chain` — the FPGA → DSP chain (FPGA-stage golden model, the
  segmenter's settings, candidate lists, tracker) on one sequence;
* :mod:`~dptbd.evaluation.execution`, :mod:`~dptbd.evaluation.worker_warmup` — where the
  Monte Carlo tasks run (this process, local processes, a dask cluster);
* :mod:`~dptbd.evaluation.metrics`, :mod:`~dptbd.evaluation.stats` — first-level counts and
  interval statistics.
"""
