"""Scenario files (TOML) for ``dptbd run``: the scene or data, the ADC, the DP, the thresholds.

The built-in scenario (:func:`default_scenario`) is paper 001's second experiment (001 §4,
"第二组"): 128 x 128, 100 frames, SNR 2.0, two targets — start (30, 100) with
V = (0.8, -0.4) and start (54, 40) with V = (0.4, 0.6) — and a constant false-alarm rate
of 0.2 %. Its TOML form (``Scenario.to_toml``, also written into every output folder)::

    name = "paper001-experiment-2"

    [scene]                    # a simulated scene (or [input] for recorded data)
    size = [128, 128]          # height, width
    frames = 100
    mu = 30.0                  # noise mean (001 §4: 30)
    sigma = 1.7320508075688772 # noise standard deviation (001 §4: variance 3.0)
    snr = 2.0                  # 001's SNR = (target mean - noise mean) / sigma
    seed = 0

    [[scene.targets]]
    start = [30.0, 100.0]      # (row, col) at frame 0 (001's start, read as (row, col))
    velocity = [0.8, -0.4]     # (row, col) pixels/frame (001's (Vx, Vy))
    # snr = 2.0                # this target's SNR (default [scene].snr)
    # birth = 0                # first frame present
    # death = 80               # first frame gone
    # turns = [{frame = 50, degrees = 90.0}]   # or {frame = 50, velocity = [0.5, 0.5]}

    [adc]                      # float scene -> integer frames (dptbd.scenes.synthetic.quantise)
    bits = 12
    gain = 16.0
    offset = 0.0

    [dp]                       # dptbd.config.DPConfig fields except width, height, input_bits
    segment_frames = 6

    [segmentation]
    false_alarm_rate = 0.002   # candidates per accumulated frame = round(rate * H * W)
    lists = "gateware"         # what the DSP receives: "gateware" (the segmenter's lists,
                               # previous segment's histogram) or "ideal" (own histogram)

    [association]              # dptbd.dsp.association.AssociationConfig fields
    capacity = 64

    [report]
    frame = 50                 # the raw frame shown in raw_frame.png (default: the middle)

Recorded data replaces ``[scene]`` and ``[adc]`` by::

    [input]
    path = "frames.npz"        # .npy, .npz or a folder of PNG/TIFF frames; relative to the file
    key = "frames"             # the array inside an .npz (default: its only array, or "frames")

Every table and key is checked: an unknown one is refused by name, with the allowed ones.
"""

from __future__ import annotations

import dataclasses
import pathlib
import tomllib
from typing import Any, Mapping

from dptbd.config import DPConfig, non_saturating_energy_bits
from dptbd.errors import ConfigError, DptbdError, check_int, check_real
from dptbd.toml_writer import dump_toml
from dptbd.evaluation.chain import LISTS
from dptbd.scenes import synthetic as scenes
from dptbd.scenes.reach import check_reach
from dptbd.dsp.association import AssociationConfig, AssociationError

__all__ = ["ScenarioError", "TargetSpec", "Scenario", "default_scenario", "load_scenario",
           "parse_scenario", "parse_target", "check_snr", "DEFAULT_NAME"]


class ScenarioError(DptbdError):
    """A scenario file or option is invalid; the message names the key."""


@dataclasses.dataclass(frozen=True)
class TargetSpec:
    """One simulated target: ``start`` and ``velocity`` as (row, col)."""

    start: tuple[float, float]
    velocity: tuple[float, float]
    snr: float | None = None
    birth: int = 0
    death: int | None = None
    turns: tuple[dict, ...] = ()

    def target(self, default_snr: float, sigma: float) -> scenes.Target:
        snr = default_snr if self.snr is None else self.snr
        turns = tuple(scenes.Turn(**t) for t in self.turns)
        return scenes.Target(self.start, self.velocity, scenes.amplitude_from_snr(snr, sigma),
                             birth=self.birth, death=self.death, turns=turns)

    def to_dict(self) -> dict:
        out: dict[str, Any] = {"start": list(self.start), "velocity": list(self.velocity)}
        if self.snr is not None:
            out["snr"] = self.snr
        if self.birth:
            out["birth"] = self.birth
        if self.death is not None:
            out["death"] = self.death
        if self.turns:
            out["turns"] = [dict(t) for t in self.turns]
        return out


#: The built-in scenario's name; recorded data without a name is named after its input.
DEFAULT_NAME = "paper001-experiment-2"


