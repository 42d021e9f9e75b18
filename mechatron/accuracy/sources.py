"""Error sources and poses of an accuracy study, and the CSV files that give them.

``tolerances.csv`` — one row per error source:

- ``parameter`` (required): a geometric parameter of the mechanism (``a2``, ``l1``…) or a coordinate (a joint name,
  ``q1``… for the k-th; the actuated ones of a closed loop): a coordinate's row is a joint error;
- the tolerance t, the largest error either side: ``tolerance`` (SI: m or rad) or with a unit suffix of
  :data:`mechatron.units.UNITS` (lengths ``tolerance_mm``, ``tolerance_um``, …; angles ``tolerance_deg``,
  ``tolerance_arcmin``, ``tolerance_arcsec``, ``tolerance_mrad``, ``tolerance_urad``; a row fills one of them);
  or ``grade``: ``IT2``…``IT17`` for lengths ([Egorov, table 8.2], the grades of [ISO 286-1]) or ``AT5``…``AT14``
  for angles ([Egorov, table 8.1]), t = half the zone width, looked up by the parameter's nominal size or by
  ``size`` / ``size_<length unit>`` (required for angles: the length of the shorter side);
- ``distribution``: ``normal`` (σ = t/k, default), ``uniform`` (σ = t/√3) or ``triangular`` (σ = t/√6);
- ``bias``: a systematic offset of the error (same unit columns as the tolerance), default 0;
- ``error``: the signed error of one given set of errors (``--method given``; same unit columns);
- a cost model for tolerance allocation (:mod:`~mechatron.accuracy.costs`: ``cost_a``, ``cost_b``, ``cost_k`` with
  ``tolerance_min[_unit]`` and ``tolerance_max[_unit]``, or ``process``), read by
  :func:`~mechatron.accuracy.costs.read_cost_models`; a row with one needs no tolerance when ``need`` is
  ``"allocate"``.

``poses.csv`` — one row per configuration: a column per coordinate (joint names or q1…qn, one per joint — a
continuous joint's angle too; for a closed loop the actuated coordinates), in rad and m, or with a unit suffix
(``<name>_deg``, ``<name>_mm``, …); an optional ``label`` column.

Both are read by :func:`mechatron.io.tables.read_csv`: a problem is reported with the file, the row and the column.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from ..io.tables import number, read_csv
from ..io.values import number as check_number
from ..kinematics.loops import loop_solver
from ..model.mechanism import Mechanism, unknown_name_error
from ..units import UNITS
from .sensitivity import coordinate_names, resolve_coordinate
from .tables import tolerance_from_grade

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd

DISTRIBUTIONS = ("normal", "uniform", "triangular")
LENGTH_UNITS = UNITS["length"]
ANGLE_UNITS = UNITS["angle"]
VALUE_FIELDS = ("tolerance", "bias", "error")
#: The columns of a cost model (:mod:`~mechatron.accuracy.costs`), and the prefixes of its tolerance bounds.
COST_COLUMNS = ("cost_a", "cost_b", "cost_k", "process")
BOUND_COLUMNS = ("tolerance_min", "tolerance_max")
#: The range of a tolerance (SI: m, rad, or a ratio; 0 = exact): below a nanometre (or nanoradian) the Monte Carlo's
#: perturbed positions cannot resolve the errors in double precision, and above 1000 m (rad) no mechanism is meant.
SMALLEST_ERROR = 1e-9
LARGEST_ERROR = 1e3


@dataclass(frozen=True)
class ErrorSource:
    """One error source: a parameter or coordinate ``name`` (``kind``), its tolerance t ≥ 0 (errors lie in
    bias ± t), distribution, bias and, for a given set of errors, ``error``; values in SI (``unit`` m or rad)."""

    name: str
    kind: str  # "parameter" or "coordinate"
    unit: str  # "m", "rad" or "-"
    tolerance: float = 0.0
    distribution: str = "normal"
    bias: float = 0.0
    error: float | None = None

    def __post_init__(self) -> None:
        t = self.tolerance
        if not (isinstance(t, (int, float, np.floating)) and (t == 0 or SMALLEST_ERROR <= t <= LARGEST_ERROR)):
            raise InputError(f"the tolerance of {self.name} must be 0 or from {SMALLEST_ERROR:g} to "
                             f"{LARGEST_ERROR:g} {self.unit}, got {t!r}")
        for what, value in (("bias", self.bias), ("error", self.error)):
            if value is not None and not (isinstance(value, (int, float, np.floating)) and math.isfinite(value)
                                          and abs(value) <= LARGEST_ERROR):
                raise InputError(f"the {what} of {self.name} must be a finite number of magnitude <= "
                                 f"{LARGEST_ERROR:g} {self.unit}, got {value!r}")
        if self.distribution not in DISTRIBUTIONS:
            raise InputError(f"unknown distribution {self.distribution!r} of {self.name}; expected one of: "
                             f"{', '.join(DISTRIBUTIONS)}")

    def sigma(self, k: float = 3.0) -> float:
        """Standard deviation of the error: t/k (normal), t/√3 (uniform), t/√6 (triangular)."""
        return {"normal": self.tolerance / k, "uniform": self.tolerance / math.sqrt(3),
                "triangular": self.tolerance / math.sqrt(6)}[self.distribution]


def source_unit(mech: Mechanism, name: str) -> tuple[str, str]:
    """(resolved name, unit) of an error source name: a parameter, or a coordinate (by name or ``qk``)."""
    if name in mech.parameters:
        kind = mech.parameters[name].kind
        return name, {"length": "m", "angle": "rad"}.get(kind, "-")
    coordinate = resolve_coordinate(mech, name)
    if coordinate is not None:
        return coordinate, "rad" if mech.joint_kind(coordinate) == "revolute" else "m"
    raise unknown_name_error(f"parameter or coordinate of {mech.name}", name,
                             list(mech.parameters) + coordinate_names(mech))


def _unit_columns(frame: pd.DataFrame, path: Path) -> dict[str, list[tuple[str, str]]]:
    """For tolerance, bias and error: their columns with the unit suffix of each."""
    known = set(LENGTH_UNITS) | set(ANGLE_UNITS)
    out: dict[str, list[tuple[str, str]]] = {f: [] for f in VALUE_FIELDS}
    allowed = {"parameter", "grade", "distribution", "label", "note", "description"}
    allowed |= {"size" + (f"_{u}" if u else "") for u in LENGTH_UNITS}
    for column in frame.columns:
        base, _, suffix = column.partition("_")
        if column in COST_COLUMNS:
            continue  # a cost model's columns (mechatron.accuracy.costs)
        if column.startswith(BOUND_COLUMNS):  # tolerance_min, tolerance_min_mm, …
            rest = column[len("tolerance_min"):]
            if rest and (rest[0] != "_" or rest[1:] not in known):
                raise InputError(f"unknown unit {rest[1:]!r} (known: {', '.join(sorted(u for u in known if u))})",
                                 file=path, field=column)
            continue
        if base in VALUE_FIELDS:
            if suffix not in known:
                raise InputError(f"unknown unit {suffix!r} (known: {', '.join(sorted(u for u in known if u))})",
                                 file=path, field=column)
            out[base].append((column, suffix))
        elif column not in allowed:
            raise InputError("unknown column (expected parameter, tolerance[_unit], grade, size[_unit], distribution, "
                             "bias[_unit], error[_unit], cost_a, cost_b, cost_k, tolerance_min[_unit], "
                             "tolerance_max[_unit], process)", file=path, field=column)
    return out


def _value(row: dict, columns: list[tuple[str, str]], unit: str, path: Path, line: int, field: str) -> float | None:
    given = [(c, s) for c, s in columns if row[c]]
    if len(given) > 1:
        raise InputError(f"give the {field} in one column, not {' and '.join(c for c, _ in given)}", file=path,
                         row=line, field=given[1][0])
    if not given:
        return None
    column, suffix = given[0]
    units = ANGLE_UNITS if unit == "rad" else LENGTH_UNITS if unit == "m" else {"": 1.0}
    if suffix not in units:
        what = {"m": "a length", "rad": "an angle"}.get(unit, "a ratio")
        raise InputError(f"{what} cannot be given in {suffix}", file=path, row=line, field=column)
    return number(row[column], file=path, row=line, field=column) * units[suffix]


def read_tolerances(path: str | Path, mech: Mechanism, need: str = "tolerance") -> list[ErrorSource]:
    """The error sources of the tolerances file ``path`` for ``mech`` (values in SI: m, rad); ``need`` is
    ``"tolerance"`` (every row needs a tolerance or grade), ``"error"`` (every row needs an error, for the method
    ``given``) or ``"allocate"`` (a row with a cost model may leave its tolerance empty: 0 until allocated).

    Raises:
        InputError: naming the file, the row and the column of a bad value.
    """
    path = Path(path)
    frame = read_csv(path)
    columns = _unit_columns(frame, path)
    if "parameter" not in frame.columns:
        raise InputError("missing column 'parameter'", file=path, field="parameter")
    costed = [c for c in ("cost_b", "process") if c in frame.columns]
    if need == "tolerance" and not columns["tolerance"] and "grade" not in frame.columns:
        raise InputError("missing column 'tolerance' (or tolerance_mm, …, or grade)", file=path, field="tolerance")
    if need == "error" and not columns["error"]:
        raise InputError("missing column 'error' (the given errors of --method given)", file=path, field="error")
    sources, seen = [], {}
    for i, row in zip(frame.index, frame.to_dict(orient="records")):
        raw = row["parameter"]
        if not raw:
            raise InputError("missing value", file=path, row=i, field="parameter")
        try:
            name, unit = source_unit(mech, raw)
        except InputError as exc:
            raise InputError(exc.message, file=path, row=i, field="parameter") from None
        if name in seen:
            raise InputError(f"{name} repeats row {seen[name]}", file=path, row=i, field="parameter")
        seen[name] = i
        tolerance = _value(row, columns["tolerance"], unit, path, i, "tolerance")
        grade = row.get("grade", "")
        if grade:
            if tolerance is not None:
                raise InputError("give a tolerance or a grade, not both", file=path, row=i, field="grade")
            tolerance = _grade_tolerance(mech, name, unit, grade, row, path, i)
        if tolerance is None and need == "allocate" and not any(row[c] for c in costed):
            raise InputError("missing tolerance (or grade, or a cost model: cost_b or process)", file=path, row=i,
                             field="tolerance")
        if tolerance is None and need == "tolerance":
            raise InputError("missing tolerance (or grade)", file=path, row=i, field="tolerance")
        if tolerance is not None and not (tolerance == 0 or SMALLEST_ERROR <= tolerance <= LARGEST_ERROR):
            need = ">= 0" if tolerance < 0 else f"0 or from {SMALLEST_ERROR:g} to {LARGEST_ERROR:g} {unit} (in SI)"
            raise InputError(f"a tolerance must be {need}, got {tolerance:g} {unit}", file=path, row=i,
                             field=next((c for c, _ in columns["tolerance"] if row[c]), "grade"))
        distribution = row.get("distribution", "").lower() or "normal"
        if distribution not in DISTRIBUTIONS:
            raise InputError(f"unknown distribution {distribution!r}; expected one of: {', '.join(DISTRIBUTIONS)}",
                             file=path, row=i, field="distribution")
        bias = _value(row, columns["bias"], unit, path, i, "bias") or 0.0
        error = _value(row, columns["error"], unit, path, i, "error")
        for what, value in (("bias", bias), ("error", error)):
            if value is not None and abs(value) > LARGEST_ERROR:
                raise InputError(f"a {what} must be of magnitude <= {LARGEST_ERROR:g} {unit} (in SI), got {value:g} "
                                 f"{unit}", file=path, row=i, field=next(c for c, _ in columns[what] if row[c]))
        if error is None and need == "error":
            raise InputError("missing error", file=path, row=i, field="error")
        kind = "parameter" if name in mech.parameters else "coordinate"
        sources.append(ErrorSource(name, kind, unit, tolerance or 0.0, distribution, bias, error))
    return sources


def _grade_tolerance(mech: Mechanism, name: str, unit: str, grade: str, row: dict, path: Path, line: int) -> float:
    prefix = grade.strip().upper()[:2]
    if (prefix == "IT" and unit != "m") or (prefix == "AT" and unit != "rad"):
        raise InputError(f"{grade} is a {'length' if prefix == 'IT' else 'angle'} grade but {name} is "
                         f"{'an angle' if unit == 'rad' else 'a length' if unit == 'm' else 'a ratio'}",
                         file=path, row=line, field="grade")
    sizes = [(c, LENGTH_UNITS[c.partition("_")[2]]) for c in row if c.partition("_")[0] == "size" and row[c]]
    if len(sizes) > 1:
        raise InputError(f"give the size in one column, not {' and '.join(c for c, _ in sizes)}", file=path,
                         row=line, field=sizes[1][0])
    if sizes:
        column, factor = sizes[0]
        size = number(row[column], file=path, row=line, field=column) * factor
    elif unit == "m" and name in mech.parameters:
        size = abs(mech.parameter_values()[name])
    else:
        raise InputError(f"a grade for {name} needs the size to look it up (column size or size_mm)", file=path,
                         row=line, field="size")
    try:
        return tolerance_from_grade(grade, size) / 2
    except InputError as exc:
        raise InputError(exc.message, file=path, row=line, field="grade") from None


def pose_column(mech: Mechanism, column: str, path: Path) -> tuple[str, float]:
    """(coordinate, factor to SI) of a poses column: a coordinate's name (or ``qk``), with a unit suffix or not."""
    name = resolve_coordinate(mech, column)
    if name is not None:
        return name, 1.0
    base, _, suffix = column.rpartition("_")
    name = resolve_coordinate(mech, base) if base else None
    if name is None:
        names = coordinate_names(mech)
        raise InputError(f"not a coordinate of {mech.name} (expected {', '.join(names)}, or q1…q{len(names)})",
                         file=path, field=column)
    kind = "angle" if mech.joint_kind(name) == "revolute" else "length"
    factor = UNITS[kind].get(suffix)
    if not suffix or factor is None:
        known = ", ".join(u for u in UNITS[kind] if u)
        raise InputError(f"{name} is {'an angle' if kind == 'angle' else 'a length'}: unknown unit {suffix!r} "
                         f"(known: {known})", file=path, field=column)
    return name, factor


