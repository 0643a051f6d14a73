"""The report of ``dptbd run``: 001's Table 1 form, track lists, and the output folder
(:func:`write_run_folder`: tables, CSV, ``summary.json``, ``scenario.toml`` and the figures of
:mod:`dptbd.evaluation.run.figures`) of a :class:`~dptbd.evaluation.run.job.RunResult`.
"""

from __future__ import annotations

import csv
import dataclasses
import math
import pathlib
import time
from typing import Any, Iterable

import numpy as np

from dptbd.evaluation.metrics import first_level_counts
from dptbd.evaluation.table1.experiment import PAPER_TABLE1
from dptbd.output_folder import json_text

__all__ = ["TOOL", "RUN_FILES", "TABLE_COLUMNS", "table_rows", "format_table", "paper_lines",
           "track_rows", "format_tracks", "format_run_tables", "write_csv", "write_json",
           "segment_for_frame", "segmentation_bits", "format_segmentation_bits", "run_summary",
           "write_run_folder"]

#: ``summary.json``'s ``tool`` field: marks a folder that ``--force`` may replace
TOOL = "dptbd run"
#: The files of a run's folder, in the order ``dptbd run`` names them
RUN_FILES = ("table.md", "table.csv", "tracks.csv", "candidates.csv", "summary.json",
             "scenario.toml", "raw_frame.png", "accumulated.png", "tracks.png")

#: Columns of the run table, in the form of 001's Table 1 (per target).
TABLE_COLUMNS = (
    ("target", "target"),
    ("start", "start"),
    ("velocity", "V"),
    ("accumulated_frames", "accumulated frames"),
    ("detections", "first-level detections"),
    ("pd", "Pd"),
    ("mean_false_points", "mean false points"),
    ("frames_until_output", "frames until output"),
    ("track_length_after_output", "detected track length (after output)"),
    ("track_length", "track length (whole)"),
    ("segments_until_confirmation", "segments until confirmation"),
    ("rms_error", "RMS position error (px)"),
    ("track_ids", "confirmed track ids"),
)


def _fmt(v: Any) -> str:
    if v is None:
        return "—"
    if isinstance(v, float):
        return "—" if math.isnan(v) else f"{v:.2f}"
    if isinstance(v, (list, tuple)) and v and isinstance(v[0], float):
        return "(" + ", ".join(f"{x:g}" for x in v) + ")"
    if isinstance(v, (list, tuple)):
        return ", ".join(str(x) for x in v) if v else "none"
    return str(v)


def received_masks(result) -> np.ndarray:
    """``(S, H, W)`` bool: the candidate points the DSP received per accumulated frame.

    First-level detections and false points are counted on these lists, i.e. on what the
    FPGA stage handed over (the gateware segmenter's lists by default, the ideal rule's with
    ``lists = "ideal"``).
    """
    masks = np.zeros(result.segments.energy.shape, dtype=bool)
    for s, c in enumerate(result.candidates):
        masks[s, c["row"], c["col"]] = True
    return masks


def table_rows(result, truth, targets, evaluation) -> list[dict]:
    """One row per target: first-level (001 §4) and track (DSP) columns.

    Parameters
    ----------
    result : PipelineResult
    truth : sequence of TargetTruth
    targets : sequence of Target
    evaluation : TrackEvaluation
    """
    ends = result.segments.end_frames
    masks = received_masks(result)
    if truth:
        every = np.stack([t.pixel[ends] for t in truth], axis=1)
        vis = np.stack([t.visible[ends] for t in truth], axis=1)
        false = first_level_counts(masks, every, vis).mean_false_points
    else:
        false = first_level_counts(masks, np.zeros((len(ends), 0, 2), int),
                                   np.zeros((len(ends), 0), bool)).mean_false_points
    rows = []
    for i, (target, tt, ev) in enumerate(zip(targets, truth, evaluation.targets)):
        c = first_level_counts(masks, tt.pixel[ends][:, None], tt.visible[ends][:, None])
        rows.append({
            "target": i + 1,
            "start": [float(target.start[0]), float(target.start[1])],
            "velocity": [float(target.velocity[0]), float(target.velocity[1])],
            "accumulated_frames": c.frames,
            "detections": c.detections,
            "pd": round(c.pd, 4) if not math.isnan(c.pd) else None,
            "mean_false_points": round(false, 2),
            "frames_until_output": ev.frames_until_output,
            "track_length_after_output": ev.track_frames_after_output if ev.track_ids else None,
            "track_length": ev.track_frames if ev.track_ids else None,
            "segments_until_confirmation": ev.segments_until_confirmation,
            "rms_error": None if math.isnan(ev.rms_error) else round(ev.rms_error, 3),
            "track_ids": list(ev.track_ids),
        })
    return rows


