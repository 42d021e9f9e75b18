"""Error sources and poses of an accuracy study, and the CSV files that give them.

``tolerances.csv`` — one row per error source:

- ``parameter`` (required): a geometric parameter of the mechanism (``a2``, ``l1``…) or a coordinate (a joint name,
  ``q1``… for the k-th; the actuated ones of a closed loop): a coordinate's row is a joint error;
- the tolerance t, the largest error either side: ``tolerance`` (SI: m or rad) or with a unit,
  ``tolerance_mm``, ``tolerance_um``, ``tolerance_deg``, ``tolerance_arcmin``, ``tolerance_arcsec``,
  ``tolerance_mrad``, ``tolerance_urad`` (a row fills one of them); or ``grade``: ``IT2``…``IT17`` for lengths
  (table 8.2) or ``AT5``…``AT14`` for angles (table 8.1), t = half the zone width, looked up by the parameter's
  nominal size or by ``size`` / ``size_mm`` (required for angles: the length of the shorter side);
- ``distribution``: ``normal`` (σ = t/k, default), ``uniform`` (σ = t/√3) or ``triangular`` (σ = t/√6);
- ``bias``: a systematic offset of the error (same unit columns as the tolerance), default 0;
- ``error``: the signed error of one given set of errors (``--method given``; same unit columns).

``poses.csv`` — one row per configuration: a column per coordinate (joint names or q1…qn; for a closed loop the
actuated coordinates), in rad and m, or ``<name>_deg`` / ``<name>_mm``; an optional ``label`` column.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from ..errors import InputError
from ..kinematics.loops import loop_solver
from ..model.mechanism import Mechanism, unknown_name_error
from ..units import UNITS
from .sensitivity import coordinate_names, resolve_coordinate
from .tables import tolerance_from_grade

DISTRIBUTIONS = ("normal", "uniform", "triangular")
LENGTH_UNITS = UNITS["length"]
ANGLE_UNITS = UNITS["angle"]
VALUE_FIELDS = ("tolerance", "bias", "error")


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


def _read_csv(path: Path) -> pd.DataFrame:
    try:
        frame = pd.read_csv(path, dtype=str, keep_default_na=False, comment="#", skipinitialspace=True)
    except FileNotFoundError:
        raise InputError("no such file", file=path) from None
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
        raise InputError(f"not a readable CSV file: {str(exc).splitlines()[0]}", file=path) from None
    frame.columns = [c.strip() for c in frame.columns]
    if frame.empty:
        raise InputError("the file has no rows", file=path)
    return frame


def _number(text: str, path: Path, row: int, column: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise InputError(f"not a number: {text!r}", file=path, row=row, field=column) from None
    if not math.isfinite(value):
        raise InputError(f"not a finite number: {text!r}", file=path, row=row, field=column)
    return value


def _unit_columns(frame: pd.DataFrame, path: Path) -> dict[str, list[tuple[str, str]]]:
    """For tolerance, bias and error: their columns with the unit suffix of each."""
    known = set(LENGTH_UNITS) | set(ANGLE_UNITS)
    out: dict[str, list[tuple[str, str]]] = {f: [] for f in VALUE_FIELDS}
    allowed = {"parameter", "grade", "size", "size_mm", "distribution", "label", "note", "description"}
    for column in frame.columns:
        base, _, suffix = column.partition("_")
        if base in VALUE_FIELDS:
            if suffix not in known:
                raise InputError(f"unknown unit {suffix!r} (known: {', '.join(sorted(u for u in known if u))})",
                                 file=path, field=column)
            out[base].append((column, suffix))
        elif column not in allowed:
            raise InputError("unknown column (expected parameter, tolerance[_unit], grade, size[_mm], distribution, "
                             "bias[_unit], error[_unit])", file=path, field=column)
    return out


def _value(row: dict, columns: list[tuple[str, str]], unit: str, path: Path, line: int, field: str) -> float | None:
    given = [(c, s) for c, s in columns if row[c].strip()]
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
    return _number(row[column], path, line, column) * units[suffix]


def read_tolerances(path: str | Path, mech: Mechanism, need: str = "tolerance") -> list[ErrorSource]:
    """The error sources of ``path`` for ``mech``; ``need`` is ``"tolerance"`` (every row needs a tolerance or
    grade) or ``"error"`` (every row needs an error, for ``--method given``)."""
    path = Path(path)
    frame = _read_csv(path)
    columns = _unit_columns(frame, path)
    if "parameter" not in frame.columns:
        raise InputError("missing column 'parameter'", file=path, field="parameter")
    if need == "tolerance" and not columns["tolerance"] and "grade" not in frame.columns:
        raise InputError("missing column 'tolerance' (or tolerance_mm, …, or grade)", file=path, field="tolerance")
    if need == "error" and not columns["error"]:
        raise InputError("missing column 'error' (the given errors of --method given)", file=path, field="error")
    sources, seen = [], {}
    for i, row in enumerate(frame.to_dict(orient="records"), start=2):
        raw = row["parameter"].strip()
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
        grade = row.get("grade", "").strip()
        if grade:
            if tolerance is not None:
                raise InputError("give a tolerance or a grade, not both", file=path, row=i, field="grade")
            tolerance = _grade_tolerance(mech, name, unit, grade, row, path, i)
        if tolerance is None and need == "tolerance":
            raise InputError("missing tolerance (or grade)", file=path, row=i, field="tolerance")
        if tolerance is not None and tolerance < 0:
            raise InputError(f"a tolerance must be >= 0, got {tolerance:g}", file=path, row=i,
                             field=next((c for c, _ in columns["tolerance"] if row[c].strip()), "tolerance"))
        distribution = row.get("distribution", "").strip().lower() or "normal"
        if distribution not in DISTRIBUTIONS:
            raise InputError(f"unknown distribution {distribution!r}; expected one of: {', '.join(DISTRIBUTIONS)}",
                             file=path, row=i, field="distribution")
        bias = _value(row, columns["bias"], unit, path, i, "bias") or 0.0
        error = _value(row, columns["error"], unit, path, i, "error")
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
    size_text = row.get("size", "").strip() or row.get("size_mm", "").strip()
    if size_text:
        column = "size" if row.get("size", "").strip() else "size_mm"
        size = _number(size_text, path, line, column) * (1e-3 if column == "size_mm" else 1.0)
    elif unit == "m" and name in mech.parameters:
        size = abs(mech.parameter_values()[name])
    else:
        raise InputError(f"a grade for {name} needs the size to look it up (column size or size_mm)", file=path,
                         row=line, field="size")
    try:
        return tolerance_from_grade(grade, size) / 2
    except InputError as exc:
        raise InputError(exc.message, file=path, row=line, field="grade") from None


def read_poses(path: str | Path, mech: Mechanism) -> tuple[np.ndarray, list[str]]:
    """The poses of ``path``: values of the coordinates (N, n_c) in SI (coordinate_names order) and labels."""
    path = Path(path)
    frame = _read_csv(path)
    names = coordinate_names(mech)
    lookup: dict[str, tuple[str, float]] = {}
    for column in frame.columns:
        if column == "label":
            continue
        base, factor = column, 1.0
        for suffix, scale in (("_deg", math.pi / 180), ("_mm", 1e-3)):
            if column.endswith(suffix):
                base, factor = column[: -len(suffix)], scale
        name = resolve_coordinate(mech, base)
        if name is None:
            raise InputError(f"not a coordinate of {mech.name} (expected {', '.join(names)}, or q1…q{len(names)})",
                             file=path, field=column)
        if name in lookup:
            raise InputError(f"{name} is given twice", file=path, field=column)
        lookup[name] = (column, factor)
    missing = [n for n in names if n not in lookup]
    if missing:
        raise InputError(f"missing column(s) {', '.join(missing)}", file=path, field=missing[0])
    values = np.empty((len(frame), len(names)))
    for i, row in enumerate(frame.to_dict(orient="records")):
        for j, name in enumerate(names):
            column, factor = lookup[name]
            if not row[column].strip():
                raise InputError("missing value", file=path, row=i + 2, field=column)
            values[i, j] = _number(row[column], path, i + 2, column) * factor
    labels = [r.strip() or str(i + 1) for i, r in enumerate(frame["label"])] if "label" in frame.columns else \
        [str(i + 1) for i in range(len(frame))]
    return values, labels


def reference_pose(mech: Mechanism) -> np.ndarray:
    """One pose (1, n_c): the reference configuration's coordinates (a closed loop's actuated inputs), or the
    neutral configuration of a serial arm moved inside its limits."""
    if mech.closures:
        solver = loop_solver(mech)
        return np.asarray(mech.reference_q, dtype=float)[solver.act][None, :]
    q = np.asarray(mech.reference_q if mech.reference_q is not None else mech.neutral(), dtype=float)
    return np.clip(q, mech.model.lowerPositionLimit, mech.model.upperPositionLimit)[None, :]


def workspace_grid(mech: Mechanism, count: int, seed: int = 0) -> np.ndarray:
    """Poses over the coordinates' ranges: a full count^n grid for n ≤ 2 coordinates, else ``count`` random poses
    (seeded). Unlimited revolute coordinates span one turn, unlimited prismatic ones ±0.5 m about the reference."""
    if count < 1:
        raise InputError(f"a grid needs at least 1 point per coordinate, got {count}")
    names = coordinate_names(mech)
    reference = reference_pose(mech)[0]
    lower, upper = np.empty(len(names)), np.empty(len(names))
    for j, name in enumerate(names):
        index = mech.model.joints[mech.joint_id(name)].idx_q
        lo, hi = mech.model.lowerPositionLimit[index], mech.model.upperPositionLimit[index]
        if not (np.isfinite(lo) and np.isfinite(hi) and hi - lo < 1e10):
            half = np.pi if mech.joint_kind(name) == "revolute" else 0.5
            lo, hi = reference[j] - half, reference[j] + half
        lower[j], upper[j] = lo, hi
    if len(names) <= 2:
        axes = [np.linspace(lo, hi, count) for lo, hi in zip(lower, upper)]
        return np.stack([g.ravel() for g in np.meshgrid(*axes, indexing="ij")], axis=1)
    rng = np.random.default_rng(seed)
    return lower + (upper - lower) * rng.random((count, len(names)))
