"""The main job of ``dptbd run`` as a library function: a scenario through the FPGA stage and
the DSP stage, with its tables (:func:`run_job` -> :class:`RunResult`).

1. :func:`prepare` loads the data (a simulated scene quantised by the scenario's ADC, or
   recorded frames), derives the DP and segmenter parameters and checks that the sequence
   can be accumulated.
2. :func:`run_job` optionally checks the generated Verilog on the frames
   (:mod:`dptbd.evaluation.run.rtl`), runs both stages
   (:func:`dptbd.evaluation.chain.run_pipeline`), scores the tracks against the ground
   truth and builds the tables (:mod:`dptbd.evaluation.run.report`).

Nothing is written: :func:`dptbd.evaluation.run.report.write_run_folder` writes a result's
folder. What the job says while it runs goes to ``log`` (``print`` in the command).

Example::

    from dptbd.evaluation.run.job import run_job
    from dptbd.evaluation.run.scenario import default_scenario

    result = run_job(default_scenario())
    print(result.table_text)
"""

from __future__ import annotations

import dataclasses
import pathlib
import time
from typing import Any, Callable, Iterable

import numpy as np

from dptbd.config import DPConfig
from dptbd.dsp.association import AssociationConfig
from dptbd.evaluation.run.rtl import RtlCheck, check_rtl
from dptbd.evaluation.run.scenario import Scenario, ScenarioError, TargetSpec, check_snr
from dptbd.model.segmentation import count_for_rate

__all__ = ["RunInput", "RunResult", "effective_scenario", "parse_target_option", "prepare",
           "run_job"]


def _silent(line: str) -> None:
    pass


@dataclasses.dataclass
class RunInput:
    """A run's data and parameters, checked (:func:`prepare`).

    Attributes
    ----------
    scenario : Scenario
        The scenario as given.
    source : str
        One line naming the data (scene or recorded file).
    frames : numpy.ndarray
        ``(T, H, W)`` unsigned ``input_bits``-bit integer frames.
    input_bits : int
    truth, targets : tuple
        Ground truth and targets of a simulated scene (empty for recorded data).
    cfg : DPConfig
        The DP and segmenter parameters (:func:`dptbd.evaluation.chain.segmenter_settings` applied).
    count : int
        n, candidate points per accumulated frame.
    assoc : AssociationConfig
    report_frame : int
        The frame the figures show.
    shift_from : str
        Where the histogram shift s came from (calibrated on the data, or the scenario).
    """

    scenario: Scenario
    source: str
    frames: np.ndarray
    input_bits: int
    truth: tuple
    targets: tuple
    cfg: DPConfig
    count: int
    assoc: AssociationConfig
    report_frame: int
    shift_from: str

    def describe(self) -> list[str]:
        """The lines ``dptbd run`` prints before the stages run."""
        cfg, sc, n_frames = self.cfg, self.scenario, self.frames.shape[0]
        return [
            f"dptbd run: {self.source}",
            f"  FPGA stage: bit-accurate golden model, K = {cfg.segment_frames}, stride "
            f"{cfg.segment_stride}, B_in = {cfg.input_bits}, B_E = {cfg.energy_bits}, "
            f"{cfg.n_segments(n_frames)} accumulated frames, {self.count} candidate points "
            f"each ({100 * sc.false_alarm_rate:g} %)",
            f"  segmentation: {sc.lists} lists — " + (
                f"the gateware segmenter's, threshold from the previous segment's histogram "
                f"(2^{cfg.histogram_bits} bins, shift s = {cfg.bin_shift} {self.shift_from}), "
                f"selected for {cfg.n_candidates} points, at most C = {cfg.record_capacity} "
                f"records, trimmed to {self.count} by the DSP; the first list after reset is "
                f"empty" if sc.lists == "gateware" else
                f"each segment's own histogram (at most {self.count} records)")]


@dataclasses.dataclass
class RunResult:
    """Everything ``dptbd run`` prints and writes (:func:`run_job`).

    Attributes
    ----------
    input : RunInput
        The data and parameters.
    scenario : Scenario
        The effective scenario (association parameters resolved): ``scenario.toml``.
    pipeline : PipelineResult
        Both stages' output.
    evaluation : TrackEvaluation or None
        Tracks scored against the ground truth (None for recorded data).
    rows : list of dict
        The per-target table (001's Table 1 form; empty for recorded data).
    tracks : list of dict
        One row per confirmed track.
    segmentation_bits : dict or None
        Bits per segment handed to the DSP (:func:`.report.segmentation_bits`).
    rtl : dict or None
        The RTL check's record (:func:`.run.rtl.check_rtl`), None without one.
    table_text : str
        The tables as printed and written to ``table.md``.
    started : float
        ``time.perf_counter()`` when the job started.
    """

    input: RunInput
    scenario: Scenario
    pipeline: Any
    evaluation: Any
    rows: list
    tracks: list
    segmentation_bits: dict | None
    rtl: dict | None
    table_text: str
    started: float

    @property
    def frames(self) -> np.ndarray:
        return self.input.frames

    @property
    def cfg(self) -> DPConfig:
        return self.input.cfg


