"""Tables and figures of ``dptbd run``: 001's Table 1 form, track lists, PNG figures.

Figures are drawn with matplotlib's object API (``Figure`` + Agg canvas), never through
``pyplot``, so no global backend or window is involved.
"""

from __future__ import annotations

import csv
import json
import math
import pathlib
from typing import Any, Iterable

import numpy as np

from dptbd.evaluation.metrics import first_level_counts
from dptbd.evaluation.table1 import PAPER_TABLE1

__all__ = ["TABLE_COLUMNS", "table_rows", "format_table", "paper_lines", "track_rows",
           "format_tracks", "write_csv", "write_json", "figure_raw_frame",
           "figure_accumulated", "figure_tracks", "segment_for_frame", "segmentation_bits",
           "format_segmentation_bits"]

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


def _jsonable(v: Any) -> Any:
    if isinstance(v, dict):
        return {str(k): _jsonable(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [_jsonable(x) for x in v]
    if isinstance(v, np.ndarray):
        return _jsonable(v.tolist())
    if isinstance(v, np.generic):
        return _jsonable(v.item())
    if isinstance(v, float) and not math.isfinite(v):
        return None
    if isinstance(v, pathlib.Path):
        return str(v)
    return v


def write_json(path: pathlib.Path, obj: Any) -> None:
    path.write_text(json.dumps(_jsonable(obj), indent=2) + "\n")


# ---- figures ----------------------------------------------------------------------------

def _figure(width: float, height: float):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), dpi=110, layout="constrained")
    FigureCanvasAgg(fig)
    return fig


_COLOURS = ("tab:red", "tab:blue", "tab:green", "tab:orange", "tab:purple", "tab:brown",
            "tab:pink", "tab:olive", "tab:cyan")


def segment_for_frame(frame: int, end_frames: np.ndarray) -> int:
    """The segment whose last frame is the first at or after ``frame`` (else the last)."""
    later = np.flatnonzero(np.asarray(end_frames) >= frame)
    return int(later[0]) if later.size else len(end_frames) - 1


def figure_raw_frame(path: pathlib.Path, frame: np.ndarray, index: int, *, input_bits: int,
                     truth_pixels: list | None = None) -> None:
    """One raw input frame; with ground truth, a second panel circles where the targets are."""
    panels = 2 if truth_pixels else 1
    fig = _figure(5.2 * panels + 0.6, 5.0)
    axes = fig.subplots(1, panels, squeeze=False)[0]
    lo, hi = np.percentile(frame, [0.5, 99.5])
    for k, ax in enumerate(axes):
        im = ax.imshow(frame, cmap="gray", vmin=lo, vmax=hi, interpolation="nearest")
        ax.set_xlabel("column")
        ax.set_ylabel("row")
        if k == 0:
            ax.set_title(f"raw frame {index} ({input_bits}-bit codes)")
        else:
            ax.set_title("the same frame: where the targets are")
            for j, pix in enumerate(truth_pixels):
                if pix is None:
                    continue
                ax.scatter([pix[1]], [pix[0]], s=260, facecolors="none",
                           edgecolors=_COLOURS[j % len(_COLOURS)], linewidths=1.6,
                           label=f"target {j + 1} at ({pix[0]}, {pix[1]})")
            ax.legend(loc="lower left", fontsize=8, framealpha=0.85)
    fig.colorbar(im, ax=list(axes), shrink=0.8, label="ADC code")
    fig.savefig(path)


def figure_accumulated(path: pathlib.Path, energy: np.ndarray, candidates: np.ndarray,
                       segment: int, first_frame: int, last_frame: int, *,
                       truth_pixels: list | None = None) -> None:
    """One segment's accumulated image E with its candidate points (and the true targets)."""
    fig = _figure(6.6, 5.6)
    ax = fig.subplots()
    lo, hi = np.percentile(energy, [1, 99.9])
    im = ax.imshow(energy, cmap="magma", vmin=lo, vmax=hi, interpolation="nearest")
    ax.scatter(candidates["col"], candidates["row"], s=40, marker="s", facecolors="none",
               edgecolors="cyan", linewidths=1.0, label=f"candidate points ({len(candidates)})")
    for j, pix in enumerate(truth_pixels or []):
        if pix is not None:
            ax.scatter([pix[1]], [pix[0]], s=260, facecolors="none",
                       edgecolors=_COLOURS[j % len(_COLOURS)], linewidths=1.6,
                       label=f"target {j + 1} (true)")
    ax.set_title(f"accumulated energy E, segment {segment} (frames {first_frame}–{last_frame})")
    ax.set_xlabel("column")
    ax.set_ylabel("row")
    ax.legend(loc="lower left", fontsize=8, framealpha=0.85)
    fig.colorbar(im, ax=ax, shrink=0.85, label="E (fixed point)")
    fig.savefig(path)


