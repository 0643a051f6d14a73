"""The ``dptbd compare`` job as one library call, :func:`compare_job`: validate everything,
run the Monte Carlo, optionally synthesise every configuration for its iCE40 cost,
summarise, and write the output folder.

Every error in the parameters, the output folder or the tools is raised before any scene
is generated. The folder is written through :func:`dptbd.output_folder.staged_folder`: the
files appear together when every one is written, and ``force`` replaces only the folder of
an earlier ``dptbd compare`` run (its ``compare_summary.json`` names the tool).
"""

from __future__ import annotations

import dataclasses
import pathlib
import sys
import time
import tomllib
from typing import Any, Mapping, Sequence

from dptbd.config import DPConfig
from dptbd.errors import ConfigError
from dptbd.output_folder import check_output_folder, staged_folder
from dptbd.evaluation.compare.report import MARKER, TOOL, markdown_tables, summarise, write_outputs
from dptbd.evaluation.compare.runner import CompareResult, check_rtl, run_compare
from dptbd.evaluation.compare.spec import CompareSpec, build_spec
from dptbd.evaluation.execution import check_worker_count, default_workers

__all__ = ["SynthOptions", "CompareOutcome", "load_config", "synth_config",
           "synthesise_all", "compare_job"]

@dataclasses.dataclass(frozen=True)
class SynthOptions:
    """How every configuration is synthesised for its hardware cost (``--synth``).

    ``variant``: ``"core"`` (DPCore, state store outside) or ``"top"`` (DPPipeline with the
    W*H store on chip); ``seeds``: nextpnr placement seeds, Fmax is their median; ``size``:
    the frame width = height the gateware is synthesised at (the Monte Carlo's scene size
    does not change the widths); ``cache_dir``: default ``~/.cache/dptbd/synth``.
    """

    variant: str = "core"
    device: str = "hx8k"
    package: str = "ct256"
    seeds: tuple[int, ...] = (1, 2, 3)
    target_mhz: float = 100.0
    size: int = 128
    cache_dir: pathlib.Path | None = None

    def check(self) -> None:
        """Refuse an unknown device, repeated seeds or an impossible size; raise
        :class:`dptbd.hw.flow.synth.ToolNotFoundError` when Yosys or nextpnr is missing."""
        from dptbd.hw.flow.synth import ICE40_DEVICES
        from dptbd.evaluation.sweep import check_tools

        if self.device not in ICE40_DEVICES:
            raise ConfigError(f"--device must be one of {ICE40_DEVICES}, got {self.device!r}")
        if len(set(self.seeds)) != len(self.seeds):
            raise ConfigError(f"--synth-seeds must be distinct, got {list(self.seeds)}")
        if not 3 <= self.size <= 4096:
            raise ConfigError(f"--synth-size must be an integer in [3, 4096], got {self.size}")
        check_tools()

    def to_dict(self) -> dict:
        """The options recorded in ``compare_summary.json`` (``run.synth``)."""
        return {"variant": self.variant, "device": self.device, "package": self.package,
                "seeds": list(self.seeds), "target_mhz": self.target_mhz, "size": self.size}


def load_config(path: pathlib.Path | None) -> dict:
    """The parsed TOML file ``path`` (``docs/compare.md``); ``{}`` for ``None``."""
    if path is None:
        return {}
    if not path.is_file():
        raise FileNotFoundError(f"--config {path}: no such file")
    try:
        return tomllib.loads(path.read_text())
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"--config {path}: not valid TOML: {exc}") from None


def synth_config(cfg: DPConfig, size: int) -> DPConfig:
    """``cfg`` at the synthesis frame size ``size`` x ``size`` (the widths unchanged)."""
    return cfg.replace(width=size, height=size)


def synthesise_all(spec: CompareSpec, synth: SynthOptions, workers: int, *,
                   progress: bool = True) -> dict:
    """Hardware cost of every configuration (cached); name -> HardwareCost.

    Each configuration is synthesised at ``synth.size`` (:func:`synth_config`). A tool
    failure on one configuration is reported on stderr and recorded in its ``error`` field
    (its cost columns stay empty), and the others go on; a failure is not cached.
    """
    import warnings

    from tqdm import tqdm

    from dptbd.config import EnergyWidthWarning
    from dptbd.hw.flow.synth import SynthToolError
    from dptbd.evaluation import sweep

    out = {}
    by_cfg = {}
    for f in tqdm(spec.configs, desc="synthesis", unit="config", disable=not progress):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", EnergyWidthWarning)
            cfg = synth_config(f.cfg, synth.size)
            if cfg not in by_cfg:
                try:
                    by_cfg[cfg] = sweep.hardware_cost(
                        cfg, variant=synth.variant, device=synth.device, package=synth.package,
                        seeds=tuple(synth.seeds), target_mhz=synth.target_mhz,
                        cache_dir=synth.cache_dir, jobs=max(1, min(workers, len(synth.seeds))))
                except (SynthToolError, ConfigError) as exc:
                    print(f"dptbd compare: synthesis of {f.name!r} failed: {exc}", file=sys.stderr)
                    by_cfg[cfg] = sweep.HardwareCost(
                        lut4=None, ff=None, bram=None, carry=None, fmax_median_mhz=None,
                        fmax_mhz=(), fits=None, logic_cells=None, device=synth.device,
                        package=synth.package, variant=synth.variant, width=cfg.width,
                        height=cfg.height, seconds=0.0, error=str(exc)[-500:])
        out[f.name] = by_cfg[cfg]
    return out


