"""Figures for results: matplotlib's object-oriented API only, so charts are drawn without a display."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure


def new_figure(width: float = 8.0, height: float = 5.0) -> Figure:
    """An empty figure with a constrained layout (no pyplot, no display needed)."""
    from matplotlib.figure import Figure

    return Figure(figsize=(width, height), layout="constrained")


def figure_axes(ax: Axes | None = None, width: float = 8.0, height: float = 5.0) -> tuple[Figure, Axes]:
    """(figure, axes): ``ax`` and its figure if given, else a new figure with one axes."""
    if ax is not None:
        return ax.get_figure(), ax
    figure = new_figure(width, height)
    return figure, figure.add_subplot()


def time_colour_bar(ax: Axes, points: Any) -> None:
    """A colour bar beside ``ax`` for ``points`` coloured by time, labelled ``t (s)``."""
    ax.get_figure().colorbar(points, ax=ax, label="t (s)")


def style_axes(ax: Axes, xlabel: str, ylabel: str, title: str | None = None, legend: bool = False,
               **legend_options: Any) -> Axes:
    """Label both axes (with their units), add a light grid, a title and, if asked, a legend."""
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    if title:
        ax.set_title(title, fontsize=10)
    ax.grid(True, alpha=0.3)
    if legend and ax.get_legend_handles_labels()[0]:
        ax.legend(**{"fontsize": 8, **legend_options})
    return ax
