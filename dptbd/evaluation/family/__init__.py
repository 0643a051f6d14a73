"""K-frame segments against paper 000's recursive DP with a forgetting factor
(``docs/detectors.md`` §6).

* :mod:`~dptbd.evaluation.family.detection` — first level: detection maps on Table 1's
  setting, counted as Table 1 counts (each map's n = 33 largest pixels);
* :mod:`~dptbd.evaluation.family.equal_pfa` — the same maps at equal false-alarm rate per
  pixel (thresholds calibrated on noise-only scenes, ``docs/detectors.md`` §7);
* :mod:`~dptbd.evaluation.family.wake` — the past positions a map keeps among its n
  largest (the recursion's wake), and its false points near the past track;
* :mod:`~dptbd.evaluation.family.recursive_pipeline` — the recursive DP's maps through the
  DSP association;
* :mod:`~dptbd.evaluation.family.association` — both through the DSP association on
  ``dptbd run``'s scenario, against ground truth;
* :mod:`~dptbd.evaluation.family.false_tracks` — what the false tracks are (wake, noise),
  and whether a noise peak persists from list to list;
* :mod:`~dptbd.evaluation.family.list_swaps` — noise-only lists replayed through the
  association with one property swapped (positions, headings, energies).
"""