def figure_tracks(path: pathlib.Path, result, *, truth=None, evaluation=None,
                  title: str = "") -> None:
    """Confirmed tracks (a position per frame) over the ground truth and all candidates.

    A track takes its target's colour (the colours of the other figures); false tracks
    and tracks of recorded data get the remaining colours.
    """
    cfg = result.cfg
    fig = _figure(9.4, 6.6)
    ax = fig.subplots()
    if result.candidates:
        allc = np.concatenate(result.candidates)
        ax.scatter(allc["col"], allc["row"], s=5, c="0.6", marker=".", linewidths=0,
                   label=f"candidate points, all {len(result.candidates)} segments")
    n_truth = len(truth or [])
    for j, tt in enumerate(truth or []):
        vis = tt.visible
        ax.plot(tt.position[vis, 1], tt.position[vis, 0], "--", color="black", lw=1.0,
                label="ground truth" if j == 0 else None)
        first = np.flatnonzero(vis)
        if first.size:
            ax.annotate(f"target {j + 1}", (tt.position[first[0], 1], tt.position[first[0], 0]),
                        textcoords="offset points", xytext=(5, 5), fontsize=9,
                        color=_COLOURS[j % len(_COLOURS)], fontweight="bold")
    spare = n_truth
    for tr in result.tracks:
        frames, pos, measured = result.positions[tr.id]
        owner = -1 if evaluation is None else evaluation.track_target.get(tr.id, -1)
        if owner >= 0:
            colour = _COLOURS[owner % len(_COLOURS)]
        else:
            colour = _COLOURS[spare % len(_COLOURS)]
            spare += 1
        what = ("" if evaluation is None else
                (f" → target {owner + 1}" if owner >= 0 else " (false track)"))
        ax.plot(pos[:, 1], pos[:, 0], "-", color=colour, lw=2.0, alpha=0.9,
                label=f"track {tr.id}{what}")
        gaps = ~measured
        if gaps.any():
            ax.plot(np.where(gaps, pos[:, 1], np.nan), np.where(gaps, pos[:, 0], np.nan), "-",
                    color="white", lw=0.8)
        conf_frame = tr.confirm_segment * cfg.segment_stride + cfg.segment_frames - 1
        at = np.flatnonzero(frames == conf_frame)
        if at.size:
            ax.scatter([pos[at[0], 1]], [pos[at[0], 0]], marker="*", s=160, color=colour,
                       edgecolors="black", linewidths=0.6, zorder=5)
        ax.scatter([pos[0, 1]], [pos[0, 0]], marker="o", s=22, color=colour,
                   edgecolors="black", linewidths=0.4, zorder=5)
    if result.tracks:
        ax.scatter([], [], marker="o", s=22, color="0.5", edgecolors="black", linewidths=0.4,
                   label="track start")
        ax.scatter([], [], marker="*", s=120, color="0.5", edgecolors="black", linewidths=0.6,
                   label="track output (confirmed)")
        ax.plot([], [], "-", color="0.5", lw=2.0, label="track (thin white core:\n"
                "missed segments, interpolated)")
    ax.set_xlim(-0.5, cfg.width - 0.5)
    ax.set_ylim(cfg.height - 0.5, -0.5)
    ax.set_aspect("equal")
    ax.set_xlabel("column")
    ax.set_ylabel("row")
    ax.set_title(title or f"confirmed tracks ({len(result.tracks)})")
    fig.legend(loc="outside right upper", fontsize=8, framealpha=0.9)
    fig.savefig(path)


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
