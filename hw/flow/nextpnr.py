"""``nextpnr-ice40`` place and route of a Yosys netlist: Fmax, utilisation, fit."""

from __future__ import annotations

import dataclasses
import json
import pathlib
import re
from typing import Mapping, Sequence

from dptbd.hw.flow.tools import SynthToolError, _run, _tail, require_tool

__all__ = [
    "ICE40_DEVICES", "PnrReport", "PnrRun",
    "parse_nextpnr_log", "parse_nextpnr_report", "pick_clock", "run_nextpnr",
]

#: Devices ``nextpnr-ice40`` knows (``--hx8k`` …).
ICE40_DEVICES = ("lp384", "lp1k", "lp4k", "lp8k", "hx1k", "hx4k", "hx8k",
                 "up3k", "up5k", "u1k", "u2k", "u4k")

#: Causes of a nextpnr failure that mean "the design does not fit this device".
_NO_FIT_PATTERNS = (
    re.compile(r"no BELs remaining", re.I),
    re.compile(r"Unable to place cell", re.I),
    re.compile(r"Unable to find legal placement", re.I),
    re.compile(r"failed to place", re.I),
    re.compile(r"Failed to route", re.I),
    re.compile(r"Failed to expand region", re.I),
)

_FMAX_RE = re.compile(
    r"Max frequency for clock\s+'(?P<clock>[^']+)':\s+(?P<fmax>[0-9.]+)\s+MHz"
    r"(?:\s+\((?P<verdict>PASS|FAIL)\s+at\s+(?P<target>[0-9.]+)\s+MHz\))?")
_UTIL_RE = re.compile(r"^Info:\s+(?P<bel>[A-Za-z0-9_]+):\s+(?P<used>\d+)/\s*(?P<avail>\d+)\s+\d+%",
                      re.M)
_ERROR_RE = re.compile(r"^ERROR:\s*(?P<msg>.*)$", re.M)


@dataclasses.dataclass(frozen=True)
class PnrReport:
    """What a nextpnr log (or ``--report`` JSON) says.

    ``fmax`` maps each clock to its **final** (post-route) Fmax in MHz; ``utilisation`` each
    BEL type to ``(used, available)``; ``errors`` lists the ``ERROR:`` messages.
    """

    fmax: Mapping[str, float]
    utilisation: Mapping[str, tuple[int, int]]
    errors: tuple[str, ...] = ()

    @property
    def over_capacity(self) -> tuple[str, ...]:
        """BEL types used beyond what the device has."""
        return tuple(b for b, (used, avail) in self.utilisation.items() if used > avail)

    @property
    def no_fit_error(self) -> str | None:
        """The first error that means the design does not fit (placement / routing), if any."""
        for err in self.errors:
            if any(p.search(err) for p in _NO_FIT_PATTERNS):
                return err
        return None


def parse_nextpnr_log(text: str) -> PnrReport:
    """Parse a ``nextpnr-ice40`` log.

    The log prints ``Max frequency for clock 'X': F MHz (PASS|FAIL at T MHz)`` after
    placement and again after routing; the last line per clock (post-route) wins. The
    ``Device utilisation:`` block gives ``BEL: used/ available``.
    """
    fmax: dict[str, float] = {}
    for m in _FMAX_RE.finditer(text):
        fmax[m.group("clock")] = float(m.group("fmax"))
    util: dict[str, tuple[int, int]] = {}
    start = text.rfind("Device utilisation:")
    if start >= 0:
        for line in text[start:].splitlines()[1:]:
            m = _UTIL_RE.match(line)
            if not m:
                break
            util[m.group("bel")] = (int(m.group("used")), int(m.group("avail")))
    errors = tuple(m.group("msg").strip() for m in _ERROR_RE.finditer(text))
    return PnrReport(fmax=fmax, utilisation=util, errors=errors)


def parse_nextpnr_report(text: str) -> PnrReport:
    """Parse the JSON written by ``nextpnr --report`` (keys ``fmax`` and ``utilization``)."""
    data = json.loads(text)
    fmax = {str(c): float(v["achieved"]) for c, v in data.get("fmax", {}).items()}
    util = {str(b): (int(v["used"]), int(v["available"]))
            for b, v in data.get("utilization", {}).items()}
    return PnrReport(fmax=fmax, utilisation=util)


def pick_clock(fmax: Mapping[str, float], clock: str = "clk") -> str | None:
    """The clock of interest among nextpnr's names (``clk$SB_IO_IN_$glb_clk`` for ``clk``).

    The only clock if there is one; else the one named ``clock`` or ``clock$…``.
    """
    if len(fmax) == 1:
        return next(iter(fmax))
    matches = [c for c in fmax if c == clock or c.startswith(clock + "$")]
    return matches[0] if len(matches) == 1 else None


