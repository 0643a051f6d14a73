"""Evaluation: the jobs that turn scenes, the golden model, the gateware and the DSP stage
into figures.

* :mod:`~dptbd.evaluation.run_job` — the main job ``dptbd run`` as a library call,
  ``run_job(scenario) -> RunResult``, with its scenario file
  (:mod:`~dptbd.evaluation.scenario`), its ``--rtl`` check (:mod:`~dptbd.evaluation.run_rtl`),
  its report and figures (:mod:`~dptbd.evaluation.run_report`,
  :mod:`~dptbd.evaluation.run_figures`);
* :mod:`~dptbd.evaluation.table1` and :mod:`~dptbd.evaluation.table1_report` — paper 001's
  Table 1 (Monte Carlo, first-level Pd);
* :mod:`~dptbd.evaluation.compare` (spec, plan, selection, runner, report, figures, job),
  :mod:`~dptbd.evaluation.snr_loss`, :mod:`~dptbd.evaluation.sweep` — fixed point vs float;
* :mod:`~dptbd.evaluation.detectors` — papers 000 and 004's detectors, CA-CFAR and their
  comparison;
* :mod:`~dptbd.evaluation.metrics`, :mod:`~dptbd.evaluation.stats` — first-level counts and
  interval statistics shared by all of them.
"""
