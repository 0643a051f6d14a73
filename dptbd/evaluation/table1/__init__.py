"""Paper 001's Table 1, ``dptbd table1`` (``docs/table1.md``).

* :mod:`~dptbd.evaluation.table1.experiment` — the setting and its Monte Carlo (first-level
  Pd and false points of the direction-weighted DP, plain DP and single-frame thresholding);
* :mod:`~dptbd.evaluation.table1.report` — the table beside the paper's.
"""
