"""Figures without a plotting backend: library code draws on matplotlib's object API.

Plot functions take ``ax=`` (draw into the caller's axes, e.g. inside a
notebook's figure) and return the :class:`matplotlib.figure.Figure`; without
``ax`` they make a figure that belongs to no backend and no pyplot state
(``matplotlib.figure.Figure``), so the library never calls ``matplotlib.use``.
:func:`save_figure` writes one atomically.
"""
from __future__ import annotations

__all__ = ["figure_and_axes", "save_figure"]


def figure_and_axes(ax=None, **figure_kw):
    """``(figure, axes)``: ``ax`` and its figure, or a new backend-free figure with one axes."""
    if ax is not None:
        return ax.figure, ax
    from matplotlib.figure import Figure

    fig = Figure(**figure_kw)
    return fig, fig.subplots()


def save_figure(fig, path, dpi: int = 120, fmt: str = "png"):
    """Write ``fig`` to ``path`` atomically (:func:`stand.io.atomic.atomic_path`)."""
    from stand.io.atomic import atomic_path

    with atomic_path(path, suffix=f".{fmt}.tmp") as tmp:
        fig.savefig(tmp, dpi=dpi, format=fmt)
    return path
