"""The bit-width sweep of ``dptbd compare``: losses, verdicts, the smallest good configuration,
and what each configuration costs in iCE40 logic.

Verdict of a configuration against float (same LUT), at every Pd level of the run
(:func:`verdict`), from the 95 % paired-bootstrap interval ``[lo, hi]`` of its SNR loss
(:mod:`dptbd.evaluation.snr_loss`):

* ``"within"``: ``hi <= tolerance`` at every level — shown to lose at most the tolerance
  (0.1 dB by default);
* ``"beyond"``: ``lo > tolerance`` at some level — shown to lose more;
* ``"undecided"``: neither; the run cannot tell (more trials narrow the interval).

The **smallest** configuration (:func:`cost_key`) is ordered by the state word
``B_E + B_d`` bits per pixel first (the state store: W*H words, the dominant memory — at
128 x 128 every bit of B_E is 16 kbit, four iCE40 block RAMs), then the synthesised
logic cells (SB_LUT4) when known, then B_in, then F. :func:`choose` returns the smallest
sweep configuration shown within the tolerance, and the smallest not shown beyond it.

Hardware cost (:func:`hardware_cost`) synthesises the gateware at a configuration's widths
with :func:`dptbd.hw.flow.synth.synthesize` (Yosys ``synth_ice40``, nextpnr-ice40 on an iCE40
HX8K, ``ct256``, one place-and-route per seed) and caches the result in a JSON file per
configuration, keyed by a hash of everything that goes into the netlist and the flow
(all DPConfig fields including the LUT, variant, device, package, seeds, target
frequency, tool versions, and the gateware's source: the ``dptbd.hw`` package's ``.py``
files, :func:`gateware_hash`): a second run costs nothing, and a changed gateware is
synthesised again.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import pathlib
from typing import Any, Callable, Mapping, Sequence

import numpy as np

from dptbd.evaluation.snr_loss import LossEstimate, bootstrap_losses
from dptbd.hw.flow.source_hash import gateware_hash  # noqa: F401  (re-exported: compare --synth keys)

__all__ = ["config_losses", "verdict", "cost_key", "choose", "hardware_key", "hardware_cost",
           "gateware_hash", "default_cache_dir", "HardwareCost", "state_store_bits", "check_tools"]


def config_losses(result) -> dict[str, list[LossEstimate]]:
    """The SNR loss of every configuration against the float model with its LUT.

    ``result``: a :class:`dptbd.evaluation.compare.CompareResult`. Configurations that compute
    identical bits share their detector, hence their numbers.
    """
    plan = result.plan
    spec = plan.spec
    det = np.transpose(result.counts["detections"], (1, 2, 0))  # (D, S, N)
    pairs = []
    for d in plan.config_detector:
        pairs.append((d, plan.fixed_float[d - len(plan.floats)]))
    unique = sorted(set(pairs))
    est = bootstrap_losses(spec.snr_db, det, result.opportunities, unique, spec.pd_levels,
                           n_boot=spec.bootstrap, seed=spec.seed)
    by_pair = dict(zip(unique, est))
    return {f.name: by_pair[p] for f, p in zip(spec.configs, pairs)}


def verdict(losses: Sequence[LossEstimate], tolerance_db: float) -> str:
    """``"within"``, ``"beyond"`` or ``"undecided"`` (module docstring)."""
    if any(e.beyond(tolerance_db) for e in losses):
        return "beyond"
    if all(e.within(tolerance_db) for e in losses):
        return "within"
    return "undecided"


def cost_key(fixed, hardware: Mapping[str, Any] | None = None) -> tuple:
    """Sort key "smaller first" of a :class:`~dptbd.evaluation.compare.FixedSpec`."""
    cfg = fixed.cfg
    lut4 = hardware.get("lut4") if hardware else None
    return (cfg.state_bits, lut4 if lut4 is not None else 0,
            cfg.input_bits, cfg.weight_frac_bits)


def choose(configs, verdicts: Mapping[str, str], hardware: Mapping[str, Mapping] | None = None
           ) -> dict[str, str | None]:
    """The smallest sweep configuration ``"within"`` the tolerance, and the smallest not
    ``"beyond"`` it (``None`` when there is none). Only sweep members are considered
    (all configurations when none is in a sweep)."""
    pool = [f for f in configs if f.in_sweep] or list(configs)
    hardware = hardware or {}

    def best(ok) -> str | None:
        cands = [f for f in pool if ok(verdicts[f.name])]
        if not cands:
            return None
        return min(cands, key=lambda f: cost_key(f, hardware.get(f.name))).name

    return {"within": best(lambda v: v == "within"),
            "not_beyond": best(lambda v: v != "beyond")}


# ==== hardware cost ======================================================================

@dataclasses.dataclass(frozen=True)
class HardwareCost:
    """What synthesis says about one configuration (``None`` fields: not measured)."""

    lut4: int | None
    ff: int | None
    bram: int | None
    carry: int | None
    fmax_median_mhz: float | None
    fmax_mhz: tuple
    fits: bool | None
    logic_cells: int | None
    device: str
    package: str
    variant: str
    width: int
    height: int
    seconds: float
    cached: bool = False
    error: str | None = None

    def to_dict(self) -> dict:
        return dataclasses.asdict(self)


def default_cache_dir() -> pathlib.Path:
    """``$XDG_CACHE_HOME/dptbd/synth`` (``~/.cache/dptbd/synth``)."""
    import os
    base = os.environ.get("XDG_CACHE_HOME") or str(pathlib.Path.home() / ".cache")
    return pathlib.Path(base) / "dptbd" / "synth"


def hardware_key(cfg, *, variant: str, device: str, package: str, seeds: Sequence[int],
                 target_mhz: float, tools: Mapping[str, str], gateware: str = "") -> str:
    """Hash of everything that determines a synthesis result (``gateware``: :func:`gateware_hash`)."""
    blob = json.dumps({"params": cfg.to_mapping(), "variant": variant, "device": device,
                       "package": package, "seeds": list(seeds), "target_mhz": target_mhz,
                       "tools": dict(tools), "gateware": gateware}, sort_keys=True, default=str)
    return hashlib.sha256(blob.encode()).hexdigest()[:24]


def _tool_versions() -> dict[str, str]:
    from dptbd.hw.flow.synth import ICE40, YOSYS, require_tool, tool_version
    return {name: tool_version(require_tool(name)) for name in (YOSYS, ICE40.nextpnr)}


def check_tools() -> None:
    """Raise (naming the PyPI package) if Yosys or nextpnr-ice40 is missing."""
    from dptbd.hw.flow.synth import ICE40, YOSYS, require_tool
    require_tool(YOSYS)
    require_tool(ICE40.nextpnr)


def hardware_cost(cfg, *, variant: str = "core", device: str = "hx8k", package: str = "ct256",
                  seeds: Sequence[int] = (1, 2, 3), target_mhz: float = 100.0,
                  cache_dir: str | pathlib.Path | None = None, jobs: int = 1,
                  synthesize: Callable | None = None,
                  tools: Mapping[str, str] | None = None,
                  gateware: str | None = None) -> HardwareCost:
    """Synthesise the gateware for ``cfg`` (or read the cache) and summarise the cost.

    ``synthesize``: the flow (default :func:`dptbd.hw.flow.synth.synthesize`; a test passes a
    stand-in), called as ``synthesize(cfg, variant=, seeds=, device=, package=,
    target_mhz=, jobs=)`` and returning a ``SynthResult``-like object. ``tools``: tool
    versions for the cache key (default: asked from the installed tools). ``gateware``: the
    gateware's source hash for the key (default: :func:`gateware_hash` with the real flow,
    ``""`` with a stand-in).
    """
    if synthesize is None:
        from dptbd.hw.flow.synth import synthesize as flow
        synthesize = flow
        tools = _tool_versions() if tools is None else tools
        gateware = gateware_hash() if gateware is None else gateware
    tools = dict(tools or {})
    cache = pathlib.Path(cache_dir) if cache_dir is not None else default_cache_dir()
    key = hardware_key(cfg, variant=variant, device=device, package=package, seeds=seeds,
                       target_mhz=target_mhz, tools=tools, gateware=gateware or "")
    path = cache / f"{key}.json"
    if path.exists():
        data = json.loads(path.read_text())
        data["cached"] = True
        data["fmax_mhz"] = tuple(data.get("fmax_mhz", ()))
        return HardwareCost(**data)
    res = synthesize(cfg, variant=variant, seeds=tuple(seeds), device=device, package=package,
                     target_mhz=target_mhz, jobs=jobs)
    seconds = float(getattr(res, "yosys_seconds", 0.0) + getattr(res, "verilog_seconds", 0.0)
                    + sum(getattr(r, "seconds", 0.0) for r in getattr(res, "runs", ())))
    util = getattr(res, "utilisation", {}) or {}
    lc = util.get("ICESTORM_LC")
    cost = HardwareCost(
        lut4=res.cells.lut4, ff=res.cells.dff, bram=res.cells.bram, carry=res.cells.carry,
        fmax_median_mhz=res.fmax_median_mhz, fmax_mhz=tuple(res.fmaxes_mhz), fits=res.fits,
        logic_cells=None if lc is None else int(lc[0]), device=device, package=package,
        variant=variant, width=cfg.width, height=cfg.height, seconds=round(seconds, 1))
    cache.mkdir(parents=True, exist_ok=True)
    data = cost.to_dict()
    data.pop("cached")
    data["fmax_mhz"] = list(data["fmax_mhz"])
    tmp = path.with_suffix(".tmp")
    tmp.write_text(json.dumps(data, indent=1, sort_keys=True))
    tmp.replace(path)
    return cost


def state_store_bits(cfg) -> int:
    """Bits of the (E, d) state store for a whole frame: W * H * (B_E + B_d)."""
    return cfg.width * cfg.height * cfg.state_bits
