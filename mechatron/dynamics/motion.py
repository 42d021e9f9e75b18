r"""Motions: point-to-point profiles, synchronised multi-axis moves, cycles with dwells, and trajectories in CSV.

A profile moves a scalar s from 0 to 1 (the fraction of the move); every axis follows q_i(t) = q_i0 + Δq_i s(t), so
all axes start and stop together on a straight line in joint space. The profile's limits are the tightest of the
axes' own: ṡ_max = min_i v_max,i/|Δq_i|, s̈_max = min_i a_max,i/|Δq_i|, s⃛_max = min_i j_max,i/|Δq_i|, which keeps
every axis within its limits and makes the move as short as they allow.

Profiles (distance D = 1, rest to rest):

- ``triangular``: constant acceleration a, then deceleration; T = 2√(D/a) (it ignores v_max);
- ``trapezoidal``: accelerate to v_max, cruise, decelerate; T = D/v + v/a, triangular if D < v²/a;
- ``scurve``: jerk-limited double-S with limits on velocity, acceleration and jerk (7 segments at most);
- ``quintic``: s = 10τ³ − 15τ⁴ + 6τ⁵, τ = t/T, with T = max(15D/(8v), √(10D/(√3 a))) from its peak velocity and
  acceleration.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from ..errors import InputError
from ..model.mechanism import Mechanism

PROFILES = ("triangular", "trapezoidal", "scurve", "quintic")


# ------------------------------------------------------------------------------------------------ profiles
@dataclass(frozen=True)
class Profile:
    """A rest-to-rest profile of s from 0 to 1: piecewise constant jerk (``segments`` of (duration, jerk)) with
    the acceleration allowed to jump between segments (``accelerations`` at each segment's start), or the quintic."""

    kind: str
    duration: float
    segments: tuple[tuple[float, float, float], ...] = ()  # (duration, acceleration at start, jerk)

    def evaluate(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(s, ṡ, s̈) at times t (clipped to [0, duration])."""
        t = np.clip(np.asarray(t, dtype=float), 0.0, self.duration)
        if self.kind == "quintic":
            T = self.duration
            tau = t / T
            s = 10 * tau**3 - 15 * tau**4 + 6 * tau**5
            ds = (30 * tau**2 - 60 * tau**3 + 30 * tau**4) / T
            dds = (60 * tau - 180 * tau**2 + 120 * tau**3) / T**2
            return s, ds, dds
        s, ds, dds = np.zeros_like(t), np.zeros_like(t), np.zeros_like(t)
        start, p, v = 0.0, 0.0, 0.0
        for k, (length, a0, j) in enumerate(self.segments):
            last = k == len(self.segments) - 1
            inside = (t >= start) & ((t < start + length) | last)
            tau = t[inside] - start
            s[inside] = p + v * tau + a0 * tau**2 / 2 + j * tau**3 / 6
            ds[inside] = v + a0 * tau + j * tau**2 / 2
            dds[inside] = a0 + j * tau
            p, v = p + v * length + a0 * length**2 / 2 + j * length**3 / 6, v + a0 * length + j * length**2 / 2
            start += length
        # rounding: the end of the last segment is exactly at rest at 1
        end = t >= self.duration
        s[end], ds[end], dds[end] = 1.0, 0.0, 0.0
        return s, ds, dds


def _check_limit(name: str, value: float) -> float:
    if not (value > 0 and math.isfinite(value)):
        raise InputError(f"the {name} limit of a move must be a finite number > 0, got {value!r}")
    return value


def make_profile(kind: str, vmax: float, amax: float, jmax: float | None = None, duration: float | None = None
                 ) -> Profile:
    """The shortest rest-to-rest profile of s: 0 → 1 of ``kind`` within the limits (per unit of s), or stretched to
    ``duration`` if that is longer (same shape, limits scaled down)."""
    if kind not in PROFILES:
        raise InputError(f"unknown profile {kind!r}; expected one of: {', '.join(PROFILES)}")
    _check_limit("acceleration", amax)
    if kind != "triangular":
        _check_limit("velocity", vmax)
    if kind == "quintic":
        T = max(15 / (8 * vmax), math.sqrt(10 / (math.sqrt(3) * amax)))
        return Profile("quintic", max(T, duration or 0.0))
    if kind == "triangular":
        profile = _trapezoid(math.inf, amax)
    elif kind == "trapezoidal":
        profile = _trapezoid(vmax, amax)
    else:
        profile = _double_s(vmax, amax, _check_limit("jerk", jmax if jmax is not None else math.inf))
    if duration is not None and duration > profile.duration:
        return _stretch(profile, duration)
    return profile


def _trapezoid(v: float, a: float) -> Profile:
    ta = min(v / a, math.sqrt(1.0 / a))  # accelerate until v or until half-way
    vpeak = a * ta
    cruise = max(0.0, (1.0 - vpeak * ta) / vpeak)
    kind = "trapezoidal" if cruise > 0 else "triangular"
    return Profile(kind, 2 * ta + cruise, ((ta, a, 0.0), (cruise, 0.0, 0.0), (ta, -a, 0.0)))


def _double_s(v: float, a: float, j: float) -> Profile:
    """Jerk-limited rest-to-rest profile (Biagiotti & Melchiorri, Trajectory Planning for Automatic Machines, 3.4)."""
    if not math.isfinite(j):
        return _trapezoid(v, a)
    if v * j >= a * a:  # the acceleration limit is reached
        tj, ta = a / j, a / j + v / a
    else:
        tj = math.sqrt(v / j)
        ta = 2 * tj
    tv = 1.0 / v - ta
    if tv < 0:  # the velocity limit is not reached: a shorter acceleration phase
        tv = 0.0
        tj = a / j
        ta = tj / 2 + math.sqrt((tj / 2) ** 2 + 1.0 / a)
        if ta < 2 * tj:  # nor the acceleration limit: jerk up and down only, D = 2 j tj³
            tj = (1.0 / (2 * j)) ** (1 / 3)
            ta = 2 * tj
    alim = j * tj
    middle = ta - 2 * tj
    segments = ((tj, 0.0, j), (middle, alim, 0.0), (tj, alim, -j), (tv, 0.0, 0.0),
                (tj, 0.0, -j), (middle, -alim, 0.0), (tj, -alim, j))
    return Profile("scurve", 2 * ta + tv, tuple(s for s in segments if s[0] > 0))


def _stretch(profile: Profile, duration: float) -> Profile:
    """The same shape in a longer time: time scaled by k, acceleration by 1/k², jerk by 1/k³."""
    k = duration / profile.duration
    return Profile(profile.kind, duration, tuple((d * k, a / k**2, j / k**3) for d, a, j in profile.segments))


# ------------------------------------------------------------------------------------------------ trajectories
@dataclass
class Trajectory:
    """Joint positions, velocities and accelerations over time: t (N,), q (N, nq), v (N, nv), a (N, nv)."""

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    names: list[str]

    def __len__(self) -> int:
        return len(self.t)

    def to_frame(self) -> pd.DataFrame:
        data = {"t": self.t}
        for i, name in enumerate(self.names):
            data[name] = self.q[:, i]
        for i, name in enumerate(self.names):
            data[f"qd_{name}"] = self.v[:, i]
        for i, name in enumerate(self.names):
            data[f"qdd_{name}"] = self.a[:, i]
        return pd.DataFrame(data)

    def to_csv(self, path: str | Path) -> Path:
        path = Path(path)
        try:
            self.to_frame().to_csv(path, index=False, float_format="%.12g")
        except OSError as exc:
            raise InputError(f"cannot write: {exc.strerror}", file=path) from None
        return path


def _axis_limits(mech: Mechanism | None, n: int, value, default: float, what: str) -> np.ndarray:
    if value is None:
        if what == "velocity" and mech is not None:
            limits = mech.model.velocityLimit.copy()
            limits[~np.isfinite(limits) | (limits <= 0) | (limits > 1e30)] = default
            return limits
        return np.full(n, default)
    arr = np.broadcast_to(np.asarray(value, dtype=float), (n,)).copy()
    if not np.all((arr > 0) & np.isfinite(arr)):
        raise InputError(f"the {what} limits must be finite and > 0, got {value!r}")
    return arr


def move(mech: Mechanism | None, start: Sequence[float], end: Sequence[float], *, profile: str = "trapezoidal",
         vmax=None, amax=None, jmax=None, duration: float | None = None, dt: float = 0.005,
         t0: float = 0.0) -> Trajectory:
    """A synchronised point-to-point move from ``start`` to ``end`` (rad, m).

    Args:
        vmax, amax, jmax: Per-axis limits (scalars or one per joint; rad/s, rad/s², rad/s³ or m/s…). Default
            velocity limits come from the model (1 rad/s where it has none), acceleration 5, jerk 50.
        duration: Make the move last this long if that is longer than the shortest move.
        dt: Sampling step (s); the end point is always included.
    """
    start, end = np.asarray(start, dtype=float), np.asarray(end, dtype=float)
    n = len(start)
    if end.shape != start.shape or (mech is not None and n != mech.nq):
        raise InputError(f"a move needs start and end with {mech.nq if mech else n} joint values each")
    if not (np.all(np.isfinite(start)) and np.all(np.isfinite(end))):
        raise InputError("the start and end of a move must be finite")
    names = mech.joint_names if mech is not None else [f"q{i + 1}" for i in range(n)]
    delta = end - start
    moving = np.abs(delta) > 0
    v_lim = _axis_limits(mech, n, vmax, 1.0, "velocity")
    a_lim = _axis_limits(mech, n, amax, 5.0, "acceleration")
    j_lim = _axis_limits(mech, n, jmax, 50.0, "jerk")
    if not moving.any():
        T = duration or 0.0
        t = t0 + np.arange(0.0, T + dt / 2, dt) if T > 0 else np.array([t0])
        return Trajectory(t, np.tile(start, (len(t), 1)), np.zeros((len(t), n)), np.zeros((len(t), n)), names)
    scale = np.abs(delta[moving])
    shape = make_profile(profile, float(np.min(v_lim[moving] / scale)), float(np.min(a_lim[moving] / scale)),
                         float(np.min(j_lim[moving] / scale)), duration)
    steps = max(1, int(math.ceil(shape.duration / dt)))
    local = np.linspace(0.0, shape.duration, steps + 1)
    s, ds, dds = shape.evaluate(local)
    return Trajectory(t0 + local, start + np.outer(s, delta), np.outer(ds, delta), np.outer(dds, delta), names)


def cycle(mech: Mechanism | None, waypoints: Sequence[Sequence[float]], *, dwell: float = 0.0,
          profile: str = "trapezoidal", vmax=None, amax=None, jmax=None, dt: float = 0.005) -> Trajectory:
    """Moves through ``waypoints`` one after another, resting ``dwell`` seconds at every waypoint after the first."""
    if len(waypoints) < 2:
        raise InputError("a cycle needs at least two waypoints")
    parts: list[Trajectory] = []
    t = 0.0
    for a, b in zip(waypoints[:-1], waypoints[1:]):
        m = move(mech, a, b, profile=profile, vmax=vmax, amax=amax, jmax=jmax, dt=dt, t0=t)
        parts.append(m if not parts else _drop_first(m))
        t = float(m.t[-1])
        if dwell > 0:
            rest = move(mech, b, b, duration=dwell, dt=dt, t0=t)
            parts.append(_drop_first(rest))
            t = float(rest.t[-1])
    return Trajectory(np.concatenate([p.t for p in parts]), np.vstack([p.q for p in parts]),
                      np.vstack([p.v for p in parts]), np.vstack([p.a for p in parts]), parts[0].names)


def _drop_first(trajectory: Trajectory) -> Trajectory:
    return Trajectory(trajectory.t[1:], trajectory.q[1:], trajectory.v[1:], trajectory.a[1:], trajectory.names)


def read_trajectory(path: str | Path, mech: Mechanism) -> Trajectory:
    """A trajectory CSV: columns ``t`` and one per joint (named as the joints, or q1…qn; for a closed-loop mechanism
    one per actuated coordinate), optional ``qd_<joint>``
    and ``qdd_<joint>``; missing velocities and accelerations are differentiated (second-order central
    differences, which need increasing times)."""
    path = Path(path)
    try:
        frame = pd.read_csv(path)
    except FileNotFoundError:
        raise InputError("no such file", file=path) from None
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
        raise InputError(f"not a readable CSV file: {str(exc).splitlines()[0]}", file=path) from None
    if "t" not in frame.columns:
        raise InputError("missing column", file=path, field="t")
    names = list(mech.actuated) if mech.closures else mech.joint_names  # a closed loop: its inputs
    aliases = [f"q{i + 1}" for i in range(len(names))]
    columns = names if all(n in frame.columns for n in names) else aliases
    missing = [c for c in columns if c not in frame.columns]
    if missing:
        raise InputError(f"missing joint column(s) {', '.join(missing)} (give {', '.join(names)})", file=path,
                         field=missing[0])

    def numeric(column: str) -> np.ndarray:
        values = pd.to_numeric(frame[column], errors="coerce").to_numpy(dtype=float)
        bad = np.flatnonzero(~np.isfinite(values))
        if len(bad):
            raise InputError(f"not a finite number: {frame[column].iloc[bad[0]]!r}", file=path,
                             row=int(bad[0]) + 2, field=column)
        return values

    t = numeric("t")
    if len(t) < 2:
        raise InputError("a trajectory needs at least two rows", file=path)
    steps = np.diff(t)
    if np.any(steps <= 0):
        row = int(np.flatnonzero(steps <= 0)[0]) + 3
        raise InputError("times must increase", file=path, row=row, field="t")
    q = np.column_stack([numeric(c) for c in columns])

    def derivative(values: np.ndarray) -> np.ndarray:
        return np.gradient(values, t, axis=0, edge_order=2) if len(t) > 2 else np.gradient(values, t, axis=0)

    def optional(prefix: str, fallback) -> np.ndarray:
        wanted = [f"{prefix}_{c}" for c in columns]
        if all(w in frame.columns for w in wanted):
            return np.column_stack([numeric(w) for w in wanted])
        return fallback()

    v = optional("qd", lambda: derivative(q))
    a = optional("qdd", lambda: derivative(v))
    return Trajectory(t, q, v, a, names)
