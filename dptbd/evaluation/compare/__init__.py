"""Fixed point against float: Monte Carlo detection performance on the same seeded scenes.

``dptbd compare`` (``docs/compare.md``) asks what a fixed-point configuration (ADC width
B_in, accumulator B_E, weight fraction F, rounding, weight LUT) costs in detection, against
the float64 model with the same (real-valued) LUT. This package runs the Monte Carlo and
reduces it to statistics; :mod:`dptbd.evaluation.snr_loss` holds the loss arithmetic,
:mod:`dptbd.evaluation.sweep` the bit-width sweep and hardware cost, and
:mod:`dptbd.evaluation.compare.report` and :mod:`~dptbd.evaluation.compare.figures`
the tables and figures.

The scene (paper 001 §4, scaled down by default)
    Gaussian noise of mean ``mu`` and standard deviation ``sigma`` (001's Table 1: 30 and
    sqrt(3) grey levels) and one point target of amplitude ``SNR * sigma``
    (:func:`dptbd.scenes.synthetic.table1_scenario`, trajectory centred in the frame). Trial
    ``i``'s noise depends only on ``(seed, i)`` and is the same at every SNR (common
    random numbers: the Pd curves are smooth and the SNR points are paired), and the same
    noise without the target is trial ``i``'s noise-only scene.

What each model sees
    The **float model** (:func:`dptbd.model.fast.floating.run_float_fast`, bit-identical to
    ``run_float``) sees the float sensor output. A **fixed configuration**
    (:func:`dptbd.model.fast.run_fixed_fast`, bit-identical to ``run_fixed``) sees the
    same frames through its ADC: ``code = clip(rint(gain * x + offset), 0, 2**B_in - 1)``
    (:func:`dptbd.scenes.synthetic.quantise`) with, unless the configuration sets
    ``adc_gain`` / ``adc_offset``, the mapping of :func:`adc_mapping`: a fixed analogue
    window ``[mu - 6 sigma, mu + 10 sigma]`` spread over the 2**B_in codes, so one sigma is
    ``2**B_in / 16`` LSB (0.5 LSB at 3 bits, 1 at 4, 4 at 6, 16 at 8). Each extra bit
    halves the LSB, as in a real ADC whose full scale is fixed by the sensor.

Measured per detector, on the same scenes
    * first-level Pd at each SNR at a constant false-alarm count: exactly n candidates per
      accumulated image (n = ``false_alarm_rate`` of the pixels,
      :func:`dptbd.model.segmentation.count_for_rate`), the n largest E with ties at the
      n-th largest broken by a pseudo-random priority per (seed, trial, segment, pixel),
      the same for every detector (:func:`candidate_indices`), so every detector — however
      coarse its E — runs at the same number of candidates (the default ``tie_rule``,
      ``random``; the rules ``gateware`` and ``gateware-bins`` select as the gateware
      segmenter does, ties at the boundary dropped whole:
      :mod:`~dptbd.evaluation.compare.selection`);
      a candidate within one pixel of the target's true pixel in the segment's last frame
      is a detection (:mod:`dptbd.evaluation.metrics`), the others are false points;
    * the false-alarm probability per pixel against a threshold, on the noise-only scenes.
      Thresholds are in noise units of a K-frame path, ``z = (E - K mu) / (sqrt(K) sigma)``;
      a fixed configuration's E is mapped back through its ADC,
      ``E_float = (E_fixed - K offset) / gain``;
    * agreement with the float model (same LUT): per accumulated image, the number of
      identical candidate points (row, column and direction d) over the larger of the two
      candidate counts, and whether the two candidate lists are identical.

All counts are kept per trial, so that every interval can be clustered by trial
(:func:`dptbd.evaluation.snr_loss.clustered_wilson`) and the SNR loss bootstrapped over trials
(:func:`dptbd.evaluation.snr_loss.bootstrap_losses`). Trials run in chunks on worker processes;
a trial's numbers depend only on the seed and its index, never on the chunking or the
number of workers.

The package, one concept per module:

* :mod:`~dptbd.evaluation.compare.luts` — the weight LUTs (:data:`LUTS`) and the default
  ADC mapping (:func:`adc_mapping`);
* :mod:`~dptbd.evaluation.compare.spec` — a whole run (:class:`CompareSpec`), built and
  validated from a TOML file by :func:`build_spec`;
* :mod:`~dptbd.evaluation.compare.configs` — one fixed configuration (:class:`FixedSpec`),
  the default configurations and sweep, and their validation;
* :mod:`~dptbd.evaluation.compare.checks` — the checks of the TOML values;
* :mod:`~dptbd.evaluation.compare.plan` — what a worker runs (:class:`Plan`, :func:`make_plan`);
* :mod:`~dptbd.evaluation.compare.selection` — the candidate rules (:data:`TIE_RULES`):
  exactly n with its tie-break priorities, and the gateware segmenter's;
* :mod:`~dptbd.evaluation.compare.runner` — the Monte Carlo (:func:`run_compare`) on a
  process pool;
* :mod:`~dptbd.evaluation.compare.report` — statistics, CSV/JSON files, Markdown tables;
* :mod:`~dptbd.evaluation.compare.figures` — the three figures;
* :mod:`~dptbd.evaluation.compare.job` — the whole ``dptbd compare`` job, validated, run and
  written to its output folder (:func:`compare_job`).
"""

from dptbd.evaluation.compare.luts import LUTS, adc_mapping, cosine_weights, lut_weights
from dptbd.evaluation.compare.spec import (
    DEFAULT_CONFIGS, DEFAULT_RUN, DEFAULT_SWEEP, TIE_RULES, CompareSpec, FixedSpec, build_spec)
from dptbd.evaluation.compare.plan import Plan, make_plan
from dptbd.evaluation.compare.selection import candidate_indices, image_keys, nth_largest
from dptbd.evaluation.compare.runner import (
    CompareResult, check_rtl, default_workers, measure_frames, run_compare)
from dptbd.evaluation.compare.report import (
    DATA_FILES, markdown_tables, summarise, write_outputs)
from dptbd.evaluation.compare.figures import FIGURES
from dptbd.evaluation.compare.job import CompareOutcome, SynthOptions, compare_job

__all__ = [
    "LUTS", "cosine_weights", "lut_weights", "adc_mapping", "FixedSpec", "CompareSpec",
    "DEFAULT_RUN", "DEFAULT_CONFIGS", "DEFAULT_SWEEP", "TIE_RULES", "build_spec", "Plan", "make_plan",
    "measure_frames", "CompareResult", "run_compare", "default_workers", "candidate_indices",
    "nth_largest", "image_keys", "check_rtl",
    "summarise", "write_outputs", "markdown_tables", "FIGURES", "DATA_FILES",
    "compare_job", "SynthOptions", "CompareOutcome",
]
