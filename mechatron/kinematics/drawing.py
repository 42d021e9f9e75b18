"""Drawings of mechanisms: the mechanism plan of [Egorov, fig. 4.10] (a planar linkage at one position, lengths in
metres) and a stick figure of a serial arm, drawn into matplotlib axes given by the caller.

Nothing here imports matplotlib at module import or writes a file: every function draws into given axes or returns
a new :class:`~matplotlib.figure.Figure` (``mechatron.io.output.save_figure`` writes one to a file).

- :func:`draw_mechanism` — a linkage at one configuration (bodies as polylines, cylinders thick, ground pivots);
- :func:`draw_positions` — a linkage at several configurations of a motion, fading from light to dark;
- :func:`draw_stick_figure` — the joint origins of a kinematic tree joined parent to child, in one projection;
- :func:`draw_plan` — a velocity or acceleration plan ([Egorov, fig. 4.10]): vectors from a pole;
- :func:`configuration_figure` — a mechanism at one configuration: a linkage's drawing or an arm's two projections;
- :func:`key_below` — one legend under a figure's axes for the labelled artists of several axes.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from ..model.mechanism import Mechanism

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

_STYLE: dict[str, dict[str, Any]] = {
    "link": dict(lw=2.0, marker="o", ms=4), "cylinder": dict(lw=5.0, solid_capstyle="round", alpha=0.6),
    "slider": dict(lw=0, marker="s", ms=9), "ground": dict(lw=1.0, ls="--")}
_KIND_LABEL = {"link": "link", "cylinder": "hydraulic cylinder", "slider": "slider", "ground": "frame (ground)"}
#: Views of a stick figure: (horizontal axis, vertical axis) as indices of x, y, z.
PROJECTIONS = {"xz": (0, 2), "xy": (0, 1), "yz": (1, 2)}


def _point_positions(mech: Mechanism, q: ArrayLike, names: Sequence[str]) -> dict[str, NDArray[np.float64]]:
    """World (x, y) (m) of the origins of the frames ``names`` at q."""
    pin.forwardKinematics(mech.model, mech.data, np.asarray(q, dtype=float))
    return {n: pin.updateFramePlacement(mech.model, mech.data, mech.frame_id(n)).translation[:2].copy()
            for n in names}


def _sketch_names(mech: Mechanism) -> list[str]:
    names = list(mech.points)
    for line in mech.sketch:
        names.extend(p for p in line.points if p not in names)
    return names


def draw_mechanism(mech: Mechanism, q: ArrayLike, ax: Axes, *, color: str | None = None, alpha: float = 1.0,
                   labels: bool = True, key: bool = False) -> Axes:
    """Draw the linkage ``mech`` at configuration ``q`` on ``ax`` (x, y in metres): its sketch lines, its ground
    pivots (triangles) and, with ``labels``, the names of its points. With ``key`` the first line of each kind and
    the first ground pivot carry a legend label (the caller adds the legend). Returns ``ax``."""
    positions = _point_positions(mech, q, _sketch_names(mech))
    keyed: set[str] = set()
    for line in mech.sketch:
        xy = np.array([positions[p] for p in line.points])
        style = dict(_STYLE.get(line.kind, _STYLE["link"]))
        label = None
        if key and line.kind not in keyed:
            keyed.add(line.kind)
            label = _KIND_LABEL.get(line.kind, line.kind)
        ax.plot(xy[:, 0], xy[:, 1], color=color or ("tab:orange" if line.kind == "cylinder" else "tab:blue"),
                alpha=alpha * style.pop("alpha", 1.0), label=label, **style)
    ground = [n for n in mech.points if mech.model.frames[mech.frame_id(n)].parentJoint == 0]
    for i, name in enumerate(ground):
        ax.plot(*positions[name], marker="^", ms=10, color="black", alpha=alpha, ls="",
                label="ground pivot" if key and i == 0 else None)
    if labels:
        for name in mech.points:
            ax.annotate(name, positions[name],  # type: ignore[arg-type]  # matplotlib's stubs: xy a tuple, not an array
                        textcoords="offset points", xytext=(4, 4), fontsize=8, alpha=alpha)
    return ax


def draw_positions(mech: Mechanism, configurations: ArrayLike, ax: Axes, *, trace: str | None = None) -> Axes:
    """Draw the linkage at several ``configurations`` (N, nq), fading from light (first) to dark (last, with its
    point names and a key), and the path of the point ``trace`` through them if given (m). Returns ``ax``."""
    configurations = np.atleast_2d(np.asarray(configurations, dtype=float))
    k = len(configurations)
    for i, q in enumerate(configurations):
        last = i == k - 1
        draw_mechanism(mech, q, ax, alpha=0.25 + 0.75 * (i + 1) / k, labels=last, key=last)
    if trace is not None:
        path = np.array([_point_positions(mech, q, [trace])[trace] for q in configurations])
        ax.plot(path[:, 0], path[:, 1], color="tab:red", lw=1, label=f"path of {trace}")
    ax.set(aspect="equal", xlabel="x (m)", ylabel="y (m)")
    ax.grid(True, alpha=0.3)
    return ax


def joint_origins(mech: Mechanism, q: ArrayLike) -> tuple[NDArray[np.float64], list[tuple[int, int]]]:
    """World positions (m) of the joint origins at q, (njoints, 3) with the universe's origin first, and the
    (parent, child) pairs that join them."""
    pin.forwardKinematics(mech.model, mech.data, np.asarray(q, dtype=float))
    origins = np.array([mech.data.oMi[j].translation for j in range(mech.model.njoints)])
    edges = [(int(mech.model.parents[j]), j) for j in range(1, mech.model.njoints)]
    return origins, edges


def draw_stick_figure(mech: Mechanism, q: ArrayLike, ax: Axes, *, view: str = "xz",
                      frame: str | None = None) -> Axes:
    """Draw the joint origins of ``mech`` at q joined parent to child, projected on the world plane ``view``
    ("xz": side view, "xy": top view, "yz": front view; metres), with the base and, if given, the origin of
    ``frame`` marked and keyed. Returns ``ax``."""
    i, j = PROJECTIONS[view]
    origins, edges = joint_origins(mech, q)
    for k, (parent, child) in enumerate(edges):
        ax.plot(origins[[parent, child], i], origins[[parent, child], j], color="tab:blue", lw=2.5, marker="o",
                ms=5, label="links (joint origin to joint origin)" if k == 0 else None)
    ax.plot(origins[0, i], origins[0, j], ls="", marker="s", ms=9, color="black", label="base")
    if frame is not None:
        fid = mech.frame_id(frame)
        placement = pin.updateFramePlacement(mech.model, mech.data, fid)
        parent = mech.model.frames[fid].parentJoint
        ends = np.array([origins[parent], placement.translation])
        ax.plot(ends[:, i], ends[:, j], color="tab:blue", lw=1.5, ls=":")
        ax.plot(placement.translation[i], placement.translation[j], ls="", marker="*", ms=13, color="tab:red",
                label=f"frame {frame}")
    names = "xyz"
    ax.set(aspect="equal", xlabel=f"{names[i]} (m)", ylabel=f"{names[j]} (m)")
    ax.grid(True, alpha=0.3)
    return ax


def draw_plan(ax: Axes, vectors: Mapping[str, ArrayLike], groups: Sequence[Sequence[str]], *, pole: str,
              unit: str, quantity: str, legend: bool = True) -> Axes:
    """A velocity or acceleration plan ([Egorov, 4.2, fig. 4.10]) on ``ax``: each point's vector (its first two
    components, in ``unit``) drawn from the pole, its tip named by the point's name in lower case; the tips of the
    points of one body (``groups``) are joined, each joining segment being the relative velocity (acceleration) of
    two points of that body, e.g. v_CB = v_C − v_B. ``quantity`` names the axes ("v" or "a"); ``legend`` adds the
    axes' legend (else the caller keys the pole and the joined tips). Returns ``ax``."""
    tips = {name: np.asarray(vec, dtype=float)[:2] for name, vec in vectors.items()}
    for name, tip in tips.items():
        ax.annotate("", xy=tip, xytext=(0, 0),  # type: ignore[arg-type]  # matplotlib's stubs: xy a tuple
                    arrowprops=dict(arrowstyle="->", color="tab:blue"))
        ax.annotate(name.lower(), tip,  # type: ignore[arg-type]  # matplotlib's stubs: xy a tuple, not an array
                    textcoords="offset points", xytext=(3, 3), fontsize=9)
    joined = False
    for group in groups:
        members = [p for p in group if p in tips]
        if len(members) >= 2:
            xy = np.array([tips[p] for p in members])
            ax.plot(xy[:, 0], xy[:, 1], color="tab:gray", ls="--", lw=1,
                    label=None if joined else "relative (points of one body)")
            joined = True
    ax.plot(0, 0, "ko", label=f"pole {pole}")
    ax.annotate(pole, (0, 0), textcoords="offset points", xytext=(-10, -10))
    every = np.array([*tips.values(), [0.0, 0.0]])
    span = max(float(np.ptp(every, axis=0).max()), 1e-12)
    ax.set_xlim(every[:, 0].min() - 0.1 * span, every[:, 0].max() + 0.1 * span)
    ax.set_ylim(every[:, 1].min() - 0.1 * span, every[:, 1].max() + 0.1 * span)
    ax.set(aspect="equal", xlabel=f"{quantity}_x ({unit})", ylabel=f"{quantity}_y ({unit})")
    ax.grid(True, alpha=0.3)
    if legend:
        ax.legend(fontsize=8, loc="upper right")
    return ax


