"""Analysis of a mechanism over the strokes of its inputs: N samples into a table (pandas), with the assembly branch
kept by continuation from sample to sample.

Each sample is assembled by Newton's method from a first-order prediction q_{k-1} + S_{k-1} (u_k − u_{k-1}) (S the
velocity map of the previous sample), then analysed for velocities and accelerations. A sample that cannot be
assembled (cylinder out of stroke, a loop that cannot close, a singular position) goes to ``failures`` with the
reason instead of into the table; the sweep goes on from the last good sample.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from .errors import InputError, MechatronError
from .linkages import LoopSolver
from .model import Measure, Mechanism

ProgressCallback = Callable[[int, int], None]


@dataclass
class SweepResult:
    """Results of :func:`sweep`.

    Attributes:
        table: One row per assembled sample: the inputs, every joint coordinate ``q_*``, velocity ``v_*`` and
            acceleration ``a_*``, each point's ``{P}_x, _y, _vx, _vy, _v, _ax, _ay, _a``, each link's
            ``{L}_angle, _omega, _epsilon`` and each measure (SI units: m, rad, s).
        failures: One row per sample that could not be analysed: its index, inputs and the reason.
        q, v, a: Joint coordinates, velocities and accelerations of the table's rows, (n, nv) arrays.
    """

    mechanism: Mechanism
    table: pd.DataFrame
    failures: pd.DataFrame
    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    measures: list[Measure] = field(default_factory=list)

    def to_csv(self, path: str | Path) -> list[Path]:
        """Write the table (and, if any, the failures next to it as ``*.failures.csv``); return the files."""
        path = Path(path)
        try:
            self.table.to_csv(path, index=False, float_format="%.10g")
            written = [path]
            if len(self.failures):
                other = path.with_name(path.stem + ".failures.csv")
                self.failures.to_csv(other, index=False)
                written.append(other)
        except OSError as exc:
            raise InputError(f"cannot write: {exc.strerror}", file=path) from None
        return written

    def check_measures(self) -> list[dict]:
        """Each measure's minimum over the sweep against its required minimum (if any)."""
        out = []
        for m in self.measures:
            values = self.table[m.name].to_numpy()
            worst = float(values.min()) if len(values) else math.nan
            out.append({"name": m.name, "kind": m.kind, "min": worst,
                        "max": float(values.max()) if len(values) else math.nan,
                        "required_min": m.minimum, "pass": None if m.minimum is None else bool(worst >= m.minimum)})
        return out


def default_inputs(mech: Mechanism, samples: int) -> dict[str, np.ndarray]:
    """Every actuated coordinate from its lower to its upper limit together (a full turn from the reference angle
    for an unlimited revolute input)."""
    lower, upper = mech.model.lowerPositionLimit, mech.model.upperPositionLimit
    solver = mech.loop_solver()
    out = {}
    for name in mech.actuated:
        i = solver.index[name]
        if np.isfinite(lower[i]) and np.isfinite(upper[i]):
            out[name] = np.linspace(lower[i], upper[i], samples)
        else:
            start = mech.reference_q[i] if mech.reference_q is not None else 0.0
            out[name] = start + np.linspace(0.0, 2 * math.pi, samples)
    return out


def _as_arrays(values: Mapping[str, object] | None, names: Sequence[str], n: int, default: Callable[[str], float],
               what: str) -> np.ndarray:
    out = np.empty((n, len(names)))
    values = dict(values or {})
    for j, name in enumerate(names):
        value = values.pop(name, None)
        out[:, j] = default(name) if value is None else np.broadcast_to(np.asarray(value, dtype=float), (n,))
    if values:
        raise InputError(f"{what}: {', '.join(values)} not actuated coordinates (actuated: {', '.join(names)})")
    if not np.all(np.isfinite(out)):
        raise InputError(f"{what} must be finite")
    return out


