"""nextpnr (``nextpnr-ice40``, ``nextpnr-ecp5``) place and route of a Yosys netlist: Fmax,
utilisation, critical path, fit."""

from __future__ import annotations

import dataclasses
import json
import pathlib
import re
from typing import Mapping, Sequence

from dptbd.hw.flow.family import ICE40, Family
from dptbd.hw.flow.tools import SynthToolError, ToolTimeoutError, _run, _tail, require_tool

__all__ = [
    "ICE40_DEVICES", "CriticalPath", "PnrReport", "PnrRun",
    "parse_nextpnr_log", "parse_nextpnr_report", "pick_clock", "run_nextpnr",
]

#: Devices ``nextpnr-ice40`` knows (``--hx8k`` …).
ICE40_DEVICES = ICE40.devices

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
class CriticalPath:
    """The slowest register-to-register path of a clock (from ``nextpnr --report``).

    ``start`` / ``end``: the cells (hierarchical names: ``max_tree.node_l1_3…``);
    ``logic_ns`` / ``routing_ns``: the delay in cells (clock-to-out, LUTs, carries, setup)
    and in wires; ``steps``: the path's segments.
    """

    start: str
    end: str
    logic_ns: float
    routing_ns: float
    steps: int

    @property
    def total_ns(self) -> float:
        return self.logic_ns + self.routing_ns

    def to_dict(self) -> dict:
        return {"start": self.start, "end": self.end, "total_ns": round(self.total_ns, 3),
                "logic_ns": round(self.logic_ns, 3), "routing_ns": round(self.routing_ns, 3),
                "steps": self.steps}


@dataclasses.dataclass(frozen=True)
class PnrReport:
    """What a nextpnr log (or ``--report`` JSON) says.

    ``fmax`` maps each clock to its **final** (post-route) Fmax in MHz; ``utilisation`` each
    BEL type to ``(used, available)``; ``errors`` lists the ``ERROR:`` messages.
    """

    fmax: Mapping[str, float]
    utilisation: Mapping[str, tuple[int, int]]
    errors: tuple[str, ...] = ()
    critical_path: CriticalPath | None = None

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
    """Parse a nextpnr log (``nextpnr-ice40`` and ``nextpnr-ecp5`` write the same lines).

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


def _critical_path(paths: Sequence[Mapping]) -> CriticalPath | None:
    """The longest clock-to-same-clock path of the report's ``critical_paths`` (``posedge
    clk`` to ``posedge clk``; I/O paths, ``<async>``, are left out)."""
    best = None
    for p in paths:
        steps = p.get("path", [])
        edge = str(p.get("from", ""))
        if not steps or edge != p.get("to") or not edge.startswith(("posedge ", "negedge ")):
            continue
        routing = sum(float(s["delay"]) for s in steps if s.get("type") == "routing")
        logic = sum(float(s["delay"]) for s in steps if s.get("type") != "routing")
        cand = CriticalPath(start=steps[0]["from"]["cell"], end=steps[-1]["to"]["cell"],
                            logic_ns=logic, routing_ns=routing, steps=len(steps))
        if best is None or cand.total_ns > best.total_ns:
            best = cand
    return best


def parse_nextpnr_report(text: str) -> PnrReport:
    """Parse the JSON written by ``nextpnr --report`` (keys ``fmax``, ``utilization`` and
    ``critical_paths``)."""
    data = json.loads(text)
    fmax = {str(c): float(v["achieved"]) for c, v in data.get("fmax", {}).items()}
    util = {str(b): (int(v["used"]), int(v["available"]))
            for b, v in data.get("utilization", {}).items()}
    return PnrReport(fmax=fmax, utilisation=util,
                     critical_path=_critical_path(data.get("critical_paths", [])))


def pick_clock(fmax: Mapping[str, float], clock: str = "clk") -> str | None:
    """The clock of interest among nextpnr's names (``clk$SB_IO_IN_$glb_clk`` on iCE40,
    ``$glbnet$clk$TRELLIS_IO_IN`` on ECP5, for ``clk``).

    The only clock if there is one; else the one named ``clock``, ``clock$…`` or
    ``$glbnet$clock$…``.
    """
    if len(fmax) == 1:
        return next(iter(fmax))
    matches = [c for c in fmax if c == clock or c.startswith(clock + "$")
               or c.startswith(f"$glbnet${clock}$")]
    return matches[0] if len(matches) == 1 else None


@dataclasses.dataclass(frozen=True)
class PnrRun:
    """One nextpnr run (one placement seed).

    ``fits``: placed and routed. ``fmax_mhz``: post-route Fmax of the clock (``None`` when it
    did not fit). ``utilisation``: ``{BEL type: (used, available)}``, also when it did not
    fit (then some type is above 100 %). ``error``: nextpnr's reason when it did not fit.
    ``timed_out``: nextpnr was stopped at its time limit (``fits`` False, ``fmax_mhz`` None,
    ``error`` ``"did not route in N s"``: whether it fits is not known).
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
    critical_path: CriticalPath | None = None
    timed_out: bool = False

    @property
    def meets_target(self) -> bool:
        return self.fmax_mhz is not None and self.fmax_mhz >= self.target_mhz

    def used(self, bel: str) -> int | None:
        """Used count of BEL type ``bel`` (``ICESTORM_LC``, ``ICESTORM_RAM``, …)."""
        return self.utilisation[bel][0] if bel in self.utilisation else None

    def to_dict(self) -> dict:
        return {"seed": self.seed, "fits": self.fits, "fmax_mhz": self.fmax_mhz,
                "target_mhz": self.target_mhz, "meets_target": self.meets_target,
                "clock": self.clock, "error": self.error, "timed_out": self.timed_out,
                "seconds": round(self.seconds, 1),
                "utilisation": {b: {"used": u, "available": a}
                                for b, (u, a) in self.utilisation.items()},
                "critical_path": (None if self.critical_path is None
                                  else self.critical_path.to_dict()),
                "log": self.log_path}


