"""The DSP stage: what runs after the FPGA's candidate lists (``docs/association.md``).

* :mod:`dptbd.dsp.association` — track and candidate records, the fixed-capacity track
  association of paper 001 §3 (:class:`~dptbd.dsp.association.Tracker`);
* :mod:`dptbd.dsp.backtrack` — paths recovered through the direction maps, a position per
  frame;
* :mod:`dptbd.dsp.chain` — the FPGA → DSP chain (segmentation, candidate lists, tracker) that
  ``dptbd run`` drives;
* :mod:`dptbd.dsp.track_metrics` — confirmed tracks against ground truth.
"""
