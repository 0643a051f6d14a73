"""dptbd.figures: object-API figures on the Agg canvas, no pyplot state, PNGs at the figure's dpi."""

import sys

import numpy as np
from PIL import Image

from dptbd.figures import DPI, new_figure, save_figure


def test_new_figure_gives_a_figure_and_its_axes_on_agg():
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    fig, ax = new_figure(4.0, 3.0)
    assert isinstance(fig.canvas, FigureCanvasAgg)
    assert tuple(fig.get_size_inches()) == (4.0, 3.0) and fig.dpi == DPI
    assert fig.axes == [ax]
    fig, axes = new_figure(6.0, 3.0, nrows=1, ncols=2, dpi=50, layout="constrained")
    assert axes.shape == (2,) and fig.dpi == 50
    assert fig.get_layout_engine().__class__.__name__ == "ConstrainedLayoutEngine"
    _, ax = new_figure(3.0, 3.0, projection="polar")
    assert ax.name == "polar"


def test_no_pyplot_figure_is_left_open():
    new_figure(2.0, 2.0)
    plt = sys.modules.get("matplotlib.pyplot")
    assert plt is None or plt.get_fignums() == []


def test_save_figure_writes_a_png_at_the_figure_dpi_or_the_one_given(tmp_path):
    fig, ax = new_figure(2.0, 1.0, dpi=100)
    ax.plot(np.arange(3))
    assert save_figure(fig, tmp_path / "a.png") == tmp_path / "a.png"
    with Image.open(tmp_path / "a.png") as img:
        assert img.format == "PNG" and img.size == (200, 100)
    save_figure(fig, str(tmp_path / "b.png"), dpi=50)
    with Image.open(tmp_path / "b.png") as img:
        assert img.size == (100, 50)


def test_the_same_figure_gives_the_same_bytes(tmp_path):
    for name in ("a.png", "b.png"):
        fig, ax = new_figure(2.0, 2.0)
        ax.plot([0, 1], [1, 0])
        save_figure(fig, tmp_path / name)
    assert (tmp_path / "a.png").read_bytes() == (tmp_path / "b.png").read_bytes()
