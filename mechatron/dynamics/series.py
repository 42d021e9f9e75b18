"""Helpers the dynamics results share: time-series columns, stacked charts against time, plain-text tables.

Charts use matplotlib's object-oriented API through :mod:`mechatron.report.figures` (imported when drawn), so
results can be built and printed without matplotlib.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

#: Units of a coordinate, its derivatives and its force, by whether it is an angle: (position, speed, acceleration,
#: force).
UNITS = {True: ("rad", "rad/s", "rad/s²", "N·m"), False: ("m", "m/s", "m/s²", "N")}


def coordinate_columns(t: ArrayLike, names: Sequence[str], positions: ArrayLike, speeds: ArrayLike,
                       accelerations: ArrayLike) -> dict[str, np.ndarray]:
    """{t, <name>, qd_<name>, qdd_<name>}: the columns of a motion of named coordinates (s; rad or m; …/s; …/s²)."""
    X, V, A = (np.asarray(x, dtype=float).reshape(len(np.atleast_1d(t)), -1) for x in (positions, speeds,
                                                                                       accelerations))
    columns: dict[str, np.ndarray] = {"t": np.asarray(t, dtype=float)}
    for prefix, values in (("", X), ("qd_", V), ("qdd_", A)):
        for i, name in enumerate(names):
            columns[f"{prefix}{name}"] = values[:, i]
    return columns


def unit_label(what: str, angular: Sequence[bool] | None, index: int) -> str:
    """``"speed (rad/s)"``: the quantity ``what`` ("position", "speed", "acceleration", "force") with the unit(s) of
    the coordinates (both units where angles and lengths mix, or where the kinds are not known). A "force" is named
    by kind: ``"torque (N·m)"`` for angles, ``"force (N)"`` for lengths, ``"torque (N·m), force (N)"`` for both."""
    kinds = sorted(set(angular)) if angular is not None and len(angular) else [True, False]
    if what == "force":
        return ", ".join(load_label(k) for k in reversed(kinds))
    return f"{what} ({', '.join(UNITS[k][index] for k in reversed(kinds))})"


def load_label(angular: bool) -> str:
    """What drives a coordinate, with its unit: ``"torque (N·m)"`` (an angle) or ``"force (N)"`` (a length)."""
    return f"{'torque' if angular else 'force'} ({UNITS[angular][3]})"


def stacked_axes(ax: Axes | None, rows: int, width: float = 9.0, height: float = 2.4) -> tuple[Figure, list[Axes]]:
    """(figure, axes): the given ``ax`` alone (the caller draws its main chart there), or a new figure with ``rows``
    axes above each other sharing the time axis."""
    from ..report.figures import figure_axes, new_figure

    if ax is not None:
        figure, ax = figure_axes(ax)
        return figure, [ax]
    figure = new_figure(width, height * rows + 0.6)
    axes = figure.subplots(rows, 1, sharex=True, squeeze=False)[:, 0]
    return figure, list(axes)


def plot_lines(ax: Axes, x: ArrayLike, ys: ArrayLike, labels: Sequence[str], xlabel: str, ylabel: str,
               title: str | None = None) -> Axes:
    """One labelled line per column of ``ys`` against ``x``, axes labelled (with units) and keyed in a legend."""
    from ..report.figures import style_axes

    Y = np.asarray(ys, dtype=float).reshape(len(np.atleast_1d(x)), -1)
    for i, label in enumerate(labels):
        ax.plot(x, Y[:, i], label=label, linewidth=1.2)
    return style_axes(ax, xlabel, ylabel, title, legend=True, ncol=min(6, max(1, len(labels))))


def text_table(rows: Sequence[Mapping[str, Any]], columns: Sequence[str] | None = None, digits: int = 5) -> str:
    """Rows of values as an aligned plain-text table (numbers with ``digits`` significant digits)."""
    if not rows:
        return "(none)"
    columns = list(columns or dict.fromkeys(k for row in rows for k in row))

    def cell(value: Any) -> str:
        if value is None:
            return "-"
        if isinstance(value, (float, np.floating)):
            return f"{float(value) + 0.0:.{digits}g}"  # + 0.0: no "-0"
        return str(value)

    cells = [[cell(row.get(c)) for c in columns] for row in rows]
    widths = [max(len(c), *(len(r[k]) for r in cells)) for k, c in enumerate(columns)]
    lines = ["  ".join(c.rjust(w) for c, w in zip(columns, widths))]
    lines += ["  ".join(v.rjust(w) for v, w in zip(r, widths)) for r in cells]
    return "\n".join(lines)