def format_table(rows: list[dict]) -> str:
    """Markdown table; the first seven columns are 001 Table 1's first-level ones."""
    head = [label for _, label in TABLE_COLUMNS]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for row in rows:
        cells = []
        for key, _ in TABLE_COLUMNS:
            v = row[key]
            if key in ("start", "velocity"):
                cells.append(f"({v[0]:g}, {v[1]:g})")
            elif key == "pd":
                cells.append("—" if v is None else f"{v:.2f}")
            elif key == "mean_false_points":
                cells.append(f"{v:.1f}")
            else:
                cells.append(_fmt(v))
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def paper_lines(snr: float, rows: list[dict]) -> str:
    """001's Table 1 rows for the same SNR and velocities, when there are any."""
    out = []
    for row in rows:
        key = (round(snr, 3), (row["velocity"][0], row["velocity"][1]))
        paper = PAPER_TABLE1.get(key)
        if paper is not None:
            det, pd, false, frames, length = paper
            out.append(f"| {row['target']} | V = ({key[1][0]:g}, {key[1][1]:g}) | 24 | {det} | "
                       f"{pd:.2f} | {false:.1f} | {frames} | {length} |")
    if not out:
        return ""
    head = ("| target | paper 001 Table 1, SNR " + f"{snr:g}" + " (one target per run) | "
            "accumulated frames | first-level detections | Pd | mean false points | "
            "frames until output | detected track length |")
    return "\n".join([head, "|" + "---|" * 8] + out)


def track_rows(result, evaluation=None) -> list[dict]:
    """One row per confirmed track."""
    cfg = result.cfg
    rows = []
    for tr in result.tracks:
        frames, pos, measured = result.positions[tr.id]
        owner = None if evaluation is None else evaluation.track_target.get(tr.id, -1)
        first_pt, last_pt = tr.points[0], tr.points[-1]
        span = max(int(last_pt["seg"]) - int(first_pt["seg"]), 1) * cfg.segment_stride
        rows.append({
            "track": tr.id,
            "target": None if owner is None else (owner + 1 if owner >= 0 else "false"),
            "first_frame": int(frames[0]),
            "confirm_frame": tr.confirm_segment * cfg.segment_stride + cfg.segment_frames - 1,
            "last_frame": int(frames[-1]),
            "hits": tr.hits,
            "segments": tr.length,
            "frames": int(len(frames)),
            "start": [int(first_pt["row"]), int(first_pt["col"])],
            "end": [int(last_pt["row"]), int(last_pt["col"])],
            "velocity": [round((int(last_pt["row"]) - int(first_pt["row"])) / span, 3),
                         round((int(last_pt["col"]) - int(first_pt["col"])) / span, 3)],
            "alive_at_end": tr.alive,
        })
    return rows


