"""Drawings and charts of mechanisms (matplotlib, object-oriented API: works without a display).

- :func:`draw_mechanism` — the linkage at one configuration (bodies as polylines, cylinders thick, ground pivots);
- :func:`plot_sweep` — the linkage at several positions along a sweep and chosen curves against the input;
- :func:`plot_plans` — velocity and acceleration plans (textbook section 4.2): every point's velocity and acceleration
  drawn from a pole, tips of points of one body joined (the relative velocities and accelerations).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pinocchio as pin
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from ..errors import InputError
from ..model.mechanism import Mechanism

_STYLE = {"link": dict(lw=2.0, marker="o", ms=4), "cylinder": dict(lw=5.0, solid_capstyle="round", alpha=0.6),
          "slider": dict(lw=0, marker="s", ms=9), "ground": dict(lw=1.0, ls="--")}


def _point_positions(mech: Mechanism, q: np.ndarray, names: Sequence[str]) -> dict[str, np.ndarray]:
    pin.forwardKinematics(mech.model, mech.data, q)
    return {n: pin.updateFramePlacement(mech.model, mech.data, mech.frame_id(n)).translation[:2].copy()
            for n in names}


def _sketch_names(mech: Mechanism) -> list[str]:
    names = list(mech.points)
    for line in mech.sketch:
        names.extend(p for p in line.points if p not in names)
    return names


def draw_mechanism(mech: Mechanism, q: np.ndarray, ax: Axes, *, color: str | None = None, alpha: float = 1.0,
                   labels: bool = True) -> None:
    """Draw ``mech`` at configuration ``q`` on ``ax`` (metres)."""
    positions = _point_positions(mech, q, _sketch_names(mech))
    for line in mech.sketch:
        xy = np.array([positions[p] for p in line.points])
        style = dict(_STYLE.get(line.kind, _STYLE["link"]))
        ax.plot(xy[:, 0], xy[:, 1], color=color or ("tab:orange" if line.kind == "cylinder" else "tab:blue"),
                alpha=alpha * style.pop("alpha", 1.0), **style)
    ground = [n for n in mech.points if mech.model.frames[mech.frame_id(n)].parentJoint == 0]
    for name in ground:
        ax.plot(*positions[name], marker="^", ms=10, color="black", alpha=alpha, ls="")
    if labels:
        for name in mech.points:
            ax.annotate(name, positions[name], textcoords="offset points", xytext=(4, 4), fontsize=8, alpha=alpha)


def plot_positions(mech: Mechanism, configurations: np.ndarray, ax: Axes, trace: str | None = None) -> None:
    """Draw several configurations (fading from light to dark) and the path of point ``trace``."""
    k = len(configurations)
    for i, q in enumerate(configurations):
        draw_mechanism(mech, q, ax, alpha=0.25 + 0.75 * (i + 1) / k, labels=i == k - 1)
    ax.set(aspect="equal", xlabel="x (m)", ylabel="y (m)")
    ax.grid(True, alpha=0.3)


def plot_sweep(result, path: str | Path, *, x: str | None = None, curves: Sequence[str] | None = None,
               positions: int = 6, trace: str | None = None, title: str | None = None) -> Path:
    """A PNG with the mechanism at ``positions`` configurations of the sweep (and the path of ``trace``) beside the
    ``curves`` (table columns) against the input ``x``."""
    mech = result.mechanism
    table = result.table
    if table.empty:
        raise InputError(f"{mech.name}: no sample could be assembled, nothing to plot")
    x = x or mech.actuated[0]
    curves = [c for c in (curves or []) if c in table.columns]
    fig = Figure(figsize=(12, 5.5), layout="constrained")
    ax_mech, ax_curves = fig.subplots(1, 2, width_ratios=[1.2, 1])
    picks = np.linspace(0, len(table) - 1, min(positions, len(table))).round().astype(int)
    plot_positions(mech, result.q[picks], ax_mech)
    if trace and f"{trace}_x" in table:
        ax_mech.plot(table[f"{trace}_x"], table[f"{trace}_y"], color="tab:red", lw=1, label=f"path of {trace}")
        ax_mech.legend(loc="best", fontsize=8)
    ax_mech.set_title(title or mech.description or mech.name, fontsize=10)
    for column in curves:
        values = table[column].to_numpy()
        is_angle = any(m.name == column and m.kind == "transmission_angle" for m in result.measures)
        ax_curves.plot(table[x], np.degrees(values) if is_angle else values,
                       label=column + (" (deg)" if is_angle else ""))
    for m in result.measures:
        if m.minimum is not None and m.name in curves and m.kind == "transmission_angle":
            ax_curves.axhline(np.degrees(m.minimum), color="gray", ls=":", lw=1)
    ax_curves.set(xlabel=x)
    ax_curves.grid(True, alpha=0.3)
    if curves:
        ax_curves.legend(fontsize=8)
    path = Path(path)
    _save(fig, path)
    return path


def plot_plans(mech: Mechanism, q: np.ndarray, v: np.ndarray, a: np.ndarray, path: str | Path,
               points: Sequence[str] | None = None) -> Path:
    """Velocity and acceleration plans (textbook fig. 4.10) of ``points`` at one position, as a PNG.

    Each point's absolute velocity is drawn from the pole p (its acceleration from the pole π); joining the tips of
    two points of one body gives their relative velocity (acceleration), e.g. v_CB = v_C − v_B.
    """
    from .transfer import point_state

    points = list(points or mech.points)
    states = {p: point_state(mech, q, v, a, p) for p in points}
    fig = Figure(figsize=(13, 4.5), layout="constrained")
    ax_mech, ax_v, ax_a = fig.subplots(1, 3)
    draw_mechanism(mech, q, ax_mech)
    ax_mech.set(aspect="equal", title="mechanism (m)")
    for ax, k, pole, unit in ((ax_v, 1, "p", "m/s"), (ax_a, 2, "π", "m/s²")):
        for name in points:
            vec = states[name][k][:2]
            ax.annotate("", xy=vec, xytext=(0, 0), arrowprops=dict(arrowstyle="->", color="tab:blue"))
            ax.annotate(name.lower(), vec, textcoords="offset points", xytext=(3, 3), fontsize=9)
        for line in mech.sketch:
            members = [p for p in line.points if p in states]
            if len(members) >= 2:
                tips = np.array([states[p][k][:2] for p in members])
                ax.plot(tips[:, 0], tips[:, 1], color="tab:gray", ls="--", lw=1)
        ax.plot(0, 0, "ko")
        ax.annotate(pole, (0, 0), textcoords="offset points", xytext=(-10, -10))
        ax.set(aspect="equal", title=f"{'velocity' if k == 1 else 'acceleration'} plan ({unit})")
        ax.grid(True, alpha=0.3)
        all_tips = np.array([states[p][k][:2] for p in points] + [[0.0, 0.0]])
        span = max(np.ptp(all_tips, axis=0).max(), 1e-12)
        ax.set_xlim(all_tips[:, 0].min() - 0.1 * span, all_tips[:, 0].max() + 0.1 * span)
        ax.set_ylim(all_tips[:, 1].min() - 0.1 * span, all_tips[:, 1].max() + 0.1 * span)
    path = Path(path)
    _save(fig, path)
    return path


def output_directory(directory: str | Path) -> Path:
    """``directory``, created if needed (an error naming it if it cannot be)."""
    directory = Path(directory)
    try:
        directory.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"cannot create the directory: {exc.strerror}", file=directory) from None
    return directory


def _save(fig: Figure, path: Path) -> None:
    try:
        fig.savefig(path, dpi=110)
    except OSError as exc:
        raise InputError(f"cannot write: {exc.strerror}", file=path) from None