def read_poses(path: str | Path, mech: Mechanism) -> tuple[NDArray[np.float64], list[str]]:
    """The poses of the poses file ``path``: values of the coordinates (N, n_c) in SI (rad, m; in
    :func:`~mechatron.accuracy.sensitivity.coordinate_names` order) and a label per pose.

    Raises:
        InputError: naming the file, the row and the column of a bad value.
    """
    path = Path(path)
    frame = read_csv(path)
    names = coordinate_names(mech)
    lookup: dict[str, tuple[str, float]] = {}
    for column in frame.columns:
        if column == "label":
            continue
        name, factor = pose_column(mech, column, path)
        if name in lookup:
            raise InputError(f"{name} is given twice", file=path, field=column)
        lookup[name] = (column, factor)
    missing = [n for n in names if n not in lookup]
    if missing:
        raise InputError(f"missing column(s) {', '.join(missing)}", file=path, field=missing[0])
    values = np.empty((len(frame), len(names)))
    for k, (i, row) in enumerate(zip(frame.index, frame.to_dict(orient="records"))):
        for j, name in enumerate(names):
            column, factor = lookup[name]
            if not row[column]:
                raise InputError("missing value", file=path, row=i, field=column)
            values[k, j] = number(row[column], file=path, row=i, field=column) * factor
    labels = [r or str(i + 1) for i, r in enumerate(frame["label"])] if "label" in frame.columns else \
        [str(i + 1) for i in range(len(frame))]
    if mech.closures:
        from ..dynamics.motion import check_input_ranges

        check_input_ranges(mech, names, values, file=path, rows=[int(n) for n in frame.index],
                           fields=[lookup[n][0] for n in names], labels=labels)
    return values, labels