def key_below(figure: Figure, axes: Sequence[Axes]) -> None:
    """One legend under the axes of ``figure`` (a constrained layout makes room for it) with every labelled artist
    of ``axes``, each label once."""
    handles: dict[str, Any] = {}
    for ax in axes:
        for handle, label in zip(*ax.get_legend_handles_labels()):
            handles.setdefault(label, handle)
    if handles:
        figure.legend(list(handles.values()), list(handles), loc="outside lower center", ncol=min(len(handles), 6),
                      fontsize=8, frameon=False)


def configuration_figure(mech: Mechanism, q: ArrayLike, *, frame: str | None = None, ax: Axes | None = None,
                         title: str | None = None) -> Figure:
    """``mech`` at configuration q (m): a linkage with a sketch as its drawing (:func:`draw_mechanism`), any other
    tree as a stick figure (:func:`draw_stick_figure`) in a side (x–z) and a top (x–y) view, the origin of ``frame``
    marked and everything keyed. Drawn into ``ax`` if given (a linkage's drawing or the side view), else into a new
    figure; returns the figure."""
    from ..report.figures import figure_axes, new_figure

    title = title or f"{mech.name} at q = {np.round(mech.coordinates(q), 4).tolist()}"
    given = ax is not None
    if mech.sketch:
        figure, ax = figure_axes(ax, 7.0, 5.5)
        draw_mechanism(mech, q, ax, key=True)
        if frame is not None:
            xy = _point_positions(mech, q, [frame])[frame]
            ax.plot(*xy, ls="", marker="*", ms=13, color="tab:red", label=f"frame {frame}")
        ax.set(aspect="equal", xlabel="x (m)", ylabel="y (m)")
        ax.set_title(title, fontsize=10)
        ax.grid(True, alpha=0.3)
        axes = [ax]
    else:
        if ax is not None:  # given
            axes = [ax]
        else:
            figure = new_figure(11.0, 5.0)
            axes = list(figure.subplots(1, 2))
        for view, axis in zip(("xz", "xy"), axes):
            draw_stick_figure(mech, q, axis, view=view, frame=frame)
            axis.set_title(f"{title}: {'side' if view == 'xz' else 'top'} view", fontsize=10)
        figure = figure_axes(axes[0])[0]
    if given:
        axes[0].legend(fontsize=8, loc="best")
    else:
        key_below(figure, axes)
    return figure
