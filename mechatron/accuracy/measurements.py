"""Measurements of a built machine for calibration: ``measurements.csv`` (format: docs/measurements_csv.md).

One row per measured pose:

- the coordinates as read by the machine's encoders, one column per coordinate exactly as in a poses file
  (:func:`~mechatron.accuracy.sources.read_poses`: joint names or ``q1``…, rad and m or ``_deg``, ``_mm``…; a closed
  loop's actuated coordinates);
- the measured position of the output frame in the world frame: ``x``, ``y``, ``z`` (m) or with a length suffix
  (``x_mm``, ``y_mm``, ``z_mm``; each column its own);
- optionally its orientation, all three or none: ``roll``, ``pitch``, ``yaw`` (rad, or ``_deg``, …), URDF's
  roll–pitch–yaw about fixed axes, R = R_z(yaw) R_y(pitch) R_x(roll);
- optionally the standard deviation of the row's position, ``sigma`` (m) or ``sigma_mm``/``sigma_um``, and of its
  orientation, ``sigma_rot`` (rad) or ``sigma_rot_deg``, ``sigma_rot_mrad``… (> 0): they weight the rows (1/σ);
  without them σ = 1 mm (:data:`DEFAULT_SIGMA`) and σ_rot = σ / 1 m (1 mrad weighs as 1 mm, mechatron's rule);
- an optional ``label``.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pinocchio as pin
from numpy.typing import NDArray

from ..errors import InputError
from ..io.tables import number, read_csv
from ..model.mechanism import Mechanism
from ..units import UNITS
from .sensitivity import coordinate_names
from .sources import pose_column

Floats = NDArray[np.float64]

POSITION = ("x", "y", "z")
ORIENTATION = ("roll", "pitch", "yaw")


@dataclass(frozen=True)
class Measurements:
    """Measured poses of a machine: ``coordinates`` (N, n_c) as the encoders read them (rad, m; in
    :func:`~mechatron.accuracy.sensitivity.coordinate_names` order), ``positions`` (N, 3) (m, world frame),
    ``rotations`` (N, 3, 3) or None, the standard deviations ``sigma`` (N,) (m) and ``sigma_rot`` (N,) (rad) that
    weight the rows, a ``label`` per row, the file's ``rows`` (line numbers) and ``file``; ``weighted`` when the
    σ of the positions are given (not the default σ of :data:`DEFAULT_SIGMA`)."""

    coordinates: Floats
    positions: Floats
    rotations: Floats | None
    sigma: Floats
    sigma_rot: Floats
    labels: tuple[str, ...]
    rows: tuple[int, ...] = ()
    file: str | None = None
    weighted: bool = False  # the file gives the σ of its positions (a sigma column): σ̂ is then tested against 1

    def __post_init__(self) -> None:
        n = len(self.positions)
        if self.coordinates.shape[0] != n or self.positions.shape != (n, 3) or len(self.labels) != n:
            raise InputError("measurements need one row of coordinates, one position (3) and one label per pose")
        if self.rotations is not None and self.rotations.shape != (n, 3, 3):
            raise InputError("measured rotations must be (N, 3, 3)")
        for what, values in (("sigma", self.sigma), ("sigma_rot", self.sigma_rot)):
            if np.shape(values) != (n,) or not np.all(np.isfinite(values) & (np.asarray(values) > 0)):
                raise InputError(f"{what} must be one finite number > 0 per measurement")
        if not (np.all(np.isfinite(self.coordinates)) and np.all(np.isfinite(self.positions))):
            raise InputError("measured coordinates and positions must be finite")

    def __len__(self) -> int:
        return len(self.positions)


def _quantity_columns(columns: list[str], base: str, kind: str, path: Path) -> list[tuple[str, float]]:
    """The columns of quantity ``base`` (``x``, ``sigma_rot``…): (column, factor to SI) for ``base`` and
    ``base_<unit>`` with a unit of ``kind``."""
    out = []
    for column in columns:
        if column == base or column.startswith(base + "_"):
            suffix = column[len(base) + 1:]
            if base == "sigma" and suffix.startswith("rot"):
                continue
            factor = UNITS[kind].get(suffix)
            if factor is None:
                known = ", ".join(u for u in UNITS[kind] if u)
                raise InputError(f"{base} is {'a length' if kind == 'length' else 'an angle'}: unknown unit "
                                 f"{suffix!r} (known: {known})", file=path, field=column)
            out.append((column, factor))
    if len(out) > 1:
        raise InputError(f"{base} is given twice ({' and '.join(c for c, _ in out)})", file=path, field=out[1][0])
    return out


def _cell(row: dict, column: str, path: Path, line: int, factor: float = 1.0) -> float:
    if not row[column]:
        raise InputError("missing value", file=path, row=line, field=column)
    return number(row[column], file=path, row=line, field=column) * factor


def read_measurements(path: str | Path, mech: Mechanism) -> Measurements:
    """The measurements of the file ``path`` for ``mech`` (values in SI: m, rad).

    Raises:
        InputError: naming the file, the row and the column of a bad value (a missing or unknown column, a unit
            that is not the quantity's, an empty or non-finite cell, a σ ≤ 0).
    """
    path = Path(path)
    frame = read_csv(path)
    columns = list(frame.columns)
    quantities: dict[str, list[tuple[str, float]]] = {}
    for base, kind in [*((b, "length") for b in POSITION), *((b, "angle") for b in ORIENTATION),
                       ("sigma", "length"), ("sigma_rot", "angle")]:
        quantities[base] = _quantity_columns(columns, base, kind, path)
    used = {c for found in quantities.values() for c, _ in found} | {"label"}
    lookup: dict[str, tuple[str, float]] = {}
    for column in columns:
        if column in used:
            continue
        try:
            name, factor = pose_column(mech, column, path)
        except InputError as exc:
            raise InputError(f"{exc.message}; or x, y, z, roll, pitch, yaw, sigma, sigma_rot (with a unit suffix), "
                             "label", file=path, field=column) from None
        if name in lookup:
            raise InputError(f"{name} is given twice", file=path, field=column)
        lookup[name] = (column, factor)
    names = coordinate_names(mech)
    missing = [n for n in names if n not in lookup] + [b for b in POSITION if not quantities[b]]
    if missing:
        raise InputError(f"missing column(s) {', '.join(missing)}", file=path, field=missing[0])
    given = [b for b in ORIENTATION if quantities[b]]
    if given and len(given) < 3:
        absent = [b for b in ORIENTATION if not quantities[b]]
        raise InputError(f"an orientation is roll, pitch and yaw: missing column(s) {', '.join(absent)}", file=path,
                         field=absent[0])
    if quantities["sigma_rot"] and not given:
        raise InputError("sigma_rot weights measured orientations: give roll, pitch and yaw too", file=path,
                         field=quantities["sigma_rot"][0][0])
    n = len(frame)
    coordinates, positions = np.empty((n, len(names))), np.empty((n, 3))
    rotations = np.empty((n, 3, 3)) if given else None
    sigma, sigma_rot = np.full(n, DEFAULT_SIGMA), np.full(n, np.nan)
    for k, (line, row) in enumerate(zip(frame.index, frame.to_dict(orient="records"))):
        for j, name in enumerate(names):
            coordinates[k, j] = _cell(row, lookup[name][0], path, line, lookup[name][1])
        positions[k] = [_cell(row, quantities[b][0][0], path, line, quantities[b][0][1]) for b in POSITION]
        if rotations is not None:
            rotations[k] = pin.rpy.rpyToMatrix(*(_cell(row, quantities[b][0][0], path, line, quantities[b][0][1])
                                                 for b in ORIENTATION))
        for base, out in (("sigma", sigma), ("sigma_rot", sigma_rot)):
            if quantities[base]:
                column, factor = quantities[base][0]
                out[k] = _cell(row, column, path, line, factor)
                if not out[k] > 0:
                    raise InputError(f"a standard deviation must be > 0, got {row[column]}", file=path, row=line,
                                     field=column)
    if not quantities["sigma_rot"]:
        sigma_rot = sigma / DEFAULT_LENGTH_SCALE
    labels = tuple(r or str(i + 1) for i, r in enumerate(frame["label"])) if "label" in frame.columns else \
        tuple(str(i + 1) for i in range(n))
    if mech.closures:
        from ..dynamics.motion import check_input_ranges

        check_input_ranges(mech, names, coordinates, file=path, rows=[int(i) for i in frame.index],
                           fields=[lookup[n][0] for n in names], labels=list(labels))
    return Measurements(coordinates, positions, rotations, sigma, sigma_rot, labels,
                        tuple(int(i) for i in frame.index), str(path), weighted=bool(quantities["sigma"]))


#: The σ of a row's position (m) when a file gives none: 1 mm, so that σ̂ reads as the residuals' spread in mm.
DEFAULT_SIGMA = 1e-3
#: The length (m) that makes an orientation residual (rad) comparable with a position residual (m) when a file
#: gives no ``sigma_rot``: σ_rot = σ / (1 m), 1 mrad weighs as 1 mm (mechatron's rule).
DEFAULT_LENGTH_SCALE = 1.0