def parse_target_option(text: str) -> TargetSpec:
    """A target given as ``ROW,COL,VROW,VCOL[,SNR]`` (``dptbd run --target``)."""
    parts = text.split(",")
    try:
        values = [float(p) for p in parts]
    except ValueError:
        values = []
    if len(values) not in (4, 5):
        raise ScenarioError(f"--target {text!r}: expected ROW,COL,VROW,VCOL or "
                            f"ROW,COL,VROW,VCOL,SNR (numbers)")
    return TargetSpec((values[0], values[1]), (values[2], values[3]),
                      snr=check_snr(f"--target {text!r}: SNR", values[4]) if len(values) == 5
                      else None)


def effective_scenario(scenario_file: pathlib.Path | None = None, *,
                       input_path: pathlib.Path | None = None, npz_key: str | None = None,
                       seed: int | None = None, snr: float | None = None,
                       targets: list[str] | None = None, segment_frames: int | None = None,
                       segment_stride: int | None = None, lists: str | None = None) -> Scenario:
    """The scenario file (None: the built-in scenario) with ``dptbd run``'s options applied,
    checked; ``None`` leaves a setting as the scenario has it.

    Recorded data (``input_path``) names the run after the data unless the scenario file
    names it; ``seed``, ``snr`` and ``targets`` (``ROW,COL,VROW,VCOL[,SNR]`` strings) apply
    to a simulated scene only; an ``snr`` applies to every target; a ``segment_frames``
    without ``segment_stride`` makes the stride K. Refusals name the option
    (:class:`~dptbd.evaluation.run.scenario.ScenarioError`).
    """
    from dptbd.evaluation.run.scenario import DEFAULT_NAME, default_scenario, load_scenario

    scenario = default_scenario() if scenario_file is None else load_scenario(scenario_file)
    changes: dict = {}
    if input_path is not None:
        changes.update(input_path=input_path, input_key=npz_key)
        # named after the data, unless the scenario file gave a name of its own
        automatic = {DEFAULT_NAME} | ({scenario.input_path.name} if scenario.input_path else set())
        if scenario_file is None or scenario.name in automatic:
            changes["name"] = pathlib.Path(input_path).expanduser().name or str(input_path)
    elif npz_key is not None:
        if scenario.simulated:
            raise ScenarioError("--npz-key needs --input (or [input] in the scenario file)")
        changes["input_key"] = npz_key
    simulated = scenario.simulated and input_path is None
    scene_opts = {"--seed": seed, "--snr": snr, "--target": targets}
    if not simulated:
        given = [k for k, v in scene_opts.items() if v is not None]
        if given:
            raise ScenarioError(f"{', '.join(given)} appl{'ies' if len(given) == 1 else 'y'} to a "
                                f"simulated scene, not to recorded data (--input / [input])")
    if seed is not None:
        if seed < 0:
            raise ScenarioError(f"--seed must be an integer in [0, inf), got {seed}")
        changes["seed"] = seed
    if snr is not None:
        changes["snr"] = check_snr("--snr", snr)
        # an SNR on the command line applies to every target
        changes["targets"] = tuple(dataclasses.replace(t, snr=None) for t in
                                   (scenario.targets if targets is None else ()))
    if targets is not None:
        changes["targets"] = tuple(parse_target_option(t) for t in targets)
    dp = dict(scenario.dp)
    if segment_frames is not None:
        dp["segment_frames"] = segment_frames
        if segment_stride is None:
            dp.pop("segment_stride", None)
    if segment_stride is not None:
        dp["segment_stride"] = segment_stride
    changes["dp"] = dp
    if lists is not None:
        changes["lists"] = lists
    scenario = scenario.replace(**changes)
    scenario.check()
    return scenario


