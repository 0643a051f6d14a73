"""The figures of ``dptbd run``: a raw frame, an accumulated image, the confirmed tracks.

Drawn in the one figure style of :mod:`dptbd.figures` (object API, Agg canvas).
"""

from __future__ import annotations

import pathlib

import numpy as np

from dptbd.figures import new_figure, save_figure

__all__ = ["figure_raw_frame", "figure_accumulated", "figure_tracks"]


_COLOURS = ("tab:red", "tab:blue", "tab:green", "tab:orange", "tab:purple", "tab:brown",
            "tab:pink", "tab:olive", "tab:cyan")


def figure_raw_frame(path: pathlib.Path, frame: np.ndarray, index: int, *, input_bits: int,
                     truth_pixels: list | None = None) -> None:
    """One raw input frame; with ground truth, a second panel circles where the targets are."""
    panels = 2 if truth_pixels else 1
    fig, axes = new_figure(5.2 * panels + 0.6, 5.0, ncols=panels, layout="constrained")
    axes = list(np.atleast_1d(axes))
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
    save_figure(fig, path)


def figure_accumulated(path: pathlib.Path, energy: np.ndarray, candidates: np.ndarray,
                       segment: int, first_frame: int, last_frame: int, *,
                       truth_pixels: list | None = None) -> None:
    """One segment's accumulated image E with its candidate points (and the true targets)."""
    fig, ax = new_figure(6.6, 5.6, layout="constrained")
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
    save_figure(fig, path)


def figure_tracks(path: pathlib.Path, result, *, truth=None, evaluation=None,
                  title: str = "") -> None:
    """Confirmed tracks (a position per frame) over the ground truth and all candidates.

    A track takes its target's colour (the colours of the other figures); false tracks
    and tracks of recorded data get the remaining colours.
    """
    cfg = result.cfg
    fig, ax = new_figure(9.4, 6.6, layout="constrained")
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
    save_figure(fig, path)
