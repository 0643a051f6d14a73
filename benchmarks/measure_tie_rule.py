"""Fixed vs float SNR loss under the gateware segmenter's tie rule (``dptbd compare``'s scene).

    python benchmarks/measure_tie_rule.py                       # the default run, both rules
    python benchmarks/measure_tie_rule.py --rules gateware --trials 480

``dptbd compare`` gives every detector exactly n candidates per accumulated image: pixels
tied at the n-th largest E are drawn by a pseudo-random priority (``docs/compare.md``, "Why
exactly n"). The gateware segmenter never breaks a tie: a pixel is kept iff its histogram
bin is at or above the threshold bin T, and T is the smallest bin whose count from the top
does not exceed n (``docs/arithmetic.md`` §6.3–§6.4), so a tied level at the boundary is
dropped whole and a coarse detector gets fewer than n candidates. This script measures the
comparison's SNR losses under each rule, on the same scenes, trials, seed and bootstrap as
``dptbd compare``:

* ``random`` — the comparison's own rule (its published numbers; a check that this script
  reproduces them);
* ``gateware`` — the segmenter's selection with each image's *own* histogram and s = 0
  (one bin per E value): ``{E > v_(n+1)}``, the rule of ``docs/arithmetic.md`` §6, which
  the gateware computes exactly for s = 0 (``test_same_segment_histogram_is_the_section_6_rule``);
* ``gateware-bins`` — the same with the histogram shift s of each configuration's
  ``DPConfig`` default (bins 2**s values wide; s = 1 for 8/16/8 at K = 6), i.e. what the
  deployed segmenter does with its own histogram. Configurations that compute identical
  DP bits share one detector in the comparison, so they share one s: the first one's.

Not modelled: the *stale* threshold (the gateware thresholds with the previous segment's
histogram, so its count scatters around n) and the empty first list after reset; float
images have no ties and keep exactly n under every rule. Only the candidate rule of the
comparison is swapped (its ``_candidates`` for this process and its forked workers); the
scenes, the models and the statistics are the library's (``dptbd.evaluation.compare``,
``dptbd.evaluation.compare_report``). This script reports; it asserts nothing.
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np


def _rule_candidates(rule: str):
    """A replacement of ``compare._candidates`` that keeps the pixels above the (n+1)-th
    largest value (of E, or of its histogram bin), ties at the boundary excluded whole."""
    from dptbd.evaluation import compare
    from dptbd.model.segmentation import histogram_bins

    state = {"cfg": None}
    original_fixed = None

    def fixed_wrapper(codes, cfg, *args, **kwargs):
        state["cfg"] = cfg
        return original_fixed(codes, cfg, *args, **kwargs)

    def candidates(energy, direction, plan, keys):
        count = plan.spec.candidate_count
        n_seg = len(plan.ends)
        h, w = energy.shape[-2:]
        flat = energy.reshape(-1, h * w)
        if rule == "gateware-bins" and np.issubdtype(flat.dtype, np.integer):
            values = histogram_bins(flat, state["cfg"])
        else:
            values = flat
        level = compare.nth_largest(values, count + 1)  # v_(n+1); -inf when n + 1 > H*W
        mask = values > level[:, None]
        images = flat.shape[0]
        n_cand = mask.sum(axis=1).astype(np.int64)
        near = plan.near_flat[np.arange(images) % n_seg]
        near_count = (mask & near).sum(axis=1).astype(np.int64)
        order = np.argsort(~mask, axis=1, kind="stable")[:, :max(count, 1)]
        idx = np.where(np.arange(order.shape[1])[None, :] < n_cand[:, None], order, 0)
        return compare._Candidates(idx.astype(np.int64), n_cand, near_count > 0, near_count,
                                   direction.reshape(images, -1))

    import dptbd.model.fast as fast
    original_fixed = fast.run_fixed_fast
    return candidates, fixed_wrapper


def run_rule(rule: str, trials: int | None, workers: int | None):
    """``dptbd compare``'s default run with one candidate rule; its summary."""
    from dptbd.evaluation import compare
    from dptbd.evaluation.compare_report import summarise
    import dptbd.model.fast as fast

    spec = compare.build_spec(None, trials=trials)
    saved = (compare._candidates, fast.run_fixed_fast)
    try:
        if rule != "random":
            cand, wrapper = _rule_candidates(rule)
            compare._candidates = cand
            fast.run_fixed_fast = wrapper
        start = time.perf_counter()
        result = compare.run_compare(spec, workers=workers)
        seconds = time.perf_counter() - start
    finally:
        compare._candidates, fast.run_fixed_fast = saved
    return summarise(result), seconds


def _fmt(v, lo, hi) -> str:
    if not np.isfinite(v):
        return "∞"
    return f"{v:+.2f} [{lo:+.2f}, {hi:+.2f}]"


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--rules", nargs="+", choices=("random", "gateware", "gateware-bins"),
                   default=["gateware", "random"], help="candidate rules (default gateware random)")
    p.add_argument("--trials", type=int, default=None, help="trials (default: compare's, 240)")
    p.add_argument("--workers", type=int, default=None, help="worker processes (default: all cores)")
    args = p.parse_args(argv)
    for rule in args.rules:
        s, seconds = run_rule(rule, args.trials, args.workers)
        run = s["run"]
        print(f"\nrule {rule}: {run['trials']} trials, seed {run['seed']}, n = "
              f"{run['candidate_count']}, {seconds:.0f} s")
        print("| configuration | B_in/B_E/F | cand./frame (noise) | loss @Pd 0.5 dB [95% CI] | "
              "loss @Pd 0.8 dB [95% CI] | verdict |")
        print("|---|---|---|---|---|---|")
        for r in s["configs"]:
            print(f"| {r['name']} | {r['widths']} | {r['noise_candidates_per_frame']:.2f} | "
                  f"{_fmt(r['loss_pd50_db'], r['loss_pd50_lo'], r['loss_pd50_hi'])} | "
                  f"{_fmt(r['loss_pd80_db'], r['loss_pd80_lo'], r['loss_pd80_hi'])} | "
                  f"{r['verdict']} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
