"""``dptbd compare``: fixed point against float — Monte Carlo Pd/Pfa, SNR loss, bit-width sweep.

Runs :func:`dptbd.evaluation.compare.run_compare` on the built-in scene (or a TOML file's),
optionally synthesises every configuration for its iCE40 cost (``--synth``, cached), and
writes CSV, JSON and PNG figures to ``--out``. ``docs/compare.md`` has a real result.
"""

from __future__ import annotations

import argparse
import pathlib
import sys
import time
import tomllib

from dptbd.config import ConfigError

HELP = "fixed vs float detection: Monte Carlo Pd/Pfa, SNR loss, bit-width sweep with iCE40 cost"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--config", type=pathlib.Path, metavar="TOML",
                        help="run parameters, [[config]] list and [sweep] table (docs/compare.md); "
                             "default: the built-in comparison")
    # The defaults quoted here are evaluation.compare.DEFAULT_RUN's (written out rather than
    # imported, so that building the CLI does not import numba;
    # tests/commands/test_compare.py::test_cli_help_quotes_the_real_defaults keeps them equal).
    parser.add_argument("--trials", type=int, help="seeded scenes (default 240, or the file's)")
    parser.add_argument("--seed", type=int, help="base seed (default 2024, or the file's)")
    parser.add_argument("--snr", type=float, nargs="*", metavar="SNR",
                        help="paper 001 linear SNRs, strictly increasing "
                             "(default 1.5 1.7 1.9 2.1 2.3 2.5 2.7 2.9, or the file's)")
    parser.add_argument("--bootstrap", type=int, metavar="B",
                        help="bootstrap resamples for the SNR-loss intervals "
                             "(default 1000, or the file's)")
    parser.add_argument("--workers", type=int, default=None,
                        help="worker processes (default: all cores; 1 = in this process)")
    parser.add_argument("--out", type=pathlib.Path, default=pathlib.Path("compare-out"),
                        help="output folder for CSV/JSON/PNG (default ./compare-out)")
    parser.add_argument("--force", action="store_true", help="write into a non-empty --out")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    parser.add_argument("--rtl", action="store_true",
                        help="RTL in the loop: accumulate the fixed-point configurations' trials "
                             "on the compiled gateware (Verilator), every output word and "
                             "candidate list checked against the golden model "
                             "(docs/compare.md); the float model stays as it is")
    synth = parser.add_argument_group("hardware cost (slow: minutes per configuration, cached)")
    synth.add_argument("--synth", action="store_true",
                       help="synthesise every configuration (Yosys synth_ice40 + nextpnr-ice40); "
                            "off by default")
    synth.add_argument("--synth-variant", choices=("core", "top"), default="core",
                       help="core: DPCore, state store outside (default); top: DPPipeline with "
                            "the W*H store on chip")
    synth.add_argument("--synth-seeds", type=int, nargs="+", default=[1, 2, 3],
                       help="nextpnr placement seeds; Fmax is their median (default 1 2 3)")
    synth.add_argument("--device", default="hx8k", help="nextpnr-ice40 device (default hx8k)")
    synth.add_argument("--package", default="ct256", help="package (default ct256)")
    synth.add_argument("--freq", type=float, default=100.0, help="nextpnr target MHz (default 100)")
    synth.add_argument("--synth-size", type=int, default=128, metavar="N",
                       help="frame width = height the gateware is synthesised at (default 128, "
                            "the gateware's reference size; the Monte Carlo's scene size does "
                            "not change the widths, only the line buffers and counters)")
    synth.add_argument("--synth-cache", type=pathlib.Path, default=None,
                       help="cache folder (default ~/.cache/dptbd/synth)")


def _load_toml(path: pathlib.Path | None) -> dict:
    if path is None:
        return {}
    if not path.is_file():
        raise FileNotFoundError(f"--config {path}: no such file")
    try:
        return tomllib.loads(path.read_text())
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"--config {path}: not valid TOML: {exc}") from None


def _check_out(out: pathlib.Path, force: bool) -> None:
    if out.exists() and not out.is_dir():
        raise FileExistsError(f"--out {out} exists and is not a folder")
    if out.is_dir() and any(out.iterdir()) and not force:
        raise FileExistsError(f"--out {out} is not empty; pass --force to overwrite its files")


