"""The golden model: plain integer numpy of ``docs/arithmetic.md`` and its float reference.

* :mod:`~dptbd.model.operators` — one named helper per RTL operator;
* :mod:`~dptbd.model.segments` — the K-frame segment schedule shared by every model;
* :mod:`~dptbd.model.fixed` — the bit-accurate golden model, :mod:`~dptbd.model.fast` its
  fused numba kernel (checked bit for bit against it);
* :mod:`~dptbd.model.reference`, :mod:`~dptbd.model.fast.floating` — the float reference of
  001 eqs (8)-(11) and its kernel;
* :mod:`~dptbd.model.segmentation` — histogram segmentation into candidate lists;
* :mod:`~dptbd.model.family` — paper 000's DP family on the same datapath (merit LUT,
  additive penalty, forgetting factor, recursive schedule: ``docs/arithmetic.md`` §8), with
  :mod:`~dptbd.model.family.operators`, :mod:`~dptbd.model.schedule`,
  :mod:`~dptbd.model.family.fast` (numba, bit for bit) and :mod:`~dptbd.model.family.floating`.

Scenes are in :mod:`dptbd.scenes`, the DSP stage in :mod:`dptbd.dsp`, the evaluation jobs
and the other papers' detectors in :mod:`dptbd.evaluation`.
"""
