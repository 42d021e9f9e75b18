r"""Kinematic calibration: the geometric parameters of a built machine identified from measured tool poses.

The unknowns x are changes from the nominal model: Δl of named geometric parameters (DH a, d, α, θ; URDF origins;
linkage lengths and pin coordinates) and encoder offsets δq of coordinates (a joint's name or ``qk``, as in a
tolerances file: the model's coordinate is the reading plus the offset, q = q_read + δq). Each measured row i
(:class:`~mechatron.accuracy.measurements.Measurements`) gives the residuals

    r_p,i = (p(l + Δl, q_read,i + δq) − p_meas,i) / σ_i ,    r_R,i = log(R(l + Δl, q_read,i + δq) R_meas,iᵀ) / σ_rot,i

(m/m; rad/rad, the orientation only where measured), and x minimises ½ Σ r² by Levenberg–Marquardt [Moré 1978]
on the exact Jacobian: ∂p/∂x and the rotation's ω from :func:`~mechatron.accuracy.sensitivity.pose_sensitivities`
(∂r_R/∂x = J_log(E) Eᵀ ω with E = R R_measᵀ and J_log Pinocchio's ``Jlog3``), the mechanism rebuilt with the new
parameters at every iterate (``Mechanism.with_parameters``; a closed loop re-assembled at each measured input).

Steps: with the columns scaled by their norms D (Moré's scaling: metres and radians made comparable), the scaled
Jacobian's SVD U S Vᵀ gives the damped step z = −V S (S² + λ s₁²)⁻¹ Uᵀ r over the singular values above
``rcond``·s₁ (the minimum-norm step where some are not), λ lowered tenfold after a step that lowers the cost and
raised tenfold after one that does not; it stops when the scaled step is below ``xtol`` relative to x or the cost
changes by less than :data:`FTOL` of itself (as MINPACK's ``ftol``).

Identifiability [Hollerbach & Wampler 1996]: the rank of the scaled Jacobian (singular values above ``rcond``·s₁)
and its condition number s₁/s_n (infinite when the rank is short). A singular vector below the threshold is a
combination of unknowns that moves no measured pose: the unknowns with a component of at least 0.1 in that
near-null space (P_kk ≥ 0.01 of its projector P = V₀V₀ᵀ), in sets linked by |P_ij| ≥ 0.01, cannot be told apart
(theta1 and q1 of a DH arm, which add; d2 and d3 where z1 ∥ z2). :func:`calibrate` refuses them, naming them,
unless ``allow_unidentifiable``: then the step is the minimum-norm one (each unidentifiable combination left at its
nominal) and those unknowns have no standard error.

Standard errors: Cov(x) = σ̂² (JᵀJ)⁻¹ with σ̂² = RSS/(m − n) (m residuals, n identifiable unknowns, the row weights
relative), the square roots of its diagonal.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pinocchio as pin
from numpy.typing import NDArray

from ..errors import InputError, SingularityError, UnreachableError
from ..io.values import number
from ..model.mechanism import Mechanism, unknown_name_error
from .calibration_result import CalibrationResult, Identifiability, Unknown
from .measurements import Measurements, read_measurements
from .sensitivity import coordinate_names, pose_sensitivities, resolve_coordinate

Floats = NDArray[np.float64]

#: Singular values of the scaled Jacobian below RCOND·s₁ are taken as zero (unidentifiable combinations).
RCOND = 1e-9
#: Relative change of the cost Σr² below which a step has converged (as MINPACK's ftol): the cost is computed to about
#: 1e-12 of itself (positions of 1 m to 1e-16 m over σ of 20 µm), so a smaller change is rounding; it moves the
#: unknowns by ~1e-5 of their standard errors.
FTOL = 1e-10
#: A component of a near-null singular vector at least this large names the unknown as one that cannot be told apart.
NULL_COMPONENT = 0.1


@dataclass
class CalibrationProblem:
    """The least-squares problem of a calibration: ``mech`` (nominal), the ``measurements``, the ``parameters``
    and the coordinates with ``offsets`` to identify, the measured ``frame``. x = (Δl, δq) (m, rad)."""

    mech: Mechanism
    measurements: Measurements
    parameters: tuple[str, ...]
    offsets: tuple[str, ...]
    frame: str
    _q: Floats | None = field(default=None, repr=False)

    @property
    def names(self) -> tuple[str, ...]:
        return self.parameters + self.offsets

    @property
    def size(self) -> int:
        """m, the number of residuals (3 per row, 6 with orientations)."""
        return len(self.measurements) * (6 if self.measurements.rotations is not None else 3)

    def mechanism(self, x: Floats) -> Mechanism:
        """The mechanism with the parameter changes of ``x``."""
        nominal = self.mech.parameter_values()
        changes = {name: nominal[name] + float(dx) for name, dx in zip(self.parameters, x)}
        return self.mech.with_parameters(changes) if changes else self.mech

    def configurations(self, x: Floats) -> Floats:
        """The configurations q (N, nq) of the measured rows with the unknowns ``x``."""
        return self._configurations(self.mechanism(x), x)

    def _configurations(self, mech: Mechanism, x: Floats) -> Floats:
        from .study import configurations

        coordinates = self.measurements.coordinates.copy()
        names = coordinate_names(self.mech)
        for name, dq in zip(self.offsets, x[len(self.parameters):]):
            coordinates[:, names.index(name)] += dq
        try:
            return configurations(mech, coordinates, self.measurements.labels)
        except InputError as exc:
            raise InputError(f"{exc.message} (with the parameters of this iterate)", file=self.measurements.file
                             ) from None

    def evaluate(self, x: Floats) -> tuple[Floats, Floats, Floats]:
        """(weighted residuals r (m,), their Jacobian ∂r/∂x (m, n), raw errors (N, 6): position error (m) and
        rotation vector of R R_measᵀ (rad, zero where not measured)) at ``x``."""
        r, J, raw = self._evaluate(x, True)
        assert J is not None
        return r, J, raw

    def residuals(self, x: Floats) -> tuple[Floats, Floats]:
        """(weighted residuals r (m,), raw errors (N, 6)) at ``x``, without the Jacobian."""
        r, _, raw = self._evaluate(x, False)
        return r, raw

    def _evaluate(self, x: Floats, jacobian: bool) -> tuple[Floats, Floats | None, Floats]:
        mech = self.mechanism(x)
        Q = self._configurations(mech, x)
        meas = self.measurements
        if jacobian:
            twists, placements = pose_sensitivities(mech, Q, self.frame, self.parameters, self.offsets)
        else:
            placements = _placements(mech, Q, self.frame)
        n = len(meas)
        raw = np.zeros((n, 6))
        raw[:, :3] = np.array([p.translation for p in placements]) - meas.positions
        blocks = [raw[:, :3] / meas.sigma[:, None]]
        rows = [twists[:, :3] / meas.sigma[:, None, None]] if jacobian else []
        if meas.rotations is not None:
            errors = [p.rotation @ R.T for p, R in zip(placements, meas.rotations)]
            raw[:, 3:] = [pin.log3(E) for E in errors]
            blocks.append(raw[:, 3:] / meas.sigma_rot[:, None])
            if jacobian:
                turn = np.array([pin.Jlog3(E) @ E.T for E in errors])
                rows.append(turn @ twists[:, 3:] / meas.sigma_rot[:, None, None])
        r = np.concatenate(blocks, axis=1).ravel()
        J = np.concatenate(rows, axis=1).reshape(len(r), -1) if jacobian else None
        return r, J, raw


def _placements(mech: Mechanism, Q: Floats, frame: str) -> list[pin.SE3]:
    fid = mech.frame_id(frame)
    out = []
    for q in Q:
        pin.framesForwardKinematics(mech.model, mech.data, q)
        out.append(mech.data.oMf[fid].copy())
    return out


def _scales(J: Floats) -> Floats:
    norms = np.linalg.norm(J, axis=0)
    return np.where(norms > 0, norms, 1.0)


def identifiability(J: Floats, names: Sequence[str], rcond: float = RCOND) -> Identifiability:
    """Rank, condition number and the unknowns that cannot be told apart of the Jacobian ``J`` (m, n), its columns
    scaled by their norms (a column of zeros is an unknown that moves nothing: unidentifiable alone)."""
    D = _scales(J)
    s, Vt = np.linalg.svd(J / D, full_matrices=False)[1:]
    kept = s > rcond * s[0] if s.size and s[0] > 0 else np.zeros(len(s), dtype=bool)
    rank = int(kept.sum())
    condition = float(s[0] / s[-1]) if rank == len(names) and rank else float("inf")
    null = Vt[rank:].T @ Vt[rank:]  # the projector onto the near-null space: basis-free
    involved = [k for k in range(len(names)) if null[k, k] >= NULL_COMPONENT**2]
    groups, placed = [], set()
    for k in involved:  # connected sets of unknowns linked through the null space
        if k in placed:
            continue
        group, todo = [], [k]
        while todo:
            i = todo.pop()
            if i in placed:
                continue
            placed.add(i)
            group.append(i)
            todo += [j for j in involved if j not in placed and abs(null[i, j]) >= NULL_COMPONENT**2]
        groups.append(tuple(names[i] for i in sorted(group)))
    return Identifiability(rank, len(names), condition, tuple(groups), tuple(float(x) for x in s))


def _step(r: Floats, J: Floats, D: Floats, damping: float, rcond: float) -> Floats:
    """The Levenberg–Marquardt step (unscaled) over the singular values above ``rcond``·s₁ of J/D."""
    U, s, Vt = np.linalg.svd(J / D, full_matrices=False)
    kept = s > rcond * s[0]
    s, U, Vt = s[kept], U[:, kept], Vt[kept]
    z = -Vt.T @ ((s / (s**2 + damping * s[0] ** 2)) * (U.T @ r))
    return z / D


def _resolve(mech: Mechanism, names: Sequence[str]) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """(parameters, coordinates with offsets) of the names asked for (parameters of ``mech``, coordinates by name
    or ``qk``)."""
    parameters: list[str] = []
    offsets: list[str] = []
    if not names:
        raise InputError(f"name the parameters to identify (of {mech.name}: {', '.join(mech.parameters)}; and joint "
                         f"offsets: {', '.join(coordinate_names(mech))})")
    for name in names:
        name = name.strip()
        coordinate = None if name in mech.parameters else resolve_coordinate(mech, name)
        if name not in mech.parameters and coordinate is None:
            raise unknown_name_error(f"parameter or joint of {mech.name}", name,
                                     list(mech.parameters) + coordinate_names(mech))
        target, value = (parameters, name) if coordinate is None else (offsets, coordinate)
        if value in parameters or value in offsets:
            raise InputError(f"{name} is named twice")
        target.append(value)
    return tuple(parameters), tuple(offsets)


def calibrate(mech: Mechanism, measurements: Measurements | str | Path, parameters: Sequence[str],
              frame: str | None = None, *, allow_unidentifiable: bool = False, rcond: float = RCOND,
              max_iterations: int = 100, xtol: float = 1e-12) -> CalibrationResult:
    """Identify ``parameters`` (names of ``mech.parameters``, and coordinates — a joint's name or ``qk`` — for
    encoder offsets) from ``measurements`` (a :class:`Measurements` or a measurements CSV) of ``frame`` (default
    the tool frame): Levenberg–Marquardt on the exact Jacobian (module docstring).

    Raises:
        InputError: an unknown name; fewer residuals than unknowns + 1; unknowns that cannot be told apart (named;
            unless ``allow_unidentifiable``); a measured pose the mechanism cannot take.
    """
    rcond = number("rcond", rcond, positive=True, maximum=0.1)
    xtol = number("xtol", xtol, positive=True, maximum=0.1)
    max_iterations = number("max_iterations", max_iterations, integer=True, minimum=1, maximum=10_000)
    if isinstance(parameters, str):
        parameters = parameters.split(",")
    meas = measurements if isinstance(measurements, Measurements) else read_measurements(measurements, mech)
    frame = frame or mech.tool_frame
    mech.frame_id(frame)
    params, offsets = _resolve(mech, parameters)
    problem = CalibrationProblem(mech, meas, params, offsets, frame)
    n = len(problem.names)
    per_row = problem.size // len(meas)
    if problem.size <= n:
        rows = f"{len(meas)} measurement gives" if len(meas) == 1 else f"{len(meas)} measurements give"
        raise InputError(f"{rows} {problem.size} equations ({per_row} per row) for {n} "
                         f"unknowns: give at least {n // per_row + 1} rows", file=meas.file)
    mech.warn_limits(problem.configurations(np.zeros(n)), "measurements",
                     [f"measurement {label}" for label in meas.labels])
    try:
        x, r, J, iterations, converged = _solve(problem, allow_unidentifiable, rcond, max_iterations, xtol)
    except (UnreachableError, SingularityError) as exc:
        raise InputError(str(exc), file=meas.file) from None
    return _result(problem, x, r, J, iterations, converged, rcond)


def _refuse(found: Identifiability) -> InputError:
    groups = "; ".join(" and ".join(g) for g in found.groups)
    return InputError(f"these measurements cannot tell apart: {groups} (the rank of the Jacobian is {found.rank} of "
                      f"{found.unknowns}; they move the measured poses alike): leave one of each out of the "
                      "parameters, measure more varied poses, or allow them for the minimum-norm change "
                      "(--allow-unidentifiable)")


def _solve(problem: CalibrationProblem, allow: bool, rcond: float, max_iterations: int, xtol: float):
    n = len(problem.names)
    x = np.zeros(n)
    r, J, _ = problem.evaluate(x)
    found = identifiability(J, problem.names, rcond)
    if found.groups and not allow:
        raise _refuse(found)
    D = _scales(J)
    cost, damping, converged = float(r @ r), 1e-3, False
    iterations = 0
    while iterations < max_iterations:
        iterations += 1
        dx = _step(r, J, D, damping, rcond)
        x_new = x + dx
        r_new = problem.residuals(x_new)[0]  # the Jacobian only for a step taken
        cost_new = float(r_new @ r_new)
        small = np.linalg.norm(dx * D) <= xtol * (np.linalg.norm(x * D) + xtol)
        settled = abs(cost - cost_new) <= FTOL * cost  # the cost no longer changes but for rounding
        if cost_new <= cost:
            x, cost = x_new, cost_new
            r, J, _ = problem.evaluate(x)
            D = np.maximum(D, _scales(J))
            damping = damping / 10 if damping > 1e-12 else 0.0
        else:
            damping = max(damping * 10, 1e-9)
        if small or settled or cost == 0.0:
            converged = True
            break
    return x, r, J, iterations, converged


def _result(problem: CalibrationProblem, x: Floats, r: Floats, J: Floats, iterations: int, converged: bool,
            rcond: float) -> CalibrationResult:
    found = identifiability(J, problem.names, rcond)
    m = problem.size
    D = _scales(J)
    U, s, Vt = np.linalg.svd(J / D, full_matrices=False)
    kept = s > rcond * s[0]
    dof = m - int(kept.sum())
    sigma2 = float(r @ r) / dof
    covariance = (Vt[kept].T / s[kept] ** 2) @ Vt[kept] / np.outer(D, D) * sigma2
    unclear = {name for group in found.groups for name in group}
    before = problem.residuals(np.zeros(len(x)))[1]
    after = problem.residuals(x)[1]
    nominal = problem.mech.parameter_values()
    unknowns = []
    for k, name in enumerate(problem.names):
        is_parameter = k < len(problem.parameters)
        unit = problem.mech.parameters[name].unit if is_parameter else \
            ("rad" if problem.mech.joint_kind(name) == "revolute" else "m")
        start = nominal[name] if is_parameter else 0.0
        error = None if name in unclear else float(np.sqrt(max(covariance[k, k], 0.0)))
        unknowns.append(Unknown(name, "parameter" if is_parameter else "joint offset", unit, start,
                                start + float(x[k]), error))
    return CalibrationResult(problem.mech.name, problem.frame, tuple(unknowns), found, before, after,
                             problem.measurements, float(np.sqrt(sigma2)), iterations, converged,
                             problem.mechanism(x), _notes(problem, r, sigma2, dof, converged, iterations))


#: The significance of the χ² test of the residuals against the σ given: below it they are taken as inconsistent.
CHI2_SIGNIFICANCE = 1e-3


def _notes(problem: CalibrationProblem, r: Floats, sigma2: float, dof: int, converged: bool,
           iterations: int) -> tuple[str, ...]:
    """What a reader of the calibration should know: no convergence; with σ given, weighted residuals that a χ²
    test rejects (RSS/(m − n) = σ̂² against χ²_{m−n}/(m − n) at :data:`CHI2_SIGNIFICANCE`), with the measurement
    whose weighted residual is largest (a possible outlier)."""
    from scipy import stats

    meas, notes = problem.measurements, []
    if not converged:
        notes.append(f"Levenberg–Marquardt stopped after {iterations} iterations without converging: the values "
                     "are the best reached")
    if meas.weighted and dof > 0 and stats.chi2.sf(sigma2 * dof, dof) < CHI2_SIGNIFICANCE:
        per_row = np.linalg.norm(r.reshape(len(meas), -1), axis=1)
        worst = int(np.argmax(per_row))
        where = f" (row {meas.rows[worst]})" if meas.rows else ""
        notes.append(f"the residuals are {np.sqrt(sigma2):.3g} times the σ given (a χ² test rejects them at "
                     f"{CHI2_SIGNIFICANCE:g}): the σ are too small, the model lacks an error source, or a measurement "
                     f"is off — the largest weighted residual is that of measurement {meas.labels[worst]}{where}, "
                     f"{per_row[worst]:.3g} σ")
    return tuple(notes)
