"""The other seed detectors and one comparison (``docs/detectors.md``).

* :mod:`~dptbd.evaluation.detectors.unified` — paper 000's DP family, the unified recursion
  (25)-(26) in float with a pluggable merit P (:mod:`~dptbd.evaluation.detectors.merits`)
  and transition term Q (:mod:`~dptbd.evaluation.detectors.transitions`);
  :mod:`~dptbd.evaluation.detectors.unified_fixed` — its integer form on paper 001's
  datapath;
* :mod:`~dptbd.evaluation.detectors.grid` — paper 004's information-accumulation detector and
  the grid Bayes filter with an existence state, on the shared machinery of
  :mod:`~dptbd.evaluation.detectors.grid_filter` (transition, likelihood, entropy);
* :mod:`~dptbd.evaluation.detectors.cfar` — CA-CFAR;
* :mod:`~dptbd.evaluation.detectors.particle` — the particle-filter TBD with an existence
  variable (Salmond-Birch / Rutten);
* :mod:`~dptbd.scenes.range_doppler` — range-Doppler scenes (Swerling I, Rayleigh noise);
* :mod:`~dptbd.evaluation.detectors.interface` — one interface for all detectors;
  :mod:`~dptbd.evaluation.detectors.adapters` — the eight detectors behind it, by name;
  :mod:`~dptbd.evaluation.detectors.scoring` — thresholds at equal Pfa and the counts;
  :mod:`~dptbd.evaluation.detectors.pd_vs_snr` — the Pd-vs-SNR comparison behind
  ``dptbd detectors``;
* :mod:`~dptbd.evaluation.detectors.paper000`, :mod:`~dptbd.evaluation.detectors.paper004` — the
  papers' simulations.
"""

from dptbd.evaluation.detectors._checks import DetectorError

__all__ = ["DetectorError"]