#: The most poses a task gives an accuracy study: its trajectory's samples, evenly thinned.
TASK_POSES = 100


def task_poses(path: str | Path, mech: Mechanism, most: int = TASK_POSES) -> tuple[NDArray[np.float64], list[str]]:
    """Poses (N, n_c) (rad, m) along the motion of the task file ``path`` (a TOML task or a trajectory CSV,
    :func:`mechatron.dynamics.task.read_task`): its trajectory's samples, evenly thinned to at most ``most`` (the
    first and the last kept), each labelled by its time (``t=0.25 s``)."""
    from ..dynamics.task import read_task

    trajectory = read_task(path, mech).trajectory
    values = trajectory.coordinates if trajectory.coordinates is not None else trajectory.q
    values = np.asarray(values, dtype=float)[:, [trajectory.names.index(n) for n in coordinate_names(mech)]]
    pick = np.unique(np.round(np.linspace(0, len(values) - 1, min(most, len(values)))).astype(int))
    return values[pick], [f"t={trajectory.t[i]:.4g} s" for i in pick]


def _coordinate_limits(mech: Mechanism) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """(lower, upper) limits (rad, m) of the error coordinates; ±inf for joints without limits (continuous)."""
    names = coordinate_names(mech)
    lower, upper = np.full(len(names), -np.inf), np.full(len(names), np.inf)
    model = mech.model
    for j, name in enumerate(names):
        joint = model.joints[mech.joint_id(name)]
        if joint.nq == 1:
            lower[j], upper[j] = model.lowerPositionLimit[joint.idx_q], model.upperPositionLimit[joint.idx_q]
    return lower, upper


