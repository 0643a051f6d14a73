"""Scene sources: what the FPGA stage is fed.

* :mod:`dptbd.scenes.synthetic` — papers 001 §4 and 000 §3/§5 image scenes (noise plus point
  targets, the papers' scenarios) with their ground truth;
* :mod:`dptbd.scenes.targets` — point targets: the papers' motion conventions, manoeuvres
  (:class:`~dptbd.scenes.targets.Turn`) and per-frame ground truth;
* :mod:`dptbd.scenes.chain` — the scenes of the end-to-end chain comparison next to 001's
  two straight targets: a manoeuvring target and two crossing targets;
* :mod:`dptbd.scenes.reach` — the refusal of targets that leave the DP's move set's reach;
* :mod:`dptbd.scenes.snr` — target amplitude from the papers' SNR definitions (001: linear,
  000: dB);
* :mod:`dptbd.scenes.adc` — the sensor: ADC quantisation of float frames to integer codes,
  paper 001's 12-bit ADC (``INPUT_BITS``, ``ADC_GAIN``);
* :mod:`dptbd.scenes.range_doppler` — paper 004's range-Doppler magnitudes (passive-radar
  geometry, Swerling I target in complex noise);
* :mod:`dptbd.scenes.recorded` — recorded integer sequences (``.npy``, ``.npz``, folders of
  PNG/TIFF frames).

:class:`SceneError` (defined in ``dptbd.scenes._checks`` with the checks the modules share)
is what they raise for a bad parameter.
"""

from dptbd.scenes._checks import SceneError

__all__ = ["SceneError"]
