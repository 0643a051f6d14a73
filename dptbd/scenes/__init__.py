"""Scene sources: what the FPGA stage is fed.

* :mod:`dptbd.scenes.synthetic` — papers 001 §4 and 000 §3/§5 image scenes (noise, point
  targets, manoeuvres), their ground truth and the ADC quantisation to integer frames;
* :mod:`dptbd.scenes.range_doppler` — paper 004's range-Doppler magnitudes (passive-radar
  geometry, Swerling I target in complex noise);
* :mod:`dptbd.scenes.recorded` — recorded integer sequences (``.npy``, ``.npz``, folders of
  PNG/TIFF frames).
"""
