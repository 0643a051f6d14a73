"""Numpy models: the float reference and the bit-accurate golden model of the DP.

Still here until the next steps of issue 11 move them out: segmentation and first-level
metrics beside the golden model, the evaluation jobs (compare, SNR loss, sweep, Table 1,
statistics) and the other papers' detectors (``dptbd.model.detectors``). Scenes are in
:mod:`dptbd.scenes`, the DSP stage in :mod:`dptbd.dsp`.
"""
