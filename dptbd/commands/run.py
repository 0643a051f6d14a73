"""``dptbd run``: the main job — FPGA stage, DSP stage, table and figures in an output folder.

With no arguments it runs the built-in scenario, paper 001's second experiment (001 §4:
128 x 128, 100 frames, SNR 2.0, two targets starting at (30, 100) with V = (0.8, -0.4) and
at (54, 40) with V = (0.4, 0.6), 0.2 % false-alarm threshold):

1. **FPGA stage** — the bit-accurate golden model of the direction-weighted DP (eqs (8)–(11),
   K = 6, segments back to back as the gateware runs them, a 12-bit ADC at 16 LSB per
   grey level as in ``dptbd.evaluation.table1``) and the constant-false-alarm-count histogram
   threshold (33 candidate points per accumulated frame). ``--rtl`` also runs the
   generated Verilog of the whole FPGA stage (``dptbd_seg``: DP pipeline + segmenter) on
   every frame (``--rtl-frames N``: the first N only) and stops unless every output word is
   bit for bit identical to the model. The simulator is Verilator by default
   (:mod:`dptbd.sim.verilator`, a cached compiled build: a few seconds for the built-in
   scene once built); ``--rtl-simulator icarus`` keeps the cocotb + Icarus bench (about
   12 min for it). The printed summary and ``summary.json`` (``rtl``) say which simulator,
   which frames, the words compared, the cycles and the simulator's speed.
2. **DSP stage** — the fixed-capacity track association of 001 §3
   (:mod:`dptbd.dsp.association`), candidates' paths recovered by backtracking the
   direction maps (:mod:`dptbd.dsp.backtrack`).

It writes, into a new output folder (default ``dptbd-run``): ``table.md``/``table.csv``
(001's Table 1 form), ``tracks.csv`` (a position per frame of every confirmed track),
``candidates.csv``, ``summary.json`` (everything, machine-readable, including the bits per
segment the FPGA hands the DSP against the whole image, also printed;
``docs/arithmetic.md`` §6.6), ``scenario.toml``
(the effective scenario: rerun with ``--scenario``) and three figures: ``raw_frame.png``,
``accumulated.png``, ``tracks.png``. Everything is written into a hidden temporary folder
beside the output folder and renamed at the end, so an error leaves nothing behind.

Recorded data (``--input`` or ``[input]`` in a scenario file: ``.npy``, ``.npz``, or a
folder of 8/16-bit PNG/TIFF frames) has no ground truth: the table lists the tracks. The run
is named after the input file or folder unless the scenario file names it.
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import functools
import json
import os
import pathlib
import shutil
import sys
import tempfile
import time

from dptbd import __version__
from dptbd.evaluation.run_rtl import _WORDS, RtlError, rtl_summary, rtl_tools_missing, run_rtl
from dptbd.model.segmentation import count_for_rate

_MARKER = "dptbd run"
_FILES = ("table.md", "table.csv", "tracks.csv", "candidates.csv", "summary.json",
          "scenario.toml", "raw_frame.png", "accumulated.png", "tracks.png")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    src = parser.add_argument_group("what to run")
    src.add_argument("--scenario", type=pathlib.Path, metavar="FILE.toml",
                     help="scenario file (TOML; see dptbd/evaluation/scenario.py); default: paper 001's "
                          "second experiment")
    src.add_argument("--input", type=pathlib.Path, metavar="PATH",
                     help="recorded data instead of a simulated scene: .npy or .npz (T, H, W) "
                          "integers, or a folder of 8/16-bit PNG or TIFF frames")
    src.add_argument("--npz-key", metavar="KEY", help="the array to use in an .npz input")
    src.add_argument("--seed", type=int, default=None, help="scene seed (default 0)")
    src.add_argument("--snr", type=float, default=None,
                     help="SNR of every target as paper 001 defines it (default 2.0)")
    src.add_argument("--target", action="append", default=None, metavar="ROW,COL,VROW,VCOL[,SNR]",
                     help="a target (start row, col; velocity rows, cols per frame); repeat "
                          "for several; replaces the scenario's targets")
    dp = parser.add_argument_group("FPGA stage")
    dp.add_argument("--segment-frames", type=int, default=None, metavar="K",
                    help="frames per segment (default 6)")
    dp.add_argument("--segment-stride", type=int, default=None, metavar="S",
                    help="frames between segment starts (default K: what the gateware does)")
    dp.add_argument("--lists", choices=("gateware", "ideal"), default=None,
                    help="candidate lists handed to the DSP: gateware (default: what the "
                         "segmenter emits, threshold from the previous segment's histogram) or "
                         "ideal (each segment's own histogram, what a two-pass segmenter gives; "
                         "docs/arithmetic.md §6.1)")
    dp.add_argument("--rtl", action="store_true",
                    help="also simulate the generated Verilog on every frame (--rtl-frames) "
                         "and check it bit for bit against the model: the whole FPGA stage "
                         "(dptbd_seg: DP + segmenter, every candidate-list word) with gateware "
                         "lists, the DP pipeline (dptbd_dp, every (E, d) word) with --lists "
                         "ideal")
    dp.add_argument("--rtl-simulator", choices=("verilator", "icarus"), default="verilator",
                    help="simulator of --rtl: verilator (default: compiled and cached, a few "
                         "seconds for 100 frames of 128 x 128 once built) or icarus (cocotb + "
                         "Icarus, about 12 min for the same)")
    dp.add_argument("--rtl-frames", type=int, default=0, metavar="N",
                    help="frames to simulate with --rtl (default 0: all; N: the first N, the "
                         "rest come from the model only, as the summary says)")
    dp.add_argument("--rtl-build-dir", type=pathlib.Path, default=None, metavar="DIR",
                    help="build cache of --rtl (default: Verilator's shared cache, "
                         "$DPTBD_BUILD_DIR/verilator or ~/.cache/dptbd/verilator; Icarus "
                         "build/sim)")
    out = parser.add_argument_group("output")
    out.add_argument("--out", type=pathlib.Path, default=pathlib.Path("dptbd-run"), metavar="DIR",
                     help="output folder, must not exist (default dptbd-run)")
    out.add_argument("--force", action="store_true",
                     help="replace an existing output folder of an earlier dptbd run")
    out.add_argument("--no-progress", action="store_true", help="no progress bars")


# ---- the scenario from file and options ------------------------------------------------

def _parse_target(text: str):
    from dptbd.evaluation.scenario import ScenarioError, TargetSpec, check_snr

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


def build_scenario(args: argparse.Namespace):
    """The effective scenario: file (or built-in) plus command-line options, checked."""
    from dptbd.evaluation.scenario import (DEFAULT_NAME, ScenarioError, check_snr, default_scenario,
                                load_scenario)

    scenario = default_scenario() if args.scenario is None else load_scenario(args.scenario)
    changes: dict = {}
    if args.input is not None:
        changes.update(input_path=args.input, input_key=args.npz_key)
        # named after the data, unless the scenario file gave a name of its own
        automatic = {DEFAULT_NAME} | ({scenario.input_path.name} if scenario.input_path else set())
        if args.scenario is None or scenario.name in automatic:
            changes["name"] = pathlib.Path(args.input).expanduser().name or str(args.input)
    elif args.npz_key is not None:
        if scenario.simulated:
            raise ScenarioError("--npz-key needs --input (or [input] in the scenario file)")
        changes["input_key"] = args.npz_key
    simulated = scenario.simulated and args.input is None
    scene_opts = {"--seed": args.seed, "--snr": args.snr, "--target": args.target}
    if not simulated:
        given = [k for k, v in scene_opts.items() if v is not None]
        if given:
            raise ScenarioError(f"{', '.join(given)} appl{'ies' if len(given) == 1 else 'y'} to a "
                                f"simulated scene, not to recorded data (--input / [input])")
    if args.seed is not None:
        if args.seed < 0:
            raise ScenarioError(f"--seed must be >= 0, got {args.seed}")
        changes["seed"] = args.seed
    if args.snr is not None:
        changes["snr"] = check_snr("--snr", args.snr)
        # an SNR on the command line applies to every target
        changes["targets"] = tuple(dataclasses.replace(t, snr=None) for t in
                                   (scenario.targets if args.target is None else ()))
    if args.target is not None:
        changes["targets"] = tuple(_parse_target(t) for t in args.target)
    dp = dict(scenario.dp)
    if args.segment_frames is not None:
        dp["segment_frames"] = args.segment_frames
        if args.segment_stride is None:
            dp.pop("segment_stride", None)
    if args.segment_stride is not None:
        dp["segment_stride"] = args.segment_stride
    changes["dp"] = dp
    if args.lists is not None:
        changes["lists"] = args.lists
    scenario = scenario.replace(**changes)
    scenario.check()
    return scenario


# ---- the output folder --------------------------------------------------------------------

def _check_out(out: pathlib.Path, force: bool) -> pathlib.Path:
    out = out.expanduser()
    resolved = out.resolve()
    if not resolved.parent.is_dir():
        raise FileNotFoundError(f"the parent folder of --out {out} does not exist")
    if resolved == pathlib.Path.cwd().resolve() or resolved in pathlib.Path.cwd().resolve().parents:
        raise ValueError(f"--out {out} is the current folder or one of its parents; give a new "
                         f"folder")
    if out.exists() or out.is_symlink():
        if not force:
            raise FileExistsError(f"output folder {out} exists; pass --force to replace it, or "
                                  f"choose another with --out DIR")
        if not out.is_dir() or out.is_symlink():
            raise FileExistsError(f"{out} exists and is not a folder; --force replaces only the "
                                  f"output folder of an earlier dptbd run")
        if any(out.iterdir()) and not _is_run_folder(out):
            raise FileExistsError(f"{out} is not the output folder of an earlier dptbd run (no "
                                  f"summary.json from dptbd run); --force will not delete it")
    return out


def _is_run_folder(path: pathlib.Path) -> bool:
    try:
        return json.loads((path / "summary.json").read_text()).get("tool") == _MARKER
    except (OSError, ValueError, AttributeError):
        return False


@contextlib.contextmanager
def staging(out: pathlib.Path, force: bool):
    """A temporary folder beside ``out``, renamed to ``out`` when the block succeeds.

    On any error the temporary folder is removed and ``out`` is left as it was.
    """
    out = _check_out(out, force)
    tmp = pathlib.Path(tempfile.mkdtemp(prefix=f".{out.name}.partial-", dir=out.resolve().parent))
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o777 & ~umask)             # mkdtemp makes it private (0700)
    try:
        yield tmp
        _check_out(out, force)  # the folder may have appeared meanwhile
        if out.exists():
            old = out.resolve().parent / f".{out.name}.old-{os.getpid()}"
            os.rename(out, old)
            os.rename(tmp, out)
            shutil.rmtree(old, ignore_errors=True)
        else:
            os.rename(tmp, out)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise


# ---- the job --------------------------------------------------------------------------------

def _progress(disabled: bool):
    if disabled:
        return None
    try:
        from tqdm import tqdm
    except ImportError:  # pragma: no cover
        return None
    return functools.partial(tqdm, disable=None, unit="segment", file=sys.stderr)


def _config_dict(cfg) -> dict:
    out = dataclasses.asdict(cfg)
    out["weights"] = [list(r) for r in cfg.weights]
    return out


def main(args: argparse.Namespace) -> int:
    """Run the job; an unreadable file or an unwritable folder is a clear error (exit 2).

    Every other refusal (bad scenario, data or option) raises an exception that the
    command line turns into ``dptbd run: error: …`` and exit status 2; in every case
    nothing is left in (or beside) the output folder (:func:`staging`).
    """
    try:
        return _main(args)
    except (FileNotFoundError, FileExistsError):
        raise                                 # the command line reports these itself
    except OSError as exc:                    # permissions, disk full, …: no traceback
        what = f" {exc.filename}" if getattr(exc, "filename", None) else ""
        print(f"dptbd run: error: cannot read or write{what}: {exc.strerror or exc}",
              file=sys.stderr)
        return 2


def _main(args: argparse.Namespace) -> int:
    from dptbd.dsp.chain import run_pipeline, segmenter_settings
    from dptbd.scenes.synthetic import quantise
    from dptbd.scenes.recorded import load_sequence
    from dptbd.dsp.track_metrics import evaluate_tracks
    from dptbd.evaluation import run_figures, run_report as report

    start = time.perf_counter()
    scenario = build_scenario(args)
    _check_out(args.out, args.force)          # refuse early, before any work
    if args.rtl_frames is not None and args.rtl_frames < 0:
        raise ValueError(f"--rtl-frames must be >= 0, got {args.rtl_frames}")
    if args.rtl:                              # a missing simulator: refused before any work
        why = rtl_tools_missing(args.rtl_simulator)
        if why is not None:
            print(f"dptbd run: error: {why}", file=sys.stderr)
            return 2

    # ---- the data ----
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
    print(f"dptbd run: {source}")
    print(f"  FPGA stage: bit-accurate golden model, K = {cfg.segment_frames}, stride "
          f"{cfg.segment_stride}, B_in = {cfg.input_bits}, B_E = {cfg.energy_bits}, "
          f"{cfg.n_segments(n_frames)} accumulated frames, {count} candidate points each "
          f"({100 * scenario.false_alarm_rate:g} %)", flush=True)

    calibrated = cfg.histogram_shift is None
    cfg = segmenter_settings(cfg, frames, count, assoc)
    shift_from = (f"calibrated on the largest pixel of the first K = {cfg.segment_frames} "
                  f"frames" if calibrated else "from the scenario")
    print(f"  segmentation: {scenario.lists} lists — " + (
        f"the gateware segmenter's, threshold from the previous segment's histogram "
        f"(2^{cfg.histogram_bits} bins, shift s = {cfg.bin_shift} {shift_from}), selected for "
        f"{cfg.n_candidates} points, at most C = {cfg.record_capacity} records, trimmed to "
        f"{count} by the DSP; the first list after reset is empty"
        if scenario.lists == "gateware" else
        f"each segment's own histogram (at most {count} records)"), flush=True)

    # ---- the RTL, if asked ----
    rtl = None
    if args.rtl:
        try:
            rtl = run_rtl(frames, cfg, args.rtl_frames, args.rtl_build_dir,
                          "segmenter" if scenario.lists == "gateware" else "dp",
                          simulator=args.rtl_simulator)
        except RtlError as exc:
            print(f"dptbd run: error: {exc}", file=sys.stderr)
            return 1
        rtl["checked"] = True
        rtl["checked_frames"] = [0, rtl["frames"] - 1]
        rtl["summary"] = rtl_summary(rtl["frames"], n_frames, rtl["module"],
                                     rtl.get("simulator"), rtl.get("words_compared"),
                                     rtl.get("cycles"), rtl.get("design", "segmenter"))
        which = (f"the first {rtl['frames']} of {n_frames} frames" if rtl["frames"] < n_frames
                 else f"all {n_frames} frames")
        cps = rtl.get("cycles_per_second")
        speed = ("" if not cps else f", {cps / 1e6:.2f} M cycles/s" if cps >= 1e6
                 else f", {cps:.0f} cycles/s")
        print(f"  RTL: {rtl['report']} — the generated Verilog ({rtl['module']} on "
              f"{str(rtl.get('simulator', '?')).capitalize()}) matches the golden model on "
              f"{which}: {rtl.get('words_compared')} "
              f"{_WORDS.get(rtl.get('design'), 'words')} compared, {rtl.get('cycles')} "
              f"cycles{speed} ({rtl['seconds']:.1f} s in all)"
              + ("; the model's output is used for the rest" if rtl["frames"] < n_frames
                 else ""), flush=True)

    # ---- the two stages ----
    result = run_pipeline(frames, cfg, count, assoc, lists=scenario.lists,
                          progress=_progress(args.no_progress))
    evaluation = None
    if truth:
        evaluation = evaluate_tracks(result.tracks, result.positions, truth, cfg,
                                     len(result.segments.end_frames))
    stats = result.stats
    seg_bits = report.segmentation_bits(result)
    if seg_bits is not None:
        print(report.format_segmentation_bits(seg_bits))
    print(f"  DSP stage: {assoc.capacity} track records, at most {stats['peak_active']} in use; "
          f"{stats['started']} tracks started, {len(result.tracks)} confirmed"
          + ("" if evaluation is None else f" ({evaluation.false_tracks} false)")
          + (f"; {stats['dropped_candidates']} candidates dropped (records full)"
             if stats["dropped_candidates"] else ""))

    # ---- tables ----
    tracks = report.track_rows(result, evaluation)
    rows = report.table_rows(result, truth, targets, evaluation) if truth else []
    text = []
    if rows:
        text.append(report.format_table(rows))
        paper = report.paper_lines(scenario.snr, rows)
        if paper:
            text += ["", paper]
    text += ["", f"confirmed tracks ({len(tracks)}):", report.format_tracks(tracks)
             if tracks else "(none)"]
    if rtl is not None:
        text += ["", rtl["summary"]]
    table_text = "\n".join(text).strip("\n")

    # ---- the output folder ----
    seg = report.segment_for_frame(report_frame, result.segments.end_frames)
    seg_first = seg * cfg.segment_stride
    seg_last = int(result.segments.end_frames[seg])
    truth_at = (lambda t: [None if not tt.visible[t] else (int(tt.pixel[t, 0]), int(tt.pixel[t, 1]))
                           for tt in truth]) if truth else (lambda t: None)
    resolved_assoc = {k: v for k, v in dataclasses.asdict(assoc).items() if v is not None}
    effective = scenario.replace(association=resolved_assoc)
    with staging(args.out, args.force) as tmp:
        (tmp / "table.md").write_text(table_text + "\n")
        report.write_csv(tmp / "table.csv", rows if rows else tracks)
        report.write_csv(tmp / "tracks.csv", list(report.iter_track_positions(result, evaluation)))
        cand_rows = [{"segment": s, "end_frame": int(result.segments.end_frames[s]),
                      "row": int(c["row"]), "col": int(c["col"]), "energy": int(c["energy"]),
                      "direction": int(c["direction"]), "path_start_row": int(c["row0"]),
                      "path_start_col": int(c["col0"])}
                     for s, cs in enumerate(result.candidates) for c in cs]
        report.write_csv(tmp / "candidates.csv", cand_rows)
        (tmp / "scenario.toml").write_text(effective.to_toml())
        run_figures.figure_raw_frame(tmp / "raw_frame.png", frames[report_frame], report_frame,
                                input_bits=input_bits, truth_pixels=truth_at(report_frame))
        run_figures.figure_accumulated(tmp / "accumulated.png", result.segments.energy[seg],
                                  result.candidates[seg], seg, seg_first, seg_last,
                                  truth_pixels=truth_at(seg_last))
        title = (f"{len(result.tracks)} confirmed track(s)"
                 + ("" if evaluation is None else f", {evaluation.false_tracks} false")
                 + f" — {n_frames} frames, {len(result.segments.end_frames)} segments")
        run_figures.figure_tracks(tmp / "tracks.png", result, truth=truth, evaluation=evaluation,
                             title=title)
        report.write_json(tmp / "summary.json", {
            "tool": _MARKER, "version": __version__,
            "source": source,
            "scenario": effective.to_dict(),
            "dp_config": _config_dict(cfg),
            "association_config": dataclasses.asdict(assoc),
            "frames": n_frames, "height": height, "width": width, "input_bits": input_bits,
            "accumulated_frames": len(result.segments.end_frames),
            "segment_end_frames": result.segments.end_frames,
            "candidates_per_frame": count,
            "lists": scenario.lists,
            "segmenter": {"histogram_bits": cfg.histogram_bits, "histogram_shift": cfg.bin_shift,
                          "histogram_shift_from": shift_from,
                          "candidate_count": cfg.n_candidates,
                          "candidate_capacity": cfg.record_capacity},
            "table": rows,
            "tracks": tracks,
            "false_tracks": None if evaluation is None else evaluation.false_tracks,
            "dsp_stats": stats,
            "bits_per_segment": seg_bits,
            "rtl": rtl if rtl is not None else {
                "checked": False, "summary": "RTL not simulated (golden model only; --rtl "
                                             "checks the generated Verilog)"},
            "report_frame": report_frame, "report_segment": seg,
            "seconds": round(time.perf_counter() - start, 2),
        })
    print()
    print(table_text)
    print()
    print(f"wrote {args.out}/ ({', '.join(_FILES)}) in {time.perf_counter() - start:.1f} s")
    return 0