@dataclasses.dataclass(frozen=True)
class Scenario:
    """Everything ``dptbd run`` needs besides the output folder."""

    name: str = DEFAULT_NAME
    height: int = 128
    width: int = 128
    frames: int = 100
    mu: float = scenes.TABLE1_MU
    sigma: float = scenes.TABLE1_SIGMA
    snr: float = 2.0
    seed: int = 0
    targets: tuple[TargetSpec, ...] = (
        TargetSpec((30.0, 100.0), (0.8, -0.4)),
        TargetSpec((54.0, 40.0), (0.4, 0.6)),
    )
    adc_bits: int = 12
    adc_gain: float = 16.0
    adc_offset: float = 0.0
    dp: Mapping[str, Any] = dataclasses.field(default_factory=lambda: {"segment_frames": 6})
    false_alarm_rate: float = 0.002
    lists: str = "gateware"
    association: Mapping[str, Any] = dataclasses.field(default_factory=dict)
    input_path: pathlib.Path | None = None
    input_key: str | None = None
    report_frame: int | None = None

    @property
    def simulated(self) -> bool:
        """True for a generated scene (with ground truth), False for recorded data."""
        return self.input_path is None

    def replace(self, **changes: Any) -> "Scenario":
        return dataclasses.replace(self, **changes)

    # ---- the objects the job needs --------------------------------------------------
    def dp_config(self, *, height: int, width: int, input_bits: int) -> DPConfig:
        """The DPConfig: ``[dp]`` plus the frame size and B_in of the data.

        ``energy_bits`` defaults to the width that never saturates (at least 16).
        """
        values = dict(self.dp)
        values.setdefault("segment_frames", 6)
        k = values["segment_frames"]
        if "energy_bits" not in values and isinstance(k, int) and not isinstance(k, bool) and k > 0:
            values["energy_bits"] = min(32, max(16, non_saturating_energy_bits(input_bits, k)))
        return DPConfig.from_mapping({**values, "height": height, "width": width,
                                      "input_bits": input_bits})

    def assoc_config(self) -> AssociationConfig:
        return AssociationConfig.from_mapping(self.association)

    def make_scene(self) -> scenes.Scene:
        """The simulated scene (float frames and ground truth)."""
        targets = [t.target(self.snr, self.sigma) for t in self.targets]
        scene = scenes.make_scene((self.height, self.width), self.frames, targets, mu=self.mu,
                                  sigma=self.sigma, seed=self.seed)
        scene.params.update(scenario=self.name, snr=self.snr)
        return scene

    def check(self) -> None:
        """Build every object once so that a bad value is refused before any work."""
        try:
            if self.simulated:
                cfg = self.dp_config(height=self.height, width=self.width, input_bits=self.adc_bits)
                for where, snr in [("[scene] snr", self.snr)] + [
                        (f"target {i + 1} snr", t.snr) for i, t in enumerate(self.targets)
                        if t.snr is not None]:
                    check_snr(where, snr)
                check_reach([t.target(self.snr, self.sigma) for t in self.targets],
                            (self.height, self.width), self.frames, cfg.radius)
                scenes.quantise([0.0], self.adc_bits, gain=self.adc_gain, offset=self.adc_offset)
                if self.report_frame is not None and not 0 <= self.report_frame < self.frames:
                    raise ScenarioError(f"[report] frame must be in [0, {self.frames - 1}], "
                                        f"got {self.report_frame}")
            else:
                self.dp_config(height=16, width=16, input_bits=8)
            self.assoc_config()
            if not 0.0 < self.false_alarm_rate <= 1.0:
                raise ScenarioError(f"[segmentation] false_alarm_rate must be in (0, 1], got "
                                    f"{self.false_alarm_rate}")
            if self.lists not in LISTS:
                raise ScenarioError(f"[segmentation] lists must be one of "
                                    f"{', '.join(map(repr, LISTS))}, got {self.lists!r}")
        except (ConfigError, AssociationError, scenes.SceneError, TypeError) as exc:
            raise ScenarioError(f"scenario {self.name!r}: {exc}") from exc

    # ---- TOML ------------------------------------------------------------------------
    def to_dict(self) -> dict:
        out: dict[str, Any] = {"name": self.name}
        if self.simulated:
            out["scene"] = {"size": [self.height, self.width], "frames": self.frames,
                            "mu": self.mu, "sigma": self.sigma, "snr": self.snr,
                            "seed": self.seed, "targets": [t.to_dict() for t in self.targets]}
            out["adc"] = {"bits": self.adc_bits, "gain": self.adc_gain, "offset": self.adc_offset}
        else:
            out["input"] = {"path": str(self.input_path)}
            if self.input_key is not None:
                out["input"]["key"] = self.input_key
        out["dp"] = {k: (v if k != "weights" else [list(r) for r in v]) for k, v in self.dp.items()}
        out["segmentation"] = {"false_alarm_rate": self.false_alarm_rate, "lists": self.lists}
        out["association"] = dict(self.association)
        if self.report_frame is not None:
            out["report"] = {"frame": self.report_frame}
        return out

    def to_toml(self) -> str:
        return dump_toml(self.to_dict())