def prepare(scenario: Scenario, *, headroom: float = 2.0) -> RunInput:
    """Load a checked scenario's data and derive the run's parameters.

    Parameters
    ----------
    scenario : Scenario
        Checked (:meth:`Scenario.check`).
    headroom : float
        The gateware segmenter selects ``headroom`` x n points; the DSP trims each list to n
        (:func:`dptbd.evaluation.chain.segmenter_settings`).

    Raises
    ------
    ValueError
        The sequence is shorter than a segment, the false-alarm rate keeps no point, or the
        report frame is outside the sequence (and whatever loading the data raises).
    """
    from dptbd.evaluation.chain import segmenter_settings
    from dptbd.scenes.recorded import load_sequence
    from dptbd.scenes.synthetic import quantise

    if scenario.simulated:
        scene = scenario.make_scene()
        frames = quantise(scene.frames, scenario.adc_bits, gain=scenario.adc_gain,
                          offset=scenario.adc_offset)
        input_bits, truth, targets = scenario.adc_bits, scene.truth, scene.targets
        source = (f"{scenario.name}: simulated {scenario.width}x{scenario.height}, "
                  f"{scenario.frames} frames, SNR {scenario.snr:g}, {len(targets)} target(s), "
                  f"seed {scenario.seed}; {input_bits}-bit ADC at gain {scenario.adc_gain:g}")
    else:
        seq = load_sequence(scenario.input_path, key=scenario.input_key)
        frames, input_bits, truth, targets = seq.frames, seq.input_bits, (), ()
        source = f"{scenario.name}: recorded data {seq.source}, {input_bits}-bit"
    n_frames, height, width = frames.shape
    cfg = scenario.dp_config(height=height, width=width, input_bits=input_bits)
    if n_frames < cfg.segment_frames:
        raise ValueError(f"the sequence has {n_frames} frame(s), shorter than one segment "
                         f"(segment_frames K = {cfg.segment_frames}): nothing to accumulate")
    count = count_for_rate(scenario.false_alarm_rate, height * width)
    if count < 1:
        raise ValueError(f"false_alarm_rate {scenario.false_alarm_rate} of {height * width} "
                         f"pixels keeps no candidate point; raise it")
    assoc = scenario.assoc_config()
    report_frame = n_frames // 2 if scenario.report_frame is None else scenario.report_frame
    if not 0 <= report_frame < n_frames:
        raise ValueError(f"[report] frame {report_frame} is outside the sequence (0 … "
                         f"{n_frames - 1})")
    calibrated = cfg.histogram_shift is None
    cfg = segmenter_settings(cfg, frames, count, assoc, headroom)
    shift_from = (f"calibrated on the largest pixel of the first K = {cfg.segment_frames} "
                  f"frames" if calibrated else "from the scenario")
    return RunInput(scenario, source, frames, input_bits, tuple(truth), tuple(targets), cfg,
                    count, assoc, report_frame, shift_from)


def run_job(scenario: Scenario, *, rtl: RtlCheck | None = None, dsp: str = "python",
            progress: Callable[..., Iterable] | None = None,
            log: Callable[[str], None] = _silent) -> RunResult:
    """Run a checked scenario through both stages and build its tables.

    Parameters
    ----------
    scenario : Scenario
        Checked (:meth:`Scenario.check`).
    rtl : RtlCheck, optional
        Also simulate the generated Verilog (the whole FPGA stage with gateware lists, the DP
        pipeline with ideal lists) and stop unless it is bit-exact
        (:class:`~dptbd.evaluation.run.rtl.RtlError`).
    dsp : {"python", "c"}
        The DSP stage's association: the Python reference model or the C firmware
        (``docs/dsp_firmware.md``); the tracks and tables are the same bit for bit.
    progress : callable, optional
        ``tqdm``-like wrapper for the per-segment loops.
    log : callable
        Receives every line the job reports while it runs (default: none).
    """
    from dptbd.evaluation.chain import run_pipeline
    from dptbd.dsp.track_metrics import evaluate_tracks
    from dptbd.evaluation.run import report

    started = time.perf_counter()
    inp = prepare(scenario)
    for line in inp.describe():
        log(line)
    cfg = inp.cfg
    record = None
    if rtl is not None:
        record = check_rtl(inp.frames, cfg, rtl,
                           "segmenter" if scenario.lists == "gateware" else "dp", log=log)

    result = run_pipeline(inp.frames, cfg, inp.count, inp.assoc, lists=scenario.lists,
                          dsp=dsp, progress=progress)
    evaluation = None
    if inp.truth:
        evaluation = evaluate_tracks(result.tracks, result.positions, inp.truth, cfg,
                                     len(result.segments.end_frames))
    seg_bits = report.segmentation_bits(result)
    if seg_bits is not None:
        log(report.format_segmentation_bits(seg_bits))
    stats = result.stats
    firmware = " (C firmware)" if dsp == "c" else ""
    log(f"  DSP stage{firmware}: {inp.assoc.capacity} track records, at most {stats['peak_active']} in "
        f"use; {stats['started']} tracks started, {len(result.tracks)} confirmed"
        + ("" if evaluation is None else f" ({evaluation.false_tracks} false)")
        + (f"; {stats['dropped_candidates']} candidates dropped (records full)"
           if stats["dropped_candidates"] else ""))

    tracks = report.track_rows(result, evaluation)
    rows = (report.table_rows(result, inp.truth, inp.targets, evaluation)
            if inp.truth else [])
    resolved = {k: v for k, v in dataclasses.asdict(inp.assoc).items() if v is not None}
    return RunResult(input=inp, scenario=scenario.replace(association=resolved),
                     pipeline=result, evaluation=evaluation, rows=rows, tracks=tracks,
                     segmentation_bits=seg_bits, rtl=record,
                     table_text=report.format_run_tables(scenario.snr, rows, tracks, record),
                     started=started)