def _measure_value(measure: Measure, position: Callable[[str], np.ndarray]) -> float:
    p = [position(name) for name in measure.points]
    if measure.kind == "transmission_angle":
        u, w = p[1] - p[0], p[3] - p[2]
        return math.acos(min(1.0, abs(u @ w) / (np.linalg.norm(u) * np.linalg.norm(w))))
    if measure.kind == "lever_arm":
        axis, r = p[1] - p[0], p[2] - p[0]
        return abs(axis[0] * r[1] - axis[1] * r[0]) / np.linalg.norm(axis)
    if measure.kind == "distance":
        return float(np.linalg.norm(p[1] - p[0]))
    raise InputError(f"unknown measure kind {measure.kind!r}")


def sweep(mech: Mechanism, inputs: Mapping[str, object] | None = None, *, samples: int = 200,
          rates: Mapping[str, object] | None = None, accelerations: Mapping[str, object] | None = None,
          points: Sequence[str] | None = None, links: Sequence[str] | None = None,
          measures: Sequence[Measure] | None = None, guess: np.ndarray | None = None,
          progress: ProgressCallback | None = None) -> SweepResult:
    """Analyse ``mech`` along the input values ``inputs`` (name → array of N values; default :func:`default_inputs`).

    Args:
        rates: Actuated rates (m/s, rad/s), scalars or arrays of N; default ``mech.input_rates`` or 1.
        accelerations: Actuated accelerations, default 0.
        points: Points to report (default ``mech.points`` without the helper frames of cylinders).
        links: Links (body frames) whose angle, angular velocity and acceleration to report (default: none).
        measures: Transmission angles, lever arms (default ``mech.measures``).
        guess: Start of the continuation (default the reference configuration: its assembly branch).
        progress: Called as progress(done, total) every few hundred samples.
    """
    base = mech.loop_solver()
    inputs = dict(inputs) if inputs is not None else default_inputs(mech, samples)
    lengths = {len(np.atleast_1d(np.asarray(v))) for v in inputs.values()}
    if len(lengths) != 1:
        raise InputError("every swept input needs the same number of samples")
    n = lengths.pop()
    names = list(mech.actuated)
    q = np.array(mech.reference_q if guess is None else guess, dtype=float)
    held = {name: q[base.index[name]] for name in names}
    U = _as_arrays(inputs, names, n, lambda name: held[name], "inputs")
    R = _as_arrays(rates, names, n, lambda name: mech.input_rates.get(name, 1.0), "rates")
    A = _as_arrays(accelerations, names, n, lambda name: 0.0, "accelerations")
    points = list(mech.points if points is None else points)
    links = list(links or [])
    measures = list(mech.measures if measures is None else measures)
    wanted = list(dict.fromkeys(points + [p for m in measures for p in m.points] + links))
    solver = LoopSolver(mech, extra_frames=wanted)  # evaluates the reported frames with the closures' frames
    states = solver.system.states
    frames = [solver.system.index[name] for name in wanted]
    nf, nv = len(frames), mech.nv

    ok = np.zeros(n, dtype=bool)
    Qs, Vs, As = np.zeros((n, nv)), np.zeros((n, nv)), np.zeros((n, nv))
    position = np.zeros((n, nf, 2))
    angle = np.zeros((n, nf))
    twist = np.zeros((n, nf, 6))  # world-aligned frame velocities [v; ω]
    accel = np.zeros((n, nf, 6))  # classical linear and angular accelerations
    failures = []
    history: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []  # (u, q, S) of the last two good samples
    step = max(1, n // 100)
    lower, upper = solver.lower[solver.act], solver.upper[solver.act]
    for k in range(n):
        u = U[k]
        try:
            outside = (u < lower - 1e-12) | (u > upper + 1e-12)
            if outside.any():
                bad = int(np.argmax(outside))
                raise MechatronError(f"{names[bad]} = {u[bad]:.6g} is outside its range "
                                     f"[{lower[bad]:.6g}, {upper[bad]:.6g}]")
            trial = _predict(q, u, history)
            trial[solver.act] = u
            trial, J = solver.newton(trial)
            S, v, a = solver.analyse(trial, J, R[k], A[k])
        except MechatronError as exc:
            failures.append({"sample": k, **{name: u[j] for j, name in enumerate(names)}, "reason": str(exc)})
            history.clear()
            continue
        q = trial
        # Remember q with one more Newton correction (free: J_d⁻¹ is known) so that the closure tolerance left in
        # each accepted sample does not build up through the extrapolation.
        polished = q.copy()
        if len(solver.dep) and solver.nrows:
            polished[solver.dep] -= solver.inverse @ solver.residual
        history = [history[-1], (u, polished, S)] if history else [(u, polished, S)]
        ok[k] = True
        Qs[k], Vs[k], As[k] = q, v, a
        position[k] = states.position[frames, :2]
        angle[k] = states.angle[frames]
        twist[k] = states.velocity[frames]
        # classical acceleration = its value at q̈ = 0 plus J q̈
        accel[k] = states.acceleration0[frames] + states.jacobian[frames] @ a
        if progress is not None and (k % step == 0 or k == n - 1):
            progress(k + 1, n)

    return _result(mech, U, ok, Qs, Vs, As, position, angle, twist, accel, wanted, points, links, measures,
                   failures, names)


def _predict(q: np.ndarray, u: np.ndarray, history: list[tuple[np.ndarray, np.ndarray, np.ndarray]]) -> np.ndarray:
    """Starting point of Newton's method for the inputs u.

    With one previous solution (u1, q1, S1): q1 + S1 (u − u1). With two, on a straight input path: the cubic Hermite
    curve through (q0, S0) at u0 and (q1, S1) at u1, extrapolated to u, so the predicted closure residual is of
    fourth order in the step and most samples need no Newton step at all.
    """
    if not history:
        return q.copy()
    u1, q1, S1 = history[-1]
    delta = u - u1
    if len(history) == 2:
        u0, q0, S0 = history[0]
        step = u1 - u0
        r = float(delta @ step) / float(step @ step)
        if np.abs(delta - r * step).max() <= 1e-12 * (1 + abs(r)) * np.abs(step).max():
            s = 1.0 + r  # Hermite parameter: 0 at u0, 1 at u1
            s2, s3 = s * s, s * s * s
            return ((2 * s3 - 3 * s2 + 1) * q0 + (s3 - 2 * s2 + s) * (S0 @ step)
                    + (3 * s2 - 2 * s3) * q1 + (s3 - s2) * (S1 @ step))
    return q1 + S1 @ delta


def _result(mech, U, ok, Qs, Vs, As, position, angle, twist, accel, frame_names, points, links, measures, failures,
            names) -> SweepResult:
    index = {name: j for j, name in enumerate(frame_names)}
    columns: dict[str, np.ndarray] = {"sample": np.flatnonzero(ok)}
    for j, name in enumerate(names):
        columns[name] = U[ok, j]
    for i, joint in enumerate(mech.joint_names):
        columns[f"q_{joint}"] = Qs[ok, i]
        columns[f"v_{joint}"] = Vs[ok, i]
        columns[f"a_{joint}"] = As[ok, i]
    for p in points:
        j = index[p]
        columns[f"{p}_x"], columns[f"{p}_y"] = position[ok, j, 0], position[ok, j, 1]
        columns[f"{p}_vx"], columns[f"{p}_vy"] = twist[ok, j, 0], twist[ok, j, 1]
        columns[f"{p}_v"] = np.hypot(twist[ok, j, 0], twist[ok, j, 1])
        columns[f"{p}_ax"], columns[f"{p}_ay"] = accel[ok, j, 0], accel[ok, j, 1]
        columns[f"{p}_a"] = np.hypot(accel[ok, j, 0], accel[ok, j, 1])
    for link in links:
        j = index[link]
        columns[f"{link}_angle"] = np.unwrap(angle[ok, j])
        columns[f"{link}_omega"], columns[f"{link}_epsilon"] = twist[ok, j, 5], accel[ok, j, 5]
    positions = position[ok]
    for m in measures:
        columns[m.name] = np.array([_measure_value(m, lambda p, row=row: row[index[p]]) for row in positions])
    failure_columns = ["sample", *names, "reason"]
    return SweepResult(mech, pd.DataFrame(columns), pd.DataFrame(failures, columns=failure_columns),
                       Qs[ok], Vs[ok], As[ok], measures)