def default_scenario() -> Scenario:
    """Paper 001's second experiment (001 §4): the scenario of ``dptbd run`` with no arguments."""
    return Scenario()


# ---- parsing ----------------------------------------------------------------------------

_TOP = {"name", "scene", "adc", "dp", "segmentation", "association", "input", "report"}
_SCENE = {"size", "frames", "mu", "sigma", "snr", "seed", "targets"}
_TARGET = {"start", "velocity", "snr", "birth", "death", "turns"}
_TURN = {"frame", "degrees", "velocity"}
_ADC = {"bits", "gain", "offset"}
_SEG = {"false_alarm_rate", "lists"}
_INPUT = {"path", "key"}
_REPORT = {"frame"}
_DP_FIXED = {"width", "height", "input_bits"}


def _check_keys(where: str, table: Any, allowed: set[str]) -> dict:
    if not isinstance(table, Mapping):
        raise ScenarioError(f"{where} must be a table, got {type(table).__name__}")
    unknown = sorted(set(table) - allowed)
    if unknown:
        raise ScenarioError(f"unknown key(s) {unknown} in {where}; allowed: {sorted(allowed)}")
    return dict(table)


def _int(where: str, v: Any, lo: int) -> int:
    """An integer >= ``lo`` (:func:`dptbd.errors.check_int`'s message)."""
    return check_int(where, v, lo, error=ScenarioError)


def _real(where: str, v: Any, *, positive: bool = False) -> float:
    """A finite real number, > 0 if ``positive`` (:func:`dptbd.errors.check_real`'s message)."""
    if positive:
        return check_real(where, v, 0.0, lo_open=True, error=ScenarioError)
    return check_real(where, v, error=ScenarioError)


def check_snr(where: str, snr: Any) -> float:
    """001's SNR, (target mean - noise mean) / sigma: a finite real number > 0, else refused
    (:func:`dptbd.errors.check_real`'s message, the SNR's definition in its name)."""
    return check_real(f"{where} (001's SNR = (target mean - noise mean) / sigma)", snr, 0.0,
                      lo_open=True, error=ScenarioError)


def _pair(where: str, v: Any) -> tuple[float, float]:
    if not isinstance(v, (list, tuple)) or len(v) != 2:
        raise ScenarioError(f"{where} must be a pair [row, col] of numbers, got {v!r}")
    return (_real(f"{where}[0]", v[0]), _real(f"{where}[1]", v[1]))


def parse_target(where: str, table: Any) -> TargetSpec:
    """One ``[[scene.targets]]`` table."""
    t = _check_keys(where, table, _TARGET)
    for key in ("start", "velocity"):
        if key not in t:
            raise ScenarioError(f"{where} needs '{key}' = [row, col]")
    turns = []
    for i, turn in enumerate(t.get("turns", [])):
        tw = _check_keys(f"{where}.turns[{i}]", turn, _TURN)
        if "frame" not in tw:
            raise ScenarioError(f"{where}.turns[{i}] needs 'frame'")
        tw["frame"] = _int(f"{where}.turns[{i}].frame", tw["frame"], 1)
        if "velocity" in tw:
            tw["velocity"] = _pair(f"{where}.turns[{i}].velocity", tw["velocity"])
        if "degrees" in tw:
            tw["degrees"] = _real(f"{where}.turns[{i}].degrees", tw["degrees"])
        turns.append(tw)
    return TargetSpec(
        start=_pair(f"{where}.start", t["start"]), velocity=_pair(f"{where}.velocity", t["velocity"]),
        snr=None if "snr" not in t else _real(f"{where}.snr", t["snr"], positive=True),
        birth=_int(f"{where}.birth", t.get("birth", 0), 0),
        death=None if "death" not in t else _int(f"{where}.death", t["death"], 1),
        turns=tuple(turns))


