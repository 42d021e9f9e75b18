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

from ..errors import InputError, MechatronError
from ..model.mechanism import Measure, Mechanism
from .geometry import measure_values
from .loops import SINGULAR_RATIO, LoopSolver, loop_solver

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
    solver = loop_solver(mech)
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


def sweep(mech: Mechanism, inputs: Mapping[str, object] | None = None, *, samples: int = 200,
          rates: Mapping[str, object] | None = None, accelerations: Mapping[str, object] | None = None,
          frames: Sequence[str] | None = None, links: Sequence[str] | None = None,
          measures: Sequence[Measure] | None = None, guess: np.ndarray | None = None,
          progress: ProgressCallback | None = None) -> SweepResult:
    """Analyse ``mech`` along the input values ``inputs`` (name → array of N values; default :func:`default_inputs`).

    Args:
        rates: Actuated rates (m/s, rad/s), scalars or arrays of N; default ``mech.input_rates`` or 1.
        accelerations: Actuated accelerations, default 0.
        frames: Points (frames) to report (default ``mech.points``).
        links: Links (body frames) whose angle, angular velocity and acceleration to report (default: none).
        measures: Transmission angles, lever arms (default ``mech.measures``).
        guess: Start of the continuation (default the reference configuration: its assembly branch).
        progress: Called as progress(done, total) every few hundred samples.
    """
    base = loop_solver(mech)
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
    points = list(mech.points if frames is None else frames)
    links = list(links or [])
    measures = list(mech.measures if measures is None else measures)
    wanted = list(dict.fromkeys(points + [p for m in measures for p in m.points] + links))
    solver = LoopSolver(mech, extra_frames=wanted)  # evaluates the reported frames with the closures' frames
    states = solver.system.states
    nv = mech.nv

    lower, upper = solver.lower[solver.act], solver.upper[solver.act]
    out_of_range = (U < lower - 1e-12) | (U > upper + 1e-12)
    failures: dict[int, str] = {}
    for k in np.flatnonzero(out_of_range.any(axis=1)):
        j = int(np.argmax(out_of_range[k]))
        failures[int(k)] = f"{names[j]} = {U[k, j]:.6g} is outside its range [{lower[j]:.6g}, {upper[j]:.6g}]"

    # pass 1, positions: continuation from sample to sample (the only sequential part)
    system, states = solver.system, solver.system.states
    Q = np.zeros((n, nv))
    Jc = np.zeros((n, system.nrows, nv))  # closure Jacobians
    H = np.zeros((n, len(system.frame_names), 4, 4))  # placements of every evaluated frame
    Jf = np.zeros((n, len(system.frame_names), 6, nv))  # their world-aligned Jacobians
    ok = np.zeros(n, dtype=bool)
    # equal input steps allow polynomial extrapolation through the previous solutions
    steps = np.diff(U, axis=0)
    scale = np.maximum(np.abs(steps).max(axis=1), 1e-300)
    same_step = np.zeros(n, dtype=bool)  # same_step[k]: U[k] − U[k−1] equals U[k−1] − U[k−2]
    same_step[2:] = np.abs(steps[1:] - steps[:-1]).max(axis=1) <= 1e-9 * scale[1:]
    history: list[np.ndarray] = []  # last good solutions, each reached by the same step as the next
    dep, act = solver.dep, solver.act
    polish = len(dep) > 0 and system.nrows > 0
    correction = None  # an approximate J_d⁻¹, refreshed every few samples, for one cheap extra Newton step
    every = max(1, n // 100)
    for k in range(n):
        if k in failures:
            history.clear()
            continue
        if history and not same_step[k]:
            del history[:-1]  # the step changed: only the last solution is a good start
        trial = _extrapolate(history, q)
        trial[act] = U[k]
        try:
            trial, J = solver.newton(trial)
        except MechatronError as exc:
            failures[k] = str(exc)
            history.clear()
            continue
        ok[k] = True
        Q[k], Jc[k], H[k], Jf[k] = trial, J, states.homogeneous, states.jacobian
        q = trial
        if polish:  # remember q after one more (quasi-)Newton step, so that the tolerance does not build up
            if correction is None or k % 16 == 0:
                correction = np.linalg.pinv(J[:, dep])
            q = trial.copy()
            q[dep] -= correction @ solver.residual
        history.append(q)
        if len(history) > 4:
            del history[0]
        if progress is not None and (k % every == 0 or k == n - 1):
            progress(k + 1, n)

    # velocities of all samples at once: q̇ = S q̇_a with S = [I; −J_d⁻¹ J_a]
    good = np.flatnonzero(ok)
    S, singular = _velocity_maps(solver, Jc[good])
    for k in good[singular]:
        failures[int(k)] = (f"{mech.name} is at a singular position ("
                            + ", ".join(f"{name} = {U[k, j]:.6g}" for j, name in enumerate(names))
                            + "): the actuated coordinates do not determine the motion")
    good, S = good[~singular], S[~singular]
    V = np.einsum("kij,kj->ki", S, R[good])
    # pass 2: J̇ q̇ and the frames' accelerations at q̈ = 0 from Pinocchio, then q̈ of all samples at once
    drift, accel0 = _drifts(solver, Q[good], V, H[good], Jf[good])
    Aq = np.einsum("kij,kj->ki", S, A[good])
    if len(dep) and system.nrows:
        Jg = Jc[good]
        rhs = np.einsum("kij,kj->ki", Jg[:, :, act], A[good]) + drift
        Aq[:, dep] = -_batched_solve(Jg[:, :, dep], rhs)

    reported = [system.index[name] for name in wanted]
    Jw = Jf[good][:, reported]
    twist = np.einsum("kfij,kj->kfi", Jw, V)
    accel = accel0[:, reported] + np.einsum("kfij,kj->kfi", Jw, Aq)  # classical acceleration: at q̈ = 0 plus J q̈
    failure_rows = [{"sample": k, **{name: U[k, j] for j, name in enumerate(names)}, "reason": failures[k]}
                    for k in sorted(failures)]
    return _result(mech, U, good, Q[good], V, Aq, H[good][:, reported], twist, accel, wanted, points, links,
                   measures, failure_rows, names)


def _extrapolate(history: list[np.ndarray], q: np.ndarray) -> np.ndarray:
    """Starting point of Newton's method: the polynomial through the last (up to four) solutions, reached in equal
    input steps, extrapolated one more step (a cubic leaves a fourth-order error, so most samples need no Newton
    step); ``q`` when there is no history."""
    m = len(history)
    if m >= 4:
        return 4 * history[-1] - 6 * history[-2] + 4 * history[-3] - history[-4]
    if m == 3:
        return 3 * history[-1] - 3 * history[-2] + history[-3]
    if m == 2:
        return 2 * history[-1] - history[-2]
    return (history[-1] if m else q).copy()


def _batched_solve(A: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Solve A_k x_k = b_k for a stack (least squares when A_k is not square)."""
    if A.shape[1] == A.shape[2]:
        return np.linalg.solve(A, b[..., None])[..., 0]
    return np.einsum("kij,kj->ki", np.linalg.pinv(A), b)


def _velocity_maps(solver: LoopSolver, Jc: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """S_k (n × nv × n_act) for a stack of closure Jacobians, and which samples are singular."""
    n, nv, na = len(Jc), solver.mech.nv, len(solver.act)
    S = np.broadcast_to(solver.selection, (n, nv, na)).copy()
    singular = np.zeros(n, dtype=bool)
    if not (len(solver.dep) and solver.nrows) or n == 0:
        return S, singular
    Jd, Ja = Jc[:, :, solver.dep], Jc[:, :, solver.act]
    square = Jd.shape[1] == Jd.shape[2]
    with np.errstate(all="ignore"):
        try:
            inverse = np.linalg.inv(Jd) if square else np.linalg.pinv(Jd)
        except np.linalg.LinAlgError:  # some sample is exactly singular: invert one by one
            inverse = np.full((n, Jd.shape[2], Jd.shape[1]), np.inf)
            for k in range(n):
                try:
                    inverse[k] = np.linalg.inv(Jd[k])
                except np.linalg.LinAlgError:
                    pass
        singular = ~(np.abs(inverse).max(axis=(1, 2)) <= SINGULAR_RATIO)
        S[:, solver.dep] = -inverse @ Ja
    return S, singular


def _drifts(solver: LoopSolver, Q: np.ndarray, V: np.ndarray, H: np.ndarray, Jf: np.ndarray
            ) -> tuple[np.ndarray, np.ndarray]:
    """Closure drift J̇ q̇ and the frames' classical accelerations at q̈ = 0 of every sample."""
    system = solver.system
    states = system.states
    n = len(Q)
    accel0 = np.zeros((n, len(system.frame_names), 6))
    drift = np.zeros((n, system.nrows))
    for k in range(n):
        states.restore(H[k], Jf[k])
        drift[k] = system.drift(Q[k], V[k])
        accel0[k] = states.acceleration0
    return drift, accel0


def _result(mech: Mechanism, U: np.ndarray, good: np.ndarray, Q: np.ndarray, V: np.ndarray, A: np.ndarray,
            H: np.ndarray, twist: np.ndarray, accel: np.ndarray, frame_names: list[str], points: list[str],
            links: list[str], measures: list[Measure], failures: list[dict], names: list[str]) -> SweepResult:
    """The table of the samples ``good`` (their q, v, a; frame placements H, twists and accelerations)."""
    index = {name: j for j, name in enumerate(frame_names)}
    columns: dict[str, np.ndarray] = {"sample": good}
    for j, name in enumerate(names):
        columns[name] = U[good, j]
    for i, joint in enumerate(mech.joint_names):
        columns[f"q_{joint}"], columns[f"v_{joint}"], columns[f"a_{joint}"] = Q[:, i], V[:, i], A[:, i]
    position = H[:, :, :2, 3]
    for p in points:
        j = index[p]
        columns[f"{p}_x"], columns[f"{p}_y"] = position[:, j, 0], position[:, j, 1]
        columns[f"{p}_vx"], columns[f"{p}_vy"] = twist[:, j, 0], twist[:, j, 1]
        columns[f"{p}_v"] = np.hypot(twist[:, j, 0], twist[:, j, 1])
        columns[f"{p}_ax"], columns[f"{p}_ay"] = accel[:, j, 0], accel[:, j, 1]
        columns[f"{p}_a"] = np.hypot(accel[:, j, 0], accel[:, j, 1])
    for link in links:
        j = index[link]
        columns[f"{link}_angle"] = np.unwrap(np.arctan2(H[:, j, 1, 0], H[:, j, 0, 0]))
        columns[f"{link}_omega"], columns[f"{link}_epsilon"] = twist[:, j, 5], accel[:, j, 5]
    for m in measures:
        columns[m.name] = measure_values(m, {p: position[:, index[p]] for p in m.points})
    failure_columns = ["sample", *names, "reason"]
    return SweepResult(mech, pd.DataFrame(columns), pd.DataFrame(failures, columns=failure_columns), Q, V, A,
                       measures)
