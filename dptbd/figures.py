"""The one figure style of every report: matplotlib's object API on the Agg canvas.

Figures are made with :func:`new_figure` and written with :func:`save_figure`; nothing goes
through ``pyplot``, so no global state, no GUI backend and no figure left open between jobs.
"""

from __future__ import annotations

import pathlib
from typing import Any

__all__ = ["new_figure", "save_figure", "DPI"]

#: Resolution of every saved figure (dots per inch).
DPI = 110


def new_figure(width: float, height: float, *, nrows: int = 1, ncols: int = 1,
               dpi: float = DPI, layout: str | None = None, **subplot_kw: Any):
    """A ``Figure`` of ``width`` x ``height`` inches on an Agg canvas and its axes.

    Returns
    -------
    (matplotlib.figure.Figure, axes)
        ``axes`` as ``Figure.subplots`` returns them (one ``Axes`` for 1 x 1).
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), dpi=dpi, layout=layout)
    FigureCanvasAgg(fig)
    axes = fig.subplots(nrows, ncols, subplot_kw=subplot_kw or None)
    return fig, axes


def save_figure(fig, path: pathlib.Path, *, dpi: float | None = None) -> pathlib.Path:
    """Write ``fig`` as PNG to ``path`` (at the figure's own dpi unless ``dpi`` is given)."""
    path = pathlib.Path(path)
    fig.savefig(path, dpi=dpi if dpi is not None else "figure")
    return path