def reference_pose(mech: Mechanism) -> NDArray[np.float64]:
    """One pose (1, n_c) (rad, m): the reference configuration's coordinates (a closed loop's actuated inputs), or
    the coordinates of a serial arm's neutral configuration moved inside its limits."""
    if mech.closures:
        solver = loop_solver(mech)
        return np.asarray(mech.reference_q, dtype=float)[solver.act][None, :]
    q = np.asarray(mech.reference_q if mech.reference_q is not None else mech.neutral(), dtype=float)
    return np.clip(mech.coordinates(q), *_coordinate_limits(mech))[None, :]


#: Bytes a pose of a study takes (its coordinates, sensitivities and row of the table; an upper bound).
POSE_BYTES = 4096.0


def workspace_grid(mech: Mechanism, count: int, seed: int = 0) -> NDArray[np.float64]:
    """Poses (rad, m) over the coordinates' ranges: a full count^n grid for n ≤ 2 coordinates, else ``count``
    random poses (seeded). Unlimited revolute (and continuous) coordinates span one turn, unlimited prismatic ones
    ±0.5 m about the reference."""
    count = check_number("count", count, integer=True, minimum=1)
    seed = check_number("seed", seed, integer=True, minimum=0)
    names = coordinate_names(mech)
    from ..io.budget import count as shown
    from ..io.budget import option, require

    poses = float(count) ** len(names) if len(names) <= 2 else float(count)
    require(f"{option('grid')} {count} gives {shown(poses)} poses", poses, POSE_BYTES,
            advice=f"use a smaller {option('grid')}")
    reference = reference_pose(mech)[0]
    lower, upper = _coordinate_limits(mech)
    for j, name in enumerate(names):
        lo, hi = lower[j], upper[j]
        if not (np.isfinite(lo) and np.isfinite(hi) and hi - lo < 1e10):
            half = np.pi if mech.joint_kind(name) == "revolute" else 0.5
            lo, hi = reference[j] - half, reference[j] + half
        lower[j], upper[j] = lo, hi
    if len(names) <= 2:
        axes = [np.linspace(lo, hi, count) for lo, hi in zip(lower, upper)]
        return np.stack([g.ravel() for g in np.meshgrid(*axes, indexing="ij")], axis=1)
    rng = np.random.default_rng(seed)
    return lower + (upper - lower) * rng.random((count, len(names)))
