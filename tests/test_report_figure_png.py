"""figure_png: one drawing cropped to its content gives the picture of savefig(bbox_inches="tight")
(within the few pixels between a text's line box and its ink), legends outside the axes kept."""
import base64
import io

import numpy as np
import pytest

from stand.reports import html
from stand.reports.html import FIGURE_DPI, figure_png

matplotlib = pytest.importorskip("matplotlib")
from matplotlib.figure import Figure  # noqa: E402
from matplotlib.image import imread  # noqa: E402

#: the tight box holds each text's line box (ascent + descent: 0.24 em of DejaVu Sans below the
#: baseline, 3 px at 10 pt and 90 dpi), the crop its ink; plus 1 px of rounding
TOL_PX = 4
PAD_PX = round(0.1 * FIGURE_DPI)


def _decode(uri):
    return imread(io.BytesIO(base64.b64decode(uri.split(",", 1)[1])), format="png")


def _tight(fig):
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=FIGURE_DPI, bbox_inches="tight")
    return buf.getvalue()


def _figure(anchor):
    fig = Figure(figsize=(5.6, 3.8))
    ax = fig.add_subplot(projection="polar")
    for k in range(3):
        ax.plot([0, k + 1.0], [0, 2.0 + k], "o-", label=f"run {k} (a long label for the legend)")
    ax.set_title("S1 [mm/s pk]", fontsize=9)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=anchor)
    return fig


@pytest.mark.parametrize("anchor", [(1.08, 1.0), (0.5, -0.32)], ids=["right", "below"])
def test_cropped_like_the_tight_box_with_the_outside_legend(anchor):
    fig = _figure(anchor)
    img = _decode(figure_png(fig))
    ref = imread(io.BytesIO(_tight(fig)), format="png")
    assert abs(img.shape[0] - ref.shape[0]) <= TOL_PX
    assert abs(img.shape[1] - ref.shape[1]) <= TOL_PX
    ink = np.any(img[..., :3] < 1.0, axis=2)               # white background elsewhere
    rows, cols = np.flatnonzero(ink.any(axis=1)), np.flatnonzero(ink.any(axis=0))
    # nothing clipped: the ink stops the pad short of every edge
    assert rows[0] == cols[0] == PAD_PX
    assert img.shape[0] - 1 - rows[-1] == img.shape[1] - 1 - cols[-1] == PAD_PX


def test_content_beyond_the_margin_falls_back_to_the_tight_box():
    fig = _figure((1.0 + 2.5 * html._MARGIN_IN, 1.0))      # legend far beyond the margin
    ref = _tight(fig)
    assert base64.b64decode(figure_png(fig).split(",", 1)[1]) == ref


def test_an_image_s_white_border_is_kept():
    fig = Figure(figsize=(4, 4))
    ax = fig.subplots()
    frame = np.ones((50, 50))
    frame[20:30, 20:30] = 0.0                               # a dark square on white
    ax.imshow(frame, cmap="gray", origin="upper")
    ax.set_axis_off()
    img = _decode(figure_png(fig))
    side = 4 * FIGURE_DPI * min(fig.subplotpars.right - fig.subplotpars.left,
                                fig.subplotpars.top - fig.subplotpars.bottom)
    assert abs(img.shape[0] - (side + 2 * PAD_PX)) <= 2
    assert abs(img.shape[1] - (side + 2 * PAD_PX)) <= 2


@pytest.mark.parametrize("size", [(9, 4.2), (8, 5), (8, 3), (5, 5), (8, 4), (8, 3.5), (4, 4), (4.6, 4.6),
                                  (3.8, 3.8), (5.6, 3.8)])
def test_the_report_figure_sizes_take_the_one_draw_path(size):
    """The canvas' pixel size is matplotlib's (a size of 737.99999 px is 738 px, not 737)."""
    fig = Figure(figsize=size)
    fig.subplots().plot([0.0, 1.0], [0.0, 1.0])
    assert html._cropped_png(fig, io.BytesIO())