def parse_scenario(data: Mapping[str, Any], base_dir: pathlib.Path | None = None) -> Scenario:
    """A :class:`Scenario` from a parsed TOML document (unknown keys refused)."""
    top = _check_keys("the scenario file", data, _TOP)
    changes: dict[str, Any] = {}
    if "name" in top:
        if not isinstance(top["name"], str):
            raise ScenarioError(f"name must be a string, got {top['name']!r}")
        changes["name"] = top["name"]
    if "input" in top:
        if "scene" in top or "adc" in top:
            raise ScenarioError("give either [scene] (a simulated scene) or [input] (recorded "
                                "data), not both; [adc] belongs to [scene]")
        inp = _check_keys("[input]", top["input"], _INPUT)
        if not isinstance(inp.get("path"), str):
            raise ScenarioError("[input] needs path = \"FILE.npy|FILE.npz|FOLDER\"")
        path = pathlib.Path(inp["path"]).expanduser()
        if base_dir is not None and not path.is_absolute():
            path = base_dir / path
        changes["input_path"] = path
        if "name" not in top:
            changes["name"] = path.name       # recorded data: named after its file or folder
        if "key" in inp:
            if not isinstance(inp["key"], str):
                raise ScenarioError(f"[input] key must be a string, got {inp['key']!r}")
            changes["input_key"] = inp["key"]
    if "scene" in top:
        sc = _check_keys("[scene]", top["scene"], _SCENE)
        if "size" in sc:
            size = sc["size"]
            if not isinstance(size, list) or len(size) != 2:
                raise ScenarioError(f"[scene] size must be [height, width], got {size!r}")
            changes["height"] = _int("[scene] size[0] (height)", size[0], 3)
            changes["width"] = _int("[scene] size[1] (width)", size[1], 3)
        if "frames" in sc:
            changes["frames"] = _int("[scene] frames", sc["frames"], 1)
        if "mu" in sc:
            changes["mu"] = _real("[scene] mu", sc["mu"])
        if "sigma" in sc:
            changes["sigma"] = _real("[scene] sigma", sc["sigma"], positive=True)
        if "snr" in sc:
            changes["snr"] = _real("[scene] snr", sc["snr"], positive=True)
        if "seed" in sc:
            changes["seed"] = _int("[scene] seed", sc["seed"], 0)
        if "targets" in sc:
            if not isinstance(sc["targets"], list):
                raise ScenarioError("[scene] targets must be an array of tables [[scene.targets]]")
            changes["targets"] = tuple(parse_target(f"[[scene.targets]] #{i + 1}", t)
                                       for i, t in enumerate(sc["targets"]))
    if "adc" in top:
        adc = _check_keys("[adc]", top["adc"], _ADC)
        if "bits" in adc:
            changes["adc_bits"] = _int("[adc] bits", adc["bits"], 1)
        if "gain" in adc:
            changes["adc_gain"] = _real("[adc] gain", adc["gain"])
        if "offset" in adc:
            changes["adc_offset"] = _real("[adc] offset", adc["offset"])
    if "dp" in top:
        dp = _check_keys("[dp]", top["dp"], {f.name for f in dataclasses.fields(DPConfig)})
        fixed = sorted(set(dp) & _DP_FIXED)
        if fixed:
            raise ScenarioError(f"[dp] {fixed}: the frame size and input width come from [scene]/"
                                f"[adc] or from the data, not from [dp]")
        changes["dp"] = {"segment_frames": 6, **dp}
    if "segmentation" in top:
        seg = _check_keys("[segmentation]", top["segmentation"], _SEG)
        if "false_alarm_rate" in seg:
            changes["false_alarm_rate"] = _real("[segmentation] false_alarm_rate",
                                                seg["false_alarm_rate"], positive=True)
        if "lists" in seg:
            changes["lists"] = seg["lists"]
    if "association" in top:
        known = {f.name for f in dataclasses.fields(AssociationConfig)}
        changes["association"] = _check_keys("[association]", top["association"], known)
    if "report" in top:
        rep = _check_keys("[report]", top["report"], _REPORT)
        if "frame" in rep:
            changes["report_frame"] = _int("[report] frame", rep["frame"], 0)
    scenario = Scenario(**changes)
    scenario.check()
    return scenario


def load_scenario(path: str | pathlib.Path) -> Scenario:
    """Read and check a scenario file; relative ``[input] path`` is relative to the file."""
    path = pathlib.Path(path)
    if not path.exists():
        raise FileNotFoundError(f"scenario file {path} does not exist")
    if not path.is_file():
        raise ScenarioError(f"scenario file {path} is not a file")
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise ScenarioError(f"scenario file {path} is not valid TOML: {exc}") from exc
    except OSError as exc:
        raise ScenarioError(f"cannot read scenario file {path}: {exc}") from exc
    try:
        return parse_scenario(data, path.resolve().parent)
    except ScenarioError as exc:
        raise ScenarioError(f"{path}: {exc}") from exc