def prepare(args: argparse.Namespace):
    """Validate everything (spec, workers, output folder, tools); return the spec.

    Every error is raised here, before any scene is generated.
    """
    from dptbd.evaluation.compare import build_spec

    spec = build_spec(_load_toml(args.config), trials=args.trials, seed=args.seed,
                      snr=args.snr, bootstrap=args.bootstrap)
    if args.workers is not None and args.workers < 1:
        raise ConfigError(f"--workers must be >= 1, got {args.workers}")
    _check_out(args.out, args.force)
    if getattr(args, "rtl", False):
        from dptbd.evaluation.compare import check_rtl
        from dptbd.sim.verilator import check_tools as check_verilator
        check_rtl(spec)
        check_verilator()
    if args.synth:
        from dptbd.hw.flow.synth import ICE40_DEVICES
        from dptbd.evaluation.sweep import check_tools
        if args.device not in ICE40_DEVICES:
            raise ConfigError(f"--device must be one of {ICE40_DEVICES}, got {args.device!r}")
        if len(set(args.synth_seeds)) != len(args.synth_seeds):
            raise ConfigError(f"--synth-seeds must be distinct, got {args.synth_seeds}")
        if not 3 <= args.synth_size <= 4096:
            raise ConfigError(f"--synth-size must be in [3, 4096], got {args.synth_size}")
        check_tools()
    return spec


def synth_config(cfg, size: int):
    """``cfg`` at the synthesis frame size ``size`` x ``size`` (the widths unchanged)."""
    return cfg.replace(width=size, height=size)


def synthesise_all(spec, args, workers: int) -> dict:
    """Hardware cost of every configuration (cached); name -> HardwareCost.

    Each configuration is synthesised at ``--synth-size`` (:func:`synth_config`). A tool
    failure on one configuration is recorded in its ``error`` field (its cost columns stay
    empty) and the others go on; a failure is not cached.
    """
    import warnings

    from tqdm import tqdm

    from dptbd.config import EnergyWidthWarning
    from dptbd.hw.flow.synth import SynthToolError
    from dptbd.evaluation.sweep import HardwareCost, hardware_cost

    out = {}
    by_cfg = {}
    for f in tqdm(spec.configs, desc="synthesis", unit="config", disable=args.no_progress):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", EnergyWidthWarning)
            cfg = synth_config(f.cfg, args.synth_size)
            if cfg not in by_cfg:
                try:
                    by_cfg[cfg] = hardware_cost(
                        cfg, variant=args.synth_variant, device=args.device,
                        package=args.package, seeds=tuple(args.synth_seeds),
                        target_mhz=args.freq, cache_dir=args.synth_cache,
                        jobs=max(1, min(workers, len(args.synth_seeds))))
                except (SynthToolError, ConfigError) as exc:
                    print(f"dptbd compare: synthesis of {f.name!r} failed: {exc}", file=sys.stderr)
                    by_cfg[cfg] = HardwareCost(
                        lut4=None, ff=None, bram=None, carry=None, fmax_median_mhz=None,
                        fmax_mhz=(), fits=None, logic_cells=None, device=args.device,
                        package=args.package, variant=args.synth_variant, width=cfg.width,
                        height=cfg.height, seconds=0.0, error=str(exc)[-500:])
        out[f.name] = by_cfg[cfg]
    return out


def main(args: argparse.Namespace) -> int:
    from dptbd.evaluation.compare import default_workers, run_compare
    from dptbd.evaluation.compare.report import markdown_tables, summarise, write_outputs

    try:
        spec = prepare(args)
    except RuntimeError as exc:  # a missing synthesis tool (dptbd.hw.flow.synth.ToolNotFoundError)
        print(f"dptbd compare: error: {exc}", file=sys.stderr)
        return 2
    workers = default_workers() if args.workers is None else args.workers
    start = time.perf_counter()
    result = run_compare(spec, workers=workers, progress=not args.no_progress,
                         rtl=getattr(args, "rtl", False))
    hardware = synthesise_all(spec, args, workers) if args.synth else None
    summary = summarise(result, hardware)
    summary["run"]["total_seconds"] = time.perf_counter() - start
    summary["run"]["synth"] = None if not args.synth else {
        "variant": args.synth_variant, "device": args.device, "package": args.package,
        "seeds": list(args.synth_seeds), "target_mhz": args.freq,
        "size": args.synth_size}
    args.out.mkdir(parents=True, exist_ok=True)
    paths = write_outputs(summary, args.out)
    print(markdown_tables(summary))
    print(f"\n{spec.trials} trials x {result.segments} segments x {len(spec.snr)} SNRs (+ noise only), "
          f"{len(spec.configs)} configurations ({len(result.plan.fixed)} distinct), seed {spec.seed}: "
          f"Monte Carlo {result.seconds:.1f} s on {workers} worker(s) "
          f"({result.trials_per_second:.2f} trials/s), total {summary['run']['total_seconds']:.1f} s"
          + (" — fixed-point trials on the RTL" if result.rtl else ""))
    if result.rtl:
        from dptbd.sim.rtl_trials import summary_line
        print(summary_line(result.rtl))
    print("wrote " + ", ".join(str(p) for p in paths))
    return 0
