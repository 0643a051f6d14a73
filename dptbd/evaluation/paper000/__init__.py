"""Paper 000's experiments in fixed point against float, ``dptbd paper000``
(``docs/detectors.md`` §1.6).

* :mod:`~dptbd.evaluation.paper000.variants` — 000's DP variants as gateware configurations
  and their final maps on the golden model or the gateware;
* :mod:`~dptbd.evaluation.paper000.experiment` — §5.1/§5.2 cases and the SNR-gain curve,
  fixed and float on the same scenes;
* :mod:`~dptbd.evaluation.paper000.report` — paired statistics and the Markdown tables.

Paper 000's float detectors themselves are :mod:`dptbd.evaluation.detectors.paper000`.
"""
