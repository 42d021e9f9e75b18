r"""Motions: point-to-point profiles, synchronised multi-axis moves, cycles with dwells, and trajectories in CSV.

A profile moves a scalar s from 0 to 1 (the fraction of the move); every axis follows q_i(t) = q_i0 + Δq_i s(t), so
all axes start and stop together on a straight line in joint space. The profile's limits are the tightest of the
axes' own: ṡ_max = min_i v_max,i/|Δq_i|, s̈_max = min_i a_max,i/|Δq_i|, s⃛_max = min_i j_max,i/|Δq_i|, which keeps
every axis within its limits and makes the move as short as they allow.

Profiles (distance D = 1, rest to rest):

- ``triangular``: constant acceleration a, then deceleration; T = 2√(D/a) (it ignores v_max);
- ``trapezoidal``: accelerate to v_max, cruise, decelerate; T = D/v + v/a, triangular if D < v²/a;
- ``scurve``: jerk-limited double-S with limits on velocity, acceleration and jerk (7 segments at most,
  [Biagiotti, 3.4]);
- ``quintic``: s = 10τ³ − 15τ⁴ + 6τ⁵, τ = t/T, with T = max(15D/(8v), √(10D/(√3 a))) from its peak velocity and
  acceleration.

Joints with more than one configuration coordinate (a continuous joint's q is (cos θ, sin θ)) move in their joint
coordinates (θ, unwrapped, so a move from −170° to +170° turns through 0); every sample's configuration is
q = neutral ⊕ coordinates (:meth:`~mechatron.model.Mechanism.configuration`, ``pin.integrate``).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from ..io.budget import option
from ..io.values import LARGEST, number, numbers
from ..model.mechanism import Mechanism
from ..report.result import Result
from .series import coordinate_columns, plot_lines, stacked_axes, text_table, unit_label

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

PROFILES = ("triangular", "trapezoidal", "scurve", "quintic")

#: The smallest sampling step of a move (s).
MIN_STEP = 1e-6
#: The most samples of one move (a larger count would not fit in memory).
MAX_SAMPLES = 1e8


# ------------------------------------------------------------------------------------------------ profiles
@dataclass(frozen=True)
class Profile:
    """A rest-to-rest profile of s from 0 to 1: piecewise constant jerk (``segments`` of (duration, jerk)) with
    the acceleration allowed to jump between segments (``accelerations`` at each segment's start), or the quintic."""

    kind: str
    duration: float
    segments: tuple[tuple[float, float, float], ...] = ()  # (duration, acceleration at start, jerk)

    def evaluate(self, t: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """(s, ṡ, s̈) (1, 1/s, 1/s²) at times t (s, clipped to [0, duration])."""
        time: NDArray[np.float64] = np.clip(np.asarray(t, dtype=float), 0.0, self.duration)
        if self.kind == "quintic":
            T = self.duration
            tau = time / T
            s = 10 * tau**3 - 15 * tau**4 + 6 * tau**5
            ds = (30 * tau**2 - 60 * tau**3 + 30 * tau**4) / T
            dds = (60 * tau - 180 * tau**2 + 120 * tau**3) / T**2
            return s, ds, dds
        s, ds, dds = np.zeros_like(time), np.zeros_like(time), np.zeros_like(time)
        start, p, v = 0.0, 0.0, 0.0
        for k, (length, a0, j) in enumerate(self.segments):
            last = k == len(self.segments) - 1
            inside = (time >= start) & ((time < start + length) | last)
            tau = time[inside] - start
            s[inside] = p + v * tau + a0 * tau**2 / 2 + j * tau**3 / 6
            ds[inside] = v + a0 * tau + j * tau**2 / 2
            dds[inside] = a0 + j * tau
            p, v = p + v * length + a0 * length**2 / 2 + j * length**3 / 6, v + a0 * length + j * length**2 / 2
            start += length
        # rounding: the end of the last segment is exactly at rest at 1
        end = time >= self.duration
        s[end], ds[end], dds[end] = 1.0, 0.0, 0.0
        return s, ds, dds


def _check_limit(name: str, value: float) -> float:
    if not (value > 0 and math.isfinite(value)):
        raise InputError(f"the {name} limit of a move must be a finite number > 0, got {value!r}")
    return value


def make_profile(kind: str, vmax: float, amax: float, jmax: float | None = None, duration: float | None = None
                 ) -> Profile:
    """The shortest rest-to-rest profile of s: 0 → 1 of ``kind`` within the limits ``vmax`` (1/s), ``amax``
    (1/s²) and ``jmax`` (1/s³) of s, or stretched to ``duration`` (s) if that is longer (same shape, limits scaled
    down). Durations: see the module docstring; the double S is [Biagiotti, 3.4]."""
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
    """Jerk-limited rest-to-rest profile, the double S of [Biagiotti, 3.4]."""
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
def coordinate_names(mech: Mechanism) -> list[str]:
    """One name per joint coordinate (velocity index): the joint's name for a one-axis joint (revolute, continuous,
    prismatic), ``<joint>_1``… for a joint with more."""
    names: list[str] = []
    for j in range(1, mech.model.njoints):
        name, nv = mech.model.names[j], mech.model.joints[j].nv
        names += [name] if nv == 1 else [f"{name}_{k + 1}" for k in range(nv)]
    return names


def coordinate_limits(mech: Mechanism) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """(lower, upper) (nv,): the position limits of every joint coordinate (rad, m); ±inf for joints without them
    (continuous joints, and every coordinate of a joint with more than one)."""
    lower, upper = np.full(mech.nv, -np.inf), np.full(mech.nv, np.inf)
    for joint in mech.model.joints[1:]:
        if joint.nq == joint.nv == 1:
            lower[joint.idx_v] = mech.model.lowerPositionLimit[joint.idx_q]
            upper[joint.idx_v] = mech.model.upperPositionLimit[joint.idx_q]
    return lower, upper


@dataclass(eq=False)
class Trajectory(Result):
    """A motion of named coordinates over time.

    Attributes:
        t: Times (N,) (s).
        q: Configurations (N, nq) of a serial mechanism (Pinocchio's q: a continuous joint's (cos θ, sin θ)), or the
            actuated coordinates (N, n) of a closed loop.
        v: Velocities (N, nv or n) (rad/s, m/s).
        a: Accelerations (N, nv or n) (rad/s², m/s²).
        names: One name per coordinate (the joint coordinates, or the actuated ones of a closed loop).
        coordinates: (N, n) one value per name (rad, m): the joint angles (unwrapped) and displacements q was made
            of, q = neutral ⊕ coordinates. Default: q (one coordinate per joint).
        angular: Which coordinates are angles (for units), if known.
    """

    t: NDArray[np.float64]
    q: NDArray[np.float64]
    v: NDArray[np.float64]
    a: NDArray[np.float64]
    names: list[str]
    coordinates: NDArray[np.float64] | None = None
    angular: list[bool] | None = field(default=None, repr=False)

    def __post_init__(self) -> None:
        self.t = np.asarray(self.t, dtype=float)
        self.q, self.v, self.a = (np.atleast_2d(np.asarray(x, dtype=float)) for x in (self.q, self.v, self.a))
        self.names = list(self.names)
        if self.coordinates is None:
            self.coordinates = self.q
        self.coordinates = np.atleast_2d(np.asarray(self.coordinates, dtype=float))
        n = len(self.names)
        if not (self.coordinates.shape == self.v.shape == self.a.shape == (len(self.t), n)):
            raise InputError(f"a trajectory needs {len(self.t)} samples of {n} coordinates ({', '.join(self.names)})"
                             f" in its coordinates, velocities and accelerations; got shapes "
                             f"{self.coordinates.shape}, {self.v.shape}, {self.a.shape}")

    def __len__(self) -> int:
        return len(self.t)

    @property
    def duration(self) -> float:
        """t_end − t_start (s)."""
        return float(self.t[-1] - self.t[0])

    # -------------------------------------------------------------------------------------------- the protocol
    def to_frame(self) -> pd.DataFrame:
        """Columns t (s), ``<name>`` (rad, m), ``qd_<name>`` (rad/s, m/s), ``qdd_<name>`` (rad/s², m/s²): the
        trajectory file format (:func:`read_trajectory`)."""
        import pandas as pd

        assert self.coordinates is not None  # set by __post_init__
        return pd.DataFrame(coordinate_columns(self.t, self.names, self.coordinates, self.v, self.a))

    def _rows(self) -> list[dict]:
        assert self.coordinates is not None  # set by __post_init__
        return [{"coordinate": name, "start": float(self.coordinates[0, i]), "end": float(self.coordinates[-1, i]),
                 "peak_speed": float(np.abs(self.v[:, i]).max()),
                 "peak_acceleration": float(np.abs(self.a[:, i]).max())} for i, name in enumerate(self.names)]

    def as_dict(self) -> dict:
        """duration (s), samples, and per coordinate its start and end (rad, m), peak speed and acceleration."""
        return {"duration": self.duration, "samples": len(self), "coordinates": self._rows()}

    def plot(self, ax: Axes | None = None) -> Figure:
        """Positions, speeds and accelerations against time (``ax``: the positions only)."""
        assert self.coordinates is not None  # set by __post_init__
        figure, axes = stacked_axes(ax, 3)
        series = (("position", self.coordinates), ("speed", self.v), ("acceleration", self.a))
        for k, (axis, (what, values)) in enumerate(zip(axes, series)):
            plot_lines(axis, self.t, values, self.names, "t (s)", unit_label(what, self.angular, k))
        axes[0].set_title("trajectory", fontsize=10)
        return figure

    def __str__(self) -> str:
        return (f"trajectory of {', '.join(self.names)}: {self.duration:.4g} s, {len(self)} samples "
                "(rad and rad/s for angles, m and m/s for lengths)\n" + text_table(self._rows()))

    def to_csv(self, path: str | Path) -> Path:
        """Write the trajectory file (:meth:`to_frame`, 12 significant digits so that it reads back as it was),
        whole or not at all."""
        from ..io.output import write_atomically

        frame = self.to_frame()
        return write_atomically(path, lambda fh: frame.to_csv(fh, index=False, float_format="%.12g"))


_UNITS = {"velocity": "rad/s or m/s", "acceleration": "rad/s² or m/s²", "jerk": "rad/s³ or m/s³"}


def _axis_limits(mech: Mechanism | None, n: int, value: ArrayLike | None, default: float, what: str,
                 name: str = "") -> np.ndarray:
    if value is None:
        if what == "velocity" and mech is not None:
            limits = mech.model.velocityLimit.copy()
            limits[~np.isfinite(limits) | (limits <= 0) | (limits > 1e30)] = default
            return limits
        return np.full(n, default)
    arr = numbers(name or what, value, positive=True, unit=_UNITS[what])
    if arr.ndim > 1 or arr.size not in (1, n):
        raise InputError(f"{name or what} must be one number or {n} (one per coordinate), got shape {arr.shape}")
    return np.broadcast_to(arr.reshape(-1), (n,)).copy()


def _sample_count(duration: float, dt: float, what: str, fix: str = "raise dt or shorten it") -> int:
    """⌈duration/dt⌉, or an InputError when that many samples (at most :data:`MAX_SAMPLES`) cannot be held."""
    steps = duration / dt
    if not steps <= MAX_SAMPLES:
        raise InputError(f"{what} of {duration:.6g} s sampled every dt = {dt:g} s needs {steps:.3g} samples, more "
                         f"than {MAX_SAMPLES:.0e}: {fix}")
    return int(math.ceil(steps))


def _names(mech: Mechanism | None, n: int) -> tuple[list[str], list[bool] | None]:
    if mech is None:
        return [f"q{i + 1}" for i in range(n)], None
    return coordinate_names(mech), [bool(x) for x in mech.angular_coordinates()]


def move(mech: Mechanism | None, start: ArrayLike, end: ArrayLike, *, profile: str = "trapezoidal",
         vmax: ArrayLike | None = None, amax: ArrayLike | None = None, jmax: ArrayLike | None = None,
         duration: float | None = None, dt: float = 0.005, t0: float = 0.0, budget: bool = True) -> Trajectory:
    """A synchronised point-to-point move from ``start`` to ``end``: one coordinate per joint (rad, m; a continuous
    joint's angle, unwrapped), each following c_i(t) = start_i + (end_i − start_i)·s(t) for the profile s of the
    module docstring; the configurations are q = neutral ⊕ c (``mech.configuration``).

    Args:
        mech: The mechanism (``None``: plain coordinates, as for the actuated inputs of a closed loop).
        vmax, amax, jmax: Per-axis limits (scalars or one per coordinate; rad/s, rad/s², rad/s³ or m/s…). Default
            velocity limits come from the model (1 rad/s where it has none), acceleration 5, jerk 50.
        duration: Make the move last this long (s) if that is longer than the shortest move.
        dt: Sampling step (s); the end point is always included.
        t0: Time of the first sample (s).
        budget: Refuse a move whose samples would not fit in memory (:mod:`mechatron.io.budget`).
    """
    start = numbers("start", start, minimum=-LARGEST, unit="rad or m")
    end = numbers("end", end, minimum=-LARGEST, unit="rad or m")
    n = len(start) if start.ndim == 1 else 0
    if start.ndim != 1 or end.shape != start.shape or (mech is not None and n != mech.nv):
        raise InputError(f"a move needs start and end with {mech.nv if mech else n} joint coordinates each")
    dt = number(option("dt"), dt, minimum=MIN_STEP, unit="s")
    t0 = number("t0", t0, minimum=-LARGEST, unit="s")
    duration = number("duration", duration, minimum=0.0, unit="s", allow_none=True)
    names, angular = _names(mech, n)
    delta = end - start
    shape = _shape(mech, start, end, profile, vmax, amax, jmax, duration)
    if budget:
        _sample_budget(dt, _samples(shape, duration, dt), n, "a shorter or faster move (vmax, amax, jmax)")
    if shape is None:
        T = duration or 0.0
        _sample_count(T, dt, "a rest", "raise dt or shorten the rest (dwell)")
        t = t0 + np.arange(0.0, T + dt / 2, dt) if T > 0 else np.array([t0])
        s, ds, dds = np.zeros(len(t)), np.zeros(len(t)), np.zeros(len(t))
    else:
        steps = max(1, _sample_count(shape.duration, dt, "a move", "raise dt or the limits vmax, amax, jmax"))
        local = np.linspace(0.0, shape.duration, steps + 1)
        s, ds, dds = shape.evaluate(local)
        t = t0 + local
    coordinates = start + np.outer(s, delta)
    q = mech.configuration(coordinates) if mech is not None else coordinates
    return Trajectory(t, q, np.outer(ds, delta), np.outer(dds, delta), names, coordinates, angular)


def _shape(mech: Mechanism | None, start: NDArray[np.float64], end: NDArray[np.float64], profile: str,
           vmax: ArrayLike | None, amax: ArrayLike | None, jmax: ArrayLike | None, duration: float | None
           ) -> Profile | None:
    """The profile of a move from ``start`` to ``end`` (None when nothing moves)."""
    n = len(start)
    delta = end - start
    moving = np.abs(delta) > 0
    if not moving.any():
        return None
    v_lim = _axis_limits(mech, n, vmax, 1.0, "velocity", "vmax")
    a_lim = _axis_limits(mech, n, amax, 5.0, "acceleration", "amax")
    j_lim = _axis_limits(mech, n, jmax, 50.0, "jerk", "jmax")
    scale = np.abs(delta[moving])
    return make_profile(profile, float(np.min(v_lim[moving] / scale)), float(np.min(a_lim[moving] / scale)),
                        float(np.min(j_lim[moving] / scale)), duration)


def _samples(shape: Profile | None, duration: float | None, dt: float) -> float:
    """The samples of a move of ``shape`` (or a rest of ``duration``) at the step ``dt`` (a float: it may be huge)."""
    T = shape.duration if shape is not None else (duration or 0.0)
    return max(1.0, math.ceil(T / dt)) + 1.0 if T > 0 else 1.0


#: Bytes a sample of a trajectory of n coordinates takes while it is built (t, the profile, q, q̇, q̈, the
#: coordinates, with the copies of :func:`cycle`): 8 · (8 + 8 n), measured with tracemalloc (tests/test_bounded.py).
def trajectory_bytes(n: int) -> float:
    """Bytes per sample of a trajectory of ``n`` coordinates while it is built (an upper bound)."""
    return 8.0 * (8 + 8 * n)


def _sample_budget(dt: float, samples: float, n: int, shorter: str, name: str = "dt") -> None:
    """Refuse (:func:`mechatron.io.budget.samples`) a trajectory of ``samples`` samples at the step ``dt``."""
    from ..io.budget import samples as within_budget

    larger = "{name}" if " " not in name else "dt"  # a file's field: "dt"
    within_budget(name, dt, samples, trajectory_bytes(n), advice=f"use a larger {larger} or {shorter}")


def cycle(mech: Mechanism | None, waypoints: Sequence[ArrayLike], *, dwell: float = 0.0,
          profile: str = "trapezoidal", vmax: ArrayLike | None = None, amax: ArrayLike | None = None,
          jmax: ArrayLike | None = None, dt: float = 0.005, dt_name: str = "dt", dwell_name: str = "dwell"
          ) -> Trajectory:
    """Moves (:func:`move`) through ``waypoints`` (one coordinate per joint each: rad, m) one after another,
    resting ``dwell`` seconds at every waypoint after the first. ``dt_name`` and ``dwell_name`` name ``dt`` and
    ``dwell`` in a refusal (:mod:`mechatron.io.budget`: ``dt``, ``--dt`` on the command line, or a file's field);
    the refusal names the dwell where the rests make most of the samples."""
    if len(waypoints) < 2:
        raise InputError("a cycle needs at least two waypoints")
    dwell = number(option(dwell_name), dwell, minimum=0.0, unit="s")
    dt = number(option(dt_name), dt, minimum=MIN_STEP, unit="s")
    points = [np.asarray(w, dtype=float) for w in waypoints]
    if all(p.ndim == 1 and p.shape == points[0].shape and np.all(np.isfinite(p)) for p in points):
        # the whole cycle's samples, before any is made
        moves = sum(_samples(_shape(mech, a, b, profile, vmax, amax, jmax, None), None, dt)
                    for a, b in zip(points[:-1], points[1:]))
        rests = (len(points) - 1) * _samples(None, dwell, dt) if dwell > 0 else 0.0
        if rests > moves:  # the dwells make most of the samples: name them first
            from ..io.budget import count, require

            shorter = option(dwell_name) if " " not in dwell_name else "dwell"
            larger = option(dt_name) if " " not in dt_name else "dt"
            require(f"{option(dwell_name)} {dwell:g} at {larger} {dt:g} gives {count(moves + rests)} samples",
                    moves + rests, trajectory_bytes(len(points[0])),
                    advice=f"use a shorter {shorter} (the dwells make most of the samples) or a larger {larger}")
        limits = ", ".join(option(k) for k in ("vmax", "amax", "jmax"))
        shorter = f"shorter or faster moves ({limits})" + (" and dwells" if dwell > 0 else "")
        _sample_budget(dt, moves + rests, len(points[0]), shorter, dt_name)
    parts: list[Trajectory] = []
    t = 0.0
    for a, b in zip(waypoints[:-1], waypoints[1:]):
        m = move(mech, a, b, profile=profile, vmax=vmax, amax=amax, jmax=jmax, dt=dt, t0=t, budget=False)
        parts.append(m if not parts else _drop_first(m))
        t = float(m.t[-1])
        if dwell > 0:
            rest = move(mech, b, b, duration=dwell, dt=dt, t0=t, budget=False)
            parts.append(_drop_first(rest))
            t = float(rest.t[-1])
    t_all, q_all, v_all, a_all = (np.concatenate([getattr(p, k) for p in parts]) for k in ("t", "q", "v", "a"))
    return Trajectory(t_all, q_all, v_all, a_all, parts[0].names, np.concatenate([p.coordinates for p in parts]),
                      parts[0].angular)


def _drop_first(trajectory: Trajectory) -> Trajectory:
    assert trajectory.coordinates is not None  # set by __post_init__
    return Trajectory(trajectory.t[1:], trajectory.q[1:], trajectory.v[1:], trajectory.a[1:], trajectory.names,
                      trajectory.coordinates[1:], trajectory.angular)


def input_ranges(mech: Mechanism, names: Sequence[str]) -> tuple[np.ndarray, np.ndarray]:
    """(lower, upper) limits (rad, m) of the closed loop's input coordinates ``names`` (its cylinders' strokes, its
    cranks' ranges); ±inf where a coordinate has none."""
    from ..kinematics.loops import loop_solver

    solver = loop_solver(mech)
    index = [solver.index[n] for n in names]
    return (np.asarray(mech.model.lowerPositionLimit, dtype=float)[index],
            np.asarray(mech.model.upperPositionLimit, dtype=float)[index])


def check_input_ranges(mech: Mechanism, names: Sequence[str], values: np.ndarray, *, file: str | Path,
                       rows: Sequence[int | str], fields: Sequence[str], labels: Sequence[str] | None = None) -> None:
    """Every row of ``values`` (rows × inputs, rad or m) of a closed loop inside its inputs' ranges (strokes), else an
    :class:`InputError` naming ``file``, the row (``rows[i]``: a line number, or a name like ``waypoints[2]``) and the
    field ``fields[j]`` (and the row's label, ``labels[i]``, if given: a pose's)."""
    if not mech.closures or not len(values):
        return
    lower, upper = input_ranges(mech, names)
    margin = 1e-9 * np.maximum(1.0, np.abs(upper - lower))
    bad = (values < lower - margin) | (values > upper + margin)
    if bad.any():
        i, j = (int(x) for x in np.argwhere(bad)[0])
        unit = "rad" if mech.joint_kind(names[j]) == "revolute" else "m"
        what = "stroke" if unit == "m" else "range"
        row = rows[i]
        label = f"pose {labels[i]}: " if labels is not None else ""
        raise InputError(f"{label}{names[j]} = {values[i, j]:.6g} {unit} is outside its {what} [{lower[j]:.6g}, "
                         f"{upper[j]:.6g}] {unit} in {mech.name}", file=file,
                         row=row if isinstance(row, int) else None,
                         field=fields[j] if isinstance(row, int) else f"{row}")


def warn_limits(mech: Mechanism, trajectory: Trajectory, what: str = "the motion") -> list[str]:
    """Warn (:class:`~mechatron.errors.LimitWarning`, one line per joint: its farthest value, when, and how many
    samples more) about the joint coordinates of a serial ``trajectory`` outside their joint limits. Returns the
    messages. (A closed loop's actuated inputs outside their range are an error where the loops are solved.)"""
    def labels(k: int) -> str:
        return f"t = {trajectory.t[k]:g} s"

    return [] if mech.closures else mech.warn_limits(trajectory.q, what, labels)


def read_trajectory(path: str | Path, mech: Mechanism) -> Trajectory:
    """A trajectory CSV: columns ``t`` (s) and one per joint coordinate (named as the joints, or q1…qn; rad, m — a
    continuous joint's angle; for a closed-loop mechanism one per actuated coordinate), optional ``qd_<name>``
    (rad/s, m/s) and ``qdd_<name>`` (rad/s², m/s²); missing velocities and accelerations are differentiated
    (second-order central differences, which need increasing times). The configurations are q = neutral ⊕ the
    coordinates (``mech.configuration``). Lines starting with ``#`` are comments."""
    from ..io.tables import numbers, read_csv

    path = Path(path)
    frame = read_csv(path, allow_empty=True)
    if "t" not in frame.columns:
        raise InputError("missing column", file=path, field="t")
    angular: list[bool] | None
    if mech.closures:  # a closed loop: its inputs
        names = list(mech.actuated)
        angular = [mech.joint_kind(n) == "revolute" for n in names]
    else:
        names, angular = _names(mech, mech.nv)
    aliases = [f"q{i + 1}" for i in range(len(names))]
    columns = names if all(n in frame.columns for n in names) else aliases
    missing = [c for c in columns if c not in frame.columns]
    if missing:
        raise InputError(f"missing joint column(s) {', '.join(missing)} (give {', '.join(names)})", file=path,
                         field=missing[0])

    def numeric(column: str) -> np.ndarray:
        return np.array(numbers(frame, column, file=path))

    t = numeric("t")
    if len(t) < 2:
        raise InputError("a trajectory needs at least two rows", file=path)
    steps = np.diff(t)
    if np.any(steps <= 0):
        row = int(frame.index[int(np.flatnonzero(steps <= 0)[0]) + 1])
        raise InputError("times must increase", file=path, row=row, field="t")
    coordinates = np.column_stack([numeric(c) for c in columns])
    check_input_ranges(mech, names, coordinates, file=path, rows=[int(n) for n in frame.index], fields=columns)

    def derivative(values: np.ndarray) -> np.ndarray:
        return np.gradient(values, t, axis=0, edge_order=2) if len(t) > 2 else np.gradient(values, t, axis=0)

    def optional(prefix: str, fallback) -> np.ndarray:
        wanted = [f"{prefix}_{c}" for c in columns]
        if all(w in frame.columns for w in wanted):
            return np.column_stack([numeric(w) for w in wanted])
        return fallback()

    v = optional("qd", lambda: derivative(coordinates))
    a = optional("qdd", lambda: derivative(v))
    q = coordinates if mech.closures else mech.configuration(coordinates)
    return Trajectory(t, q, v, a, names, coordinates, angular)
