"""Sizing reports: a text table per joint, CSV and JSON export, speed–torque charts of the chosen motors (and
force–speed charts of the chosen cylinders)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from ..errors import InputError
from ..io.output import output_directory
from ..io.output import save_figure as _save
from .cylinders import CylinderSizing
from .motor import continuous_torque, peak_torque_limit
from .sizing import JointSizing, SizingResult

RPM = 60 / (2 * math.pi)


def clean(value):
    """``value`` with numpy scalars as Python numbers and non-finite floats as None (strict JSON)."""
    if isinstance(value, dict):
        return {str(k): clean(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [clean(v) for v in value]
    if isinstance(value, np.ndarray):
        return clean(value.tolist())
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def to_json(result: SizingResult) -> str:
    return json.dumps(clean(result.as_dict()), indent=2, allow_nan=False)


def _write(path: Path, text: str) -> Path:
    try:
        path.write_text(text)
    except OSError as exc:
        raise InputError(f"cannot write: {exc.strerror}", file=path) from None
    return path


def write_json(result: SizingResult, path: str | Path) -> Path:
    return _write(Path(path), to_json(result) + "\n")


def write_csv(result: SizingResult, path: str | Path) -> Path:
    """Every check of every joint, one row each (:meth:`SizingResult.table`)."""
    return _write(Path(path), result.table().to_csv(index=False, float_format="%.8g"))


def _display(check) -> tuple[str, str, str]:
    """Value, limit and unit as shown to people: speeds in rpm, pressures in MPa."""
    value, limit, unit = check.value, check.limit, check.unit
    if unit == "rad/s":
        value, limit, unit = value * RPM, limit * RPM, "rpm"
    elif unit == "Pa":
        value, limit, unit = value / 1e6, limit / 1e6, "MPa"
    return f"{value:.4g}", f"{limit:.4g}", unit


def _joint_text(j) -> list[str]:
    if isinstance(j, CylinderSizing):
        head = (f"{j.joint}: cylinder {j.cylinder} ×{j.count} (bore {j.cylinder_data['bore'] * 1e3:g} mm, rod "
                f"{j.cylinder_data['rod'] * 1e3:g} mm), peak flow {j.peak_flow * 6e4:.1f} l/min")
    else:
        through = "direct drive" if j.converter == "direct" else f"{j.converter_kind} {j.converter}, u = {j.ratio:.4g}"
        head = f"{j.joint}: motor {j.motor} + {through}"
    lines = [head if j.feasible else f"{head}  — NO FEASIBLE DRIVE; the closest one shown"]
    lines.append(f"    {'check':<32}{'value':>11}{'limit':>11}  {'unit':<6}{'margin':>8}  result")
    for c in j.checks:
        value, limit, unit = _display(c)
        lines.append(f"    {c.name:<32}{value:>11}{limit:>11}  {unit:<6}{c.margin:>8.1%}  "
                     f"{'PASS' if c.passed else 'FAIL'}")
    if not j.feasible:
        lines.append("    closest candidates and the checks they fail (load factor = value/limit):")
        for row in j.closest.to_dict(orient="records"):
            name = f"{row['motor']} + {row['converter']}" if "motor" in row else row["cylinder"]
            lines.append(f"      {name}: {row['failed']}")
    return lines


def text_report(result: SizingResult) -> str:
    """The sizing as text: the chosen drive of every joint with every check, margin and PASS/FAIL."""
    joints = result.joints
    duration = joints[0].duty.duration if joints else 0.0
    lines = [f"{result.mechanism}: drive sizing for '{result.task}' ({duration:.3f} s, objective {result.objective})"]
    if result.objective == "time":
        lines.append(f"fastest feasible pace: the task replayed ×{result.time_scale:.3f} in time "
                     f"({duration:.3f} s instead of {duration / result.time_scale:.3f} s)")
    for j in joints:
        lines += [""] + _joint_text(j)
    verdict = "every joint has a feasible drive" if result.feasible else \
        "NOT FEASIBLE: no drive passes every check for " + ", ".join(j.joint for j in joints if not j.feasible)
    lines += ["", verdict]
    return "\n".join(lines)


# ------------------------------------------------------------------------------------------------ charts
def speed_torque_chart(sizing: JointSizing, path: str | Path) -> Path:
    """The chosen motor's continuous and intermittent speed–torque limits with the task's operating points and
    its RMS point (mean speed, RMS torque)."""
    m = sizing.motor_data
    n, torque = sizing.operating_points()
    top = m["max_speed"]
    speed = np.linspace(0.0, top, 200)
    fig = Figure(figsize=(7.5, 5), layout="constrained")
    ax = fig.subplots()
    ax.fill_between(speed * RPM, 0, peak_torque_limit(speed, m["peak_torque"], m["rated_torque"],
                                                      m["rated_speed"], top), color="tab:orange", alpha=0.18,
                    label="intermittent zone")
    ax.fill_between(speed * RPM, 0, continuous_torque(speed, m["rated_torque"], m["rated_speed"], top),
                    color="tab:green", alpha=0.3, label="continuous zone (S1)")
    ax.scatter(np.abs(n) * RPM, np.abs(torque), s=6, c=sizing.duty.t, cmap="viridis", label="operating points")
    rms = next(c for c in sizing.checks if c.name == "RMS torque")
    mean_speed = next((c.value for c in sizing.checks if c.name == "transmission mean input speed"),
                      float(np.mean(np.abs(n))))
    ax.plot([mean_speed * RPM], [rms.value], "r*", ms=14, label=f"RMS torque {rms.value:.3g} N·m at mean speed")
    ax.set_xlabel("motor speed (rpm)")
    ax.set_ylabel("motor torque (N·m)")
    ax.set_xlim(0, top * RPM * 1.05)
    ax.set_ylim(0, max(m["peak_torque"], float(np.abs(torque).max())) * 1.1)
    status = "" if sizing.feasible else " — NOT FEASIBLE"
    through = "direct" if sizing.converter == "direct" else f"{sizing.converter}, u = {sizing.ratio:.4g}"
    ax.set_title(f"{sizing.joint}: {sizing.motor} ({through}){status}")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper right", fontsize=8)
    _save(fig, Path(path))
    return Path(path)


def force_speed_chart(sizing: CylinderSizing, path: str | Path) -> Path:
    """The chosen cylinder's force over speed along the task with its push and pull limits."""
    c = sizing.cylinder_data
    push = next(x for x in sizing.checks if x.name == "push pressure")
    piston = math.pi * c["bore"] ** 2 / 4
    annulus = piston - math.pi * c["rod"] ** 2 / 4
    count = sizing.count
    fig = Figure(figsize=(7.5, 5), layout="constrained")
    ax = fig.subplots()
    ax.scatter(sizing.duty.speed, sizing.duty.torque / count / 1e3, s=6, c=sizing.duty.t, cmap="viridis",
               label="force per cylinder along the task")
    ax.axhline(push.limit * piston / 1e3, color="tab:red", label="push limit p·A_piston")
    ax.axhline(-push.limit * annulus / 1e3, color="tab:purple", label="pull limit p·A_annulus")
    ax.set_xlabel("cylinder speed (m/s)")
    ax.set_ylabel("force (kN, + pushes)")
    ax.set_title(f"{sizing.joint}: {count}× {sizing.cylinder}" + ("" if sizing.feasible else " — NOT FEASIBLE"))
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    _save(fig, Path(path))
    return Path(path)


def write_charts(result: SizingResult, directory: str | Path) -> list[Path]:
    """One chart per joint in ``directory`` (created if needed): ``<mechanism>_<joint>.png``."""
    directory = output_directory(directory)
    out = []
    for j in result.joints:
        path = directory / f"{result.mechanism}_{j.joint}.png"
        out.append(force_speed_chart(j, path) if isinstance(j, CylinderSizing) else speed_torque_chart(j, path))
    return out