@dataclasses.dataclass(frozen=True)
class PnrRun:
    """One nextpnr run (one placement seed).

    ``fits``: placed and routed. ``fmax_mhz``: post-route Fmax of the clock (``None`` when it
    did not fit). ``utilisation``: ``{BEL type: (used, available)}``, also when it did not
    fit (then some type is above 100 %). ``error``: nextpnr's reason when it did not fit.
    """

    seed: int
    fits: bool
    fmax_mhz: float | None
    target_mhz: float
    utilisation: Mapping[str, tuple[int, int]]
    seconds: float
    error: str | None = None
    clock: str | None = None
    log_path: str | None = None

    @property
    def meets_target(self) -> bool:
        return self.fmax_mhz is not None and self.fmax_mhz >= self.target_mhz

    def used(self, bel: str) -> int | None:
        """Used count of BEL type ``bel`` (``ICESTORM_LC``, ``ICESTORM_RAM``, …)."""
        return self.utilisation[bel][0] if bel in self.utilisation else None

    def to_dict(self) -> dict:
        return {"seed": self.seed, "fits": self.fits, "fmax_mhz": self.fmax_mhz,
                "target_mhz": self.target_mhz, "meets_target": self.meets_target,
                "clock": self.clock, "error": self.error, "seconds": round(self.seconds, 1),
                "utilisation": {b: {"used": u, "available": a}
                                for b, (u, a) in self.utilisation.items()},
                "log": self.log_path}


def run_nextpnr(netlist: pathlib.Path, *, seed: int, device: str = "hx8k",
                package: str = "ct256", target_mhz: float = 100.0, clock: str = "clk",
                nextpnr: str = "nextpnr-ice40", timeout: float = 1800,
                extra_args: Sequence[str] = ()) -> PnrRun:
    """Place and route ``netlist`` once (``--seed seed``); log ``nextpnr-seed<N>.log``.

    Runs with ``--pcf-allow-unconstrained`` (pins placed automatically) and
    ``--timing-allow-fail`` (a missed target is reported in ``fmax_mhz``, not an error).
    A design that does not fit returns ``fits=False``; other failures raise
    :class:`SynthToolError`.
    """
    if device not in ICE40_DEVICES:
        raise ValueError(f"device must be one of {ICE40_DEVICES}, got {device!r}")
    exe = require_tool(nextpnr)
    work = netlist.parent
    log = work / f"nextpnr-seed{seed}.log"
    report = work / f"nextpnr-seed{seed}.report.json"
    for stale in (log, report):
        stale.unlink(missing_ok=True)
    cmd = [exe, f"--{device}", "--package", package, "--json", netlist.name,
           "--freq", f"{target_mhz:g}", "--pcf-allow-unconstrained", "--timing-allow-fail",
           "--seed", str(seed), "--report", report.name, "-l", log.name, "-q", *extra_args]
    proc, seconds = _run(cmd, cwd=work, timeout=timeout, tool="nextpnr", log_path=log)
    log_text = log.read_text(errors="replace") if log.exists() else ""
    parsed = parse_nextpnr_log(log_text + "\n" + proc.stderr)
    if proc.returncode == 0 and report.exists():
        from_json = parse_nextpnr_report(report.read_text())
        parsed = PnrReport(fmax=from_json.fmax or parsed.fmax,
                           utilisation=from_json.utilisation or parsed.utilisation,
                           errors=parsed.errors)
    if proc.returncode == 0:
        name = pick_clock(parsed.fmax, clock)
        if name is None:
            raise SynthToolError(f"nextpnr finished but reported no Fmax for clock {clock!r} "
                                 f"(clocks: {sorted(parsed.fmax)})", tool="nextpnr",
                                 returncode=0, log_tail=_tail(log_text))
        return PnrRun(seed=seed, fits=True, fmax_mhz=parsed.fmax[name], target_mhz=target_mhz,
                      utilisation=parsed.utilisation, seconds=seconds, clock=name,
                      log_path=str(log))
    over = parsed.over_capacity
    reason = parsed.no_fit_error
    if over or reason:
        parts = []
        if over:
            parts.append("over capacity: " + ", ".join(
                f"{b} {parsed.utilisation[b][0]}/{parsed.utilisation[b][1]}" for b in over))
        if reason:
            parts.append("nextpnr: " + reason)
        reason = "; ".join(parts)
        return PnrRun(seed=seed, fits=False, fmax_mhz=None, target_mhz=target_mhz,
                      utilisation=parsed.utilisation, seconds=seconds, error=reason,
                      log_path=str(log))
    raise SynthToolError(f"nextpnr failed (exit {proc.returncode}): {' '.join(cmd)}",
                         tool="nextpnr", returncode=proc.returncode,
                         log_tail=_tail(log_text or proc.stderr))
