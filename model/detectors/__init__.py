"""The other seed detectors and one comparison (``docs/detectors.md``).

* :mod:`~dptbd.model.detectors.unified` — paper 000's DP family, the unified recursion
  (25)-(26) with a pluggable merit P and transition term Q (float, and the integer form on
  paper 001's datapath);
* :mod:`~dptbd.model.detectors.grid` — paper 004's information-accumulation detector and
  the grid Bayes filter with an existence state;
* :mod:`~dptbd.model.detectors.cfar` — CA-CFAR;
* :mod:`~dptbd.scenes.range_doppler` — range-Doppler scenes (Swerling I, Rayleigh noise);
* :mod:`~dptbd.model.detectors.interface` and :mod:`~dptbd.model.detectors.compare` — one
  interface for all detectors and the Pd-vs-SNR comparison behind ``dptbd detectors``;
* :mod:`~dptbd.model.detectors.paper000`, :mod:`~dptbd.model.detectors.paper004` — the
  papers' simulations.
"""

from dptbd.model.detectors._checks import DetectorError

__all__ = ["DetectorError"]