def format_tracks(rows: list[dict]) -> str:
    head = ["track", "target", "first frame", "output frame", "last frame", "detected segments",
            "segments", "frames", "start (row, col)", "end (row, col)", "V (px/frame)", "alive"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in rows:
        lines.append("| " + " | ".join([
            str(r["track"]), "—" if r["target"] is None else str(r["target"]),
            str(r["first_frame"]), str(r["confirm_frame"]), str(r["last_frame"]), str(r["hits"]),
            str(r["segments"]), str(r["frames"]), f"({r['start'][0]}, {r['start'][1]})",
            f"({r['end'][0]}, {r['end'][1]})",
            f"({r['velocity'][0]:g}, {r['velocity'][1]:g})", "yes" if r["alive_at_end"] else "no",
        ]) + " |")
    return "\n".join(lines)


def format_run_tables(snr: float, rows: list[dict], tracks: list[dict],
                      rtl: dict | None = None) -> str:
    """``table.md``: the per-target table and 001's rows beside it (simulated scenes), the
    confirmed tracks, and the RTL check's summary line."""
    text = []
    if rows:
        text.append(format_table(rows))
        paper = paper_lines(snr, rows)
        if paper:
            text += ["", paper]
    text += ["", f"confirmed tracks ({len(tracks)}):", format_tracks(tracks)
             if tracks else "(none)"]
    if rtl is not None:
        text += ["", rtl["summary"]]
    return "\n".join(text).strip("\n")


def write_csv(path: pathlib.Path, rows: list[dict]) -> None:
    """Rows of dicts as CSV; lists become ``a;b`` cells."""
    if not rows:
        path.write_text("")
        return
    with open(path, "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        for row in rows:
            writer.writerow({k: (";".join(str(x) for x in v) if isinstance(v, (list, tuple))
                                 else ("" if v is None else v)) for k, v in row.items()})


def write_json(path: pathlib.Path, obj: Any) -> None:
    """``obj`` as strict JSON (:func:`dptbd.output_folder.json_text`: non-finite as null)."""
    path.write_text(json_text(obj, indent=2) + "\n")


def segment_for_frame(frame: int, end_frames: np.ndarray) -> int:
    """The segment whose last frame is the first at or after ``frame`` (else the last)."""
    later = np.flatnonzero(np.asarray(end_frames) >= frame)
    return int(later[0]) if later.size else len(end_frames) - 1


def iter_track_positions(result, evaluation=None) -> Iterable[dict]:
    """Per-frame track positions, for ``tracks.csv``."""
    for tr in result.tracks:
        frames, pos, measured = result.positions[tr.id]
        owner = None if evaluation is None else evaluation.track_target.get(tr.id, -1)
        for f, (r, c), m in zip(frames, pos, measured):
            yield {"track": tr.id,
                   "target": "" if owner is None else (owner + 1 if owner >= 0 else "false"),
                   "frame": int(f), "row": round(float(r), 3), "col": round(float(c), 3),
                   "measured": int(bool(m))}


def segmentation_bits(result) -> dict | None:
    """Bits per segment the FPGA hands the DSP, measured on this run (``docs/arithmetic.md``
    §6.6), against the whole accumulated image.

    Two lists are measured on the run's accumulated images: the ones the DSP stage used
    (``result.candidates``: the gateware's by default, or the §6 rule on the segment's own
    histogram with ``lists = "ideal"``) and the gateware segmenter's (threshold from the previous segment's histogram, §6.1,
    :func:`dptbd.model.segmentation.segment_sequence`, bit for bit what ``dptbd_seg``
    emits). Each list costs (records + 1 trailer) payload words of
    :func:`dptbd.hw.candidate_layout.bits_per_segment`. ``None`` when the gateware layouts
    cannot be imported (Amaranth missing).
    """
    import dataclasses

    from dptbd.model.segmentation import segment_sequence

    try:
        from dptbd.hw.candidate_layout import bits_per_segment
    except ImportError:  # pragma: no cover - depends on the installation
        return None
    cfg = result.cfg
    if cfg.candidate_count is None:
        cfg = dataclasses.replace(cfg, candidate_count=result.count)
    bits = bits_per_segment(cfg)
    used = np.array([len(c) for c in result.candidates], dtype=float)
    lists = segment_sequence(result.segments.energy, result.segments.direction, cfg)
    gate = np.array([lst.count for lst in lists], dtype=float)

    def per(counts: np.ndarray) -> dict:
        mean_bits = float((counts.mean() + 1) * bits.word) if counts.size else float(bits.word)
        return {"records_mean": round(float(counts.mean()), 2) if counts.size else 0.0,
                "records_max": int(counts.max()) if counts.size else 0,
                "bits_mean": round(mean_bits, 1),
                "reduction": round(bits.image / mean_bits, 1)}

    return {"image_bits": bits.image, "word_bits": bits.word, "record_bits": bits.record,
            "trailer_bits": bits.trailer, "n": cfg.n_candidates, "capacity": cfg.record_capacity,
            "nominal_bits": bits.nominal, "nominal_reduction": round(bits.image / bits.nominal, 1),
            "worst_bits": bits.worst, "worst_reduction": round(bits.image / bits.worst, 1),
            "lists": getattr(result, "lists", "gateware"), "dsp_count": result.count,
            "dsp_lists": per(used), "gateware_lists": per(gate),
            "gateware_overflows": int(sum(lst.overflow for lst in lists))}


def format_segmentation_bits(sb: dict) -> str:
    """One printed line for :func:`segmentation_bits`."""
    d, g = sb["dsp_lists"], sb["gateware_lists"]
    if sb.get("lists") == "gateware":
        return (f"  FPGA -> DSP: {sb['image_bits']} bits per segment for the whole accumulated "
                f"image; the gateware segmenter's lists (selected for n = {sb['n']}) took "
                f"{g['bits_mean']:.0f} bits ({g['records_mean']:.1f} records + trailer, "
                f"{sb['word_bits']}-bit words): {g['reduction']:.0f}x fewer; the DSP keeps "
                f"{d['records_mean']:.1f} records per list after trimming to "
                f"{sb['dsp_count']}")
    return (f"  FPGA -> DSP: {sb['image_bits']} bits per segment for the whole accumulated image; "
            f"the candidate lists took {d['bits_mean']:.0f} bits ({d['records_mean']:.1f} "
            f"records + trailer, {sb['word_bits']}-bit words): {d['reduction']:.0f}x fewer; "
            f"the gateware segmenter's (previous segment's histogram) {g['bits_mean']:.0f} bits "
            f"({g['records_mean']:.1f} records): {g['reduction']:.0f}x fewer")


def run_summary(result, seconds: float) -> dict:
    """``summary.json`` of a :class:`~dptbd.evaluation.run.job.RunResult`."""
    from dptbd import __version__

    inp, pipeline = result.input, result.pipeline
    cfg, (n_frames, height, width) = inp.cfg, inp.frames.shape
    seg = segment_for_frame(inp.report_frame, pipeline.segments.end_frames)
    return {
        "tool": TOOL, "version": __version__,
        "source": inp.source,
        "scenario": result.scenario.to_dict(),
        "dp_config": cfg.to_mapping(),
        "association_config": dataclasses.asdict(inp.assoc),
        "frames": n_frames, "height": height, "width": width, "input_bits": inp.input_bits,
        "accumulated_frames": len(pipeline.segments.end_frames),
        "segment_end_frames": pipeline.segments.end_frames,
        "candidates_per_frame": inp.count,
        "lists": result.scenario.lists,
        "segmenter": {"histogram_bits": cfg.histogram_bits, "histogram_shift": cfg.bin_shift,
                      "histogram_shift_from": inp.shift_from,
                      "candidate_count": cfg.n_candidates,
                      "candidate_capacity": cfg.record_capacity},
        "table": result.rows,
        "tracks": result.tracks,
        "false_tracks": None if result.evaluation is None else result.evaluation.false_tracks,
        "dsp_stats": pipeline.stats,
        # written only for the C firmware, so that a default run's summary is unchanged
        **({"dsp": pipeline.dsp} if pipeline.dsp != "python" else {}),
        "bits_per_segment": result.segmentation_bits,
        "rtl": result.rtl if result.rtl is not None else {
            "checked": False, "summary": "RTL not simulated (golden model only; --rtl "
                                         "checks the generated Verilog)"},
        "report_frame": inp.report_frame, "report_segment": seg,
        "seconds": round(seconds, 2),
    }


def _candidate_rows(pipeline) -> list[dict]:
    ends = pipeline.segments.end_frames
    return [{"segment": s, "end_frame": int(ends[s]),
             "row": int(c["row"]), "col": int(c["col"]), "energy": int(c["energy"]),
             "direction": int(c["direction"]), "path_start_row": int(c["row0"]),
             "path_start_col": int(c["col0"])}
            for s, cs in enumerate(pipeline.candidates) for c in cs]


def write_run_folder(result, out: pathlib.Path, force: bool = False) -> pathlib.Path:
    """Write a run's folder (:data:`RUN_FILES`) through :func:`dptbd.output_folder.staged_folder`:
    all of it or, on any error, nothing; ``force`` replaces only an earlier run's folder.

    Returns
    -------
    pathlib.Path
        The folder written.
    """
    from dptbd.evaluation.run import figures as run_figures
    from dptbd.output_folder import staged_folder

    inp, pipeline, evaluation = result.input, result.pipeline, result.evaluation
    truth, cfg = inp.truth, inp.cfg
    n_frames = inp.frames.shape[0]
    seg = segment_for_frame(inp.report_frame, pipeline.segments.end_frames)
    seg_first = seg * cfg.segment_stride
    seg_last = int(pipeline.segments.end_frames[seg])

    def truth_at(t: int) -> list | None:
        if not truth:
            return None
        return [None if not tt.visible[t] else (int(tt.pixel[t, 0]), int(tt.pixel[t, 1]))
                for tt in truth]

    with staged_folder(out, force, marker="summary.json", tool=TOOL) as tmp:
        (tmp / "table.md").write_text(result.table_text + "\n")
        write_csv(tmp / "table.csv", result.rows if result.rows else result.tracks)
        write_csv(tmp / "tracks.csv", list(iter_track_positions(pipeline, evaluation)))
        write_csv(tmp / "candidates.csv", _candidate_rows(pipeline))
        (tmp / "scenario.toml").write_text(result.scenario.to_toml())
        run_figures.figure_raw_frame(tmp / "raw_frame.png", inp.frames[inp.report_frame],
                                     inp.report_frame, input_bits=inp.input_bits,
                                     truth_pixels=truth_at(inp.report_frame))
        run_figures.figure_accumulated(tmp / "accumulated.png", pipeline.segments.energy[seg],
                                       pipeline.candidates[seg], seg, seg_first, seg_last,
                                       truth_pixels=truth_at(seg_last))
        title = (f"{len(pipeline.tracks)} confirmed track(s)"
                 + ("" if evaluation is None else f", {evaluation.false_tracks} false")
                 + f" — {n_frames} frames, {len(pipeline.segments.end_frames)} segments")
        run_figures.figure_tracks(tmp / "tracks.png", pipeline, truth=truth,
                                  evaluation=evaluation, title=title)
        write_json(tmp / "summary.json",
                   run_summary(result, time.perf_counter() - result.started))
    return out