@dataclasses.dataclass
class CompareOutcome:
    """What :func:`compare_job` ran and wrote."""

    result: CompareResult
    summary: dict
    paths: list[pathlib.Path]

    @property
    def workers(self) -> int:
        return self.result.workers

    def text(self) -> str:
        """The tables, the run's size and speed, and the files written (what the command
        prints)."""
        spec, result, run = self.result.spec, self.result, self.summary["run"]
        lines = [markdown_tables(self.summary),
                 f"\n{spec.trials} trials x {result.segments} segments x {len(spec.snr)} SNRs "
                 f"(+ noise only), {len(spec.configs)} configurations "
                 f"({len(result.plan.fixed)} distinct), seed {spec.seed}"
                 + ("" if spec.tie_rule == "random" else f", tie rule {spec.tie_rule}") + ": "
                 f"Monte Carlo {result.seconds:.1f} s on {result.workers} worker(s) "
                 f"({result.trials_per_second:.2f} trials/s), total {run['total_seconds']:.1f} s"
                 + (" — fixed-point trials on the RTL" if result.rtl else "")]
        if result.rtl:
            from dptbd.sim.rtl.trials import summary_line
            lines.append(summary_line(result.rtl))
        lines.append("wrote " + ", ".join(str(p) for p in self.paths))
        return "\n".join(lines)


def compare_job(config: pathlib.Path | Mapping[str, Any] | None, out: pathlib.Path, *,
                force: bool = False, trials: int | None = None, seed: int | None = None,
                snr: Sequence[float] | None = None, bootstrap: int | None = None,
                tie_rule: str | None = None, workers: int | None = None,
                progress: bool = True, rtl: bool = False,
                synth: SynthOptions | None = None, scheduler: str | None = None,
                dashboard: bool = False) -> CompareOutcome:
    """Validate, run and write one comparison (``docs/compare.md``).

    Parameters
    ----------
    config : pathlib.Path, mapping or None
        A TOML file (:func:`load_config`), its parsed contents, or ``None`` for the
        built-in comparison (:func:`~dptbd.evaluation.compare.spec.build_spec`).
    out : pathlib.Path
        The output folder: a new one, or with ``force`` an earlier ``dptbd compare`` run's.
    trials, seed, snr, bootstrap, tie_rule
        Overrides of the run's parameters (``None``: the file's or the default;
        ``tie_rule`` one of :data:`~dptbd.evaluation.compare.spec.TIE_RULES`).
    workers : int, optional
        Worker processes (default: every core available); 1 runs in this process. With
        ``scheduler``: the number of workers the cluster must have (default: any).
    progress : bool
        Progress bars on stderr.
    rtl : bool
        Accumulate the fixed-point configurations' trials on the compiled gateware.
    synth : SynthOptions, optional
        Synthesise every configuration for its iCE40 cost (slow, cached).
    scheduler : str, optional
        ``tcp://HOST:PORT`` of an existing dask cluster (default: ``DPTBD_SCHEDULER`` if
        set, else a local one; ``docs/distributed.md``).
    dashboard : bool
        Print the dask dashboard's address.

    Raises
    ------
    dptbd.errors.ConfigError, FileNotFoundError, FileExistsError, ValueError
        Bad parameters or output folder, before any work (a bad ``workers``:
        :class:`dptbd.evaluation.execution.ExecutionError`).
    RuntimeError
        A missing tool (Yosys/nextpnr with ``synth``, Verilator with ``rtl``), before any
        work.
    """
    mapping = load_config(config) if config is None or isinstance(config, pathlib.Path) else config
    spec = build_spec(mapping, trials=trials, seed=seed, snr=snr, bootstrap=bootstrap,
                      tie_rule=tie_rule)
    if workers is not None:
        check_worker_count(workers)
    out = check_output_folder(out, force, marker=MARKER, tool=TOOL)
    if rtl:
        from dptbd.sim.verilator import check_tools as check_verilator
        check_rtl(spec)
        check_verilator()
    if synth is not None:
        synth.check()

    start = time.perf_counter()
    result = run_compare(spec, workers=workers, progress=progress, rtl=rtl, scheduler=scheduler,
                         dashboard=dashboard)
    local = default_workers() if workers is None else workers
    hardware = synthesise_all(spec, synth, local, progress=progress) if synth else None
    summary = summarise(result, hardware)
    summary["run"]["total_seconds"] = time.perf_counter() - start
    summary["run"]["synth"] = None if synth is None else synth.to_dict()
    with staged_folder(out, force, marker=MARKER, tool=TOOL) as folder:
        names = [p.name for p in write_outputs(summary, folder)]
    return CompareOutcome(result=result, summary=summary, paths=[out / n for n in names])