def run_nextpnr(netlist: pathlib.Path, *, seed: int, device: str | None = None,
                package: str | None = None, target_mhz: float | None = None,
                clock: str = "clk", family: Family = ICE40, nextpnr: str | None = None,
                timeout: float = 1800, extra_args: Sequence[str] = ()) -> PnrRun:
    """Place and route ``netlist`` once (``--seed seed``); log ``nextpnr-seed<N>.log``.

    ``device``, ``package``, ``target_mhz`` and ``nextpnr`` default to the ``family``'s.
    Runs with the family's unconstrained-I/O flag (pins placed automatically) and
    ``--timing-allow-fail`` (a missed target is reported in ``fmax_mhz``, not an error).
    A design that does not fit returns ``fits=False``; a run still going after ``timeout``
    seconds is stopped (:class:`~dptbd.hw.flow.tools.ToolTimeoutError` of the tool call) and
    returns ``timed_out=True`` with ``error`` ``"did not route in N s"`` (router1 can stall
    for hours on a seed whose overused wires do not fall); other failures raise
    :class:`SynthToolError`.
    """
    device = family.default_device if device is None else device
    package = family.default_package if package is None else package
    target_mhz = family.default_target_mhz if target_mhz is None else target_mhz
    device_args = family.device_args(device, package)      # ValueError before any work
    exe = require_tool(family.nextpnr if nextpnr is None else nextpnr)
    work = netlist.parent
    log = work / f"nextpnr-seed{seed}.log"
    report = work / f"nextpnr-seed{seed}.report.json"
    for stale in (log, report):
        stale.unlink(missing_ok=True)
    cmd = [exe, *device_args, "--json", netlist.name,
           "--freq", f"{target_mhz:g}", family.unconstrained_flag, "--timing-allow-fail",
           "--seed", str(seed), "--report", report.name, "-l", log.name, "-q", *extra_args]
    try:
        proc, seconds = _run(cmd, cwd=work, timeout=timeout, tool="nextpnr", log_path=log)
    except ToolTimeoutError:
        proc = None
    log_text = log.read_text(errors="replace") if log.exists() else ""
    if proc is None:
        return PnrRun(seed=seed, fits=False, fmax_mhz=None, target_mhz=target_mhz,
                      utilisation=parse_nextpnr_log(log_text).utilisation, seconds=timeout,
                      error=f"did not route in {timeout:g} s", log_path=str(log),
                      timed_out=True)
    parsed = parse_nextpnr_log(log_text + "\n" + proc.stderr)
    if proc.returncode == 0 and report.exists():
        from_json = parse_nextpnr_report(report.read_text())
        parsed = PnrReport(fmax=from_json.fmax or parsed.fmax,
                           utilisation=from_json.utilisation or parsed.utilisation,
                           errors=parsed.errors, critical_path=from_json.critical_path)
    if proc.returncode == 0:
        name = pick_clock(parsed.fmax, clock)
        if name is None:
            raise SynthToolError(f"nextpnr finished but reported no Fmax for clock {clock!r} "
                                 f"(clocks: {sorted(parsed.fmax)})", tool="nextpnr",
                                 returncode=0, log_tail=_tail(log_text))
        return PnrRun(seed=seed, fits=True, fmax_mhz=parsed.fmax[name], target_mhz=target_mhz,
                      utilisation=parsed.utilisation, seconds=seconds, clock=name,
                      log_path=str(log), critical_path=parsed.critical_path)
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
