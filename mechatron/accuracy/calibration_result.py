"""What a calibration returns: :class:`CalibrationResult` — the identified values with their standard errors, the
identifiability of the unknowns, the residuals before and after, and the calibrated mechanism.

It follows the result protocol (:class:`~mechatron.report.result.Result`): ``to_frame()`` is the table of unknowns
(nominal, identified, change, standard error, unit), ``as_dict()`` everything as plain data (no NaN),
``plot()`` the position residual of every measurement before and after (mm), ``str()`` the report printed by
``mechatron calibrate``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from ..report.result import Result, frame_records, readable
from .measurements import Measurements

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..model.mechanism import Mechanism
    from ..report.html import Report

#: Measurements the text report lists one by one.
SHOWN_ROWS = 20


@dataclass(frozen=True)
class Unknown:
    """One identified unknown: a geometric ``parameter`` or a ``joint offset`` (``kind``), its ``nominal`` and
    ``identified`` value (SI, ``unit`` m or rad; a joint offset's nominal is 0) and the standard error of the
    identified value (None where it cannot be told apart from others)."""

    name: str
    kind: str
    unit: str
    nominal: float
    identified: float
    std_error: float | None

    @property
    def change(self) -> float:
        return self.identified - self.nominal


@dataclass(frozen=True)
class Identifiability:
    """The scaled Jacobian at the solution: its ``rank`` of ``unknowns``, its condition number s₁/s_n (inf when
    rank-deficient), the ``groups`` of unknowns that cannot be told apart (one per near-null singular vector) and
    the ``singular_values`` (of the Jacobian with unit-norm columns)."""

    rank: int
    unknowns: int
    condition: float
    groups: tuple[tuple[str, ...], ...]
    singular_values: tuple[float, ...]

    @property
    def identifiable(self) -> bool:
        return self.rank == self.unknowns


def _shown(value: float, unit: str) -> tuple[float, str]:
    """A value in the unit a report shows: mm for m, degrees for rad."""
    return (value * 1e3, "mm") if unit == "m" else (math.degrees(value), "deg") if unit == "rad" else (value, unit)


@dataclass
class CalibrationResult(Result):
    """A calibration (:func:`~mechatron.accuracy.calibration.calibrate`).

    Attributes:
        mechanism: The nominal mechanism's name.
        frame: The measured frame.
        unknowns: The identified unknowns, parameters first, then joint offsets.
        identifiability: Rank, condition number and the unknowns that cannot be told apart.
        before, after: Per measurement (N, 6): the position error p_model − p_measured (m) and the rotation vector
            of R_model R_measuredᵀ (rad; zeros where no orientation was measured), with the nominal model and with
            the calibrated one.
        measurements: The measurements.
        sigma: σ̂, the standard deviation of a weighted residual (r/σ) after the fit: 1 when the measurements' σ
            are right (dimensionless; without σ columns σ = 1 mm, so σ̂ is the spread in mm).
        iterations: Levenberg–Marquardt iterations.
        converged: Whether the step fell below its tolerance within the iterations allowed.
        calibrated: The mechanism with the identified parameters (joint offsets are not parameters: see
            :meth:`offsets`; :meth:`write` puts them into the file where the format can hold them).
        notes: What the fit says of itself: no convergence, residuals inconsistent with the σ given (with the
            largest one's measurement).
    """

    mechanism: str
    frame: str
    unknowns: tuple[Unknown, ...]
    identifiability: Identifiability
    before: NDArray[np.float64]
    after: NDArray[np.float64]
    measurements: Measurements
    sigma: float
    iterations: int
    converged: bool
    calibrated: Mechanism
    notes: tuple[str, ...] = ()

    # ------------------------------------------------------------------------------------------ values
    def values(self) -> dict[str, float]:
        """The identified geometric parameters (m, rad)."""
        return {u.name: u.identified for u in self.unknowns if u.kind == "parameter"}

    def offsets(self) -> dict[str, float]:
        """The identified joint offsets (rad, m): the model's coordinate is the reading plus the offset."""
        return {u.name: u.identified for u in self.unknowns if u.kind == "joint offset"}

    def unknown(self, name: str) -> Unknown:
        return next(u for u in self.unknowns if u.name == name)

    @property
    def oriented(self) -> bool:
        return self.measurements.rotations is not None

    def statistics(self) -> dict[str, float]:
        """RMS and largest position error (m) before and after, and of the rotation error (rad) if measured."""
        out = {}
        for when, errors in (("before", self.before), ("after", self.after)):
            for what, block in (("position", errors[:, :3]), ("rotation", errors[:, 3:]))[:2 if self.oriented else 1]:
                size = np.linalg.norm(block, axis=1)
                out[f"rms_{what}_{when}"] = float(np.sqrt(np.mean(size**2)))
                out[f"max_{what}_{when}"] = float(size.max())
        return out

    def residuals(self) -> pd.DataFrame:
        """One row per measurement: ``label``, ``row`` (the file's line), the position error before and after
        (``dx_before`` … ``dr_before``, ``dr_after``, m) and, with orientations, ``rotation_before``,
        ``rotation_after`` (rad)."""
        import pandas as pd

        table: dict[str, object] = {"label": list(self.measurements.labels)}
        if self.measurements.rows:
            table["row"] = list(self.measurements.rows)
        for when, errors in (("before", self.before), ("after", self.after)):
            for k, axis in enumerate("xyz"):
                table[f"d{axis}_{when}"] = errors[:, k]
            table[f"dr_{when}"] = np.linalg.norm(errors[:, :3], axis=1)
            if self.oriented:
                table[f"rotation_{when}"] = np.linalg.norm(errors[:, 3:], axis=1)
        return pd.DataFrame(table)

    # ------------------------------------------------------------------------------------------ protocol
    def to_frame(self) -> pd.DataFrame:
        """One row per unknown: ``name``, ``kind``, ``unit``, ``nominal``, ``identified``, ``change``, ``std_error``
        (SI; NaN where it cannot be told apart) and ``identifiable``."""
        import pandas as pd

        unclear = {n for g in self.identifiability.groups for n in g}
        return pd.DataFrame([{"name": u.name, "kind": u.kind, "unit": u.unit, "nominal": u.nominal,
                              "identified": u.identified, "change": u.change,
                              "std_error": np.nan if u.std_error is None else u.std_error,
                              "identifiable": u.name not in unclear} for u in self.unknowns])

    def as_dict(self) -> dict:
        ident = self.identifiability
        return {"mechanism": self.mechanism, "frame": self.frame, "file": self.measurements.file,
                "measurements": len(self.measurements), "orientation": self.oriented,
                "unknowns": frame_records(self.to_frame()),
                "identifiability": {"rank": ident.rank, "unknowns": ident.unknowns,
                                    "condition_number": ident.condition if math.isfinite(ident.condition) else None,
                                    "cannot_be_told_apart": [list(g) for g in ident.groups],
                                    "singular_values": list(ident.singular_values)},
                "statistics": self.statistics(), "sigma": self.sigma, "iterations": self.iterations,
                "converged": self.converged, "notes": list(self.notes), "residuals": frame_records(self.residuals())}

    def plot(self, ax: Axes | None = None) -> Figure:
        """The position error |Δr| (mm) of every measurement with the nominal and with the calibrated model."""
        from ..report.figures import figure_axes, style_axes

        figure, ax = figure_axes(ax, max(6.0, 0.12 * len(self.measurements) + 3), 4.5)
        index = np.arange(len(self.measurements))
        width = 0.4
        ax.bar(index - width / 2, np.linalg.norm(self.before[:, :3], axis=1) * 1e3, width, label="nominal model")
        ax.bar(index + width / 2, np.linalg.norm(self.after[:, :3], axis=1) * 1e3, width, label="calibrated model")
        ax.set_xticks(index[:: max(1, len(index) // 25)])
        ax.set_xticklabels([self.measurements.labels[i] for i in index[:: max(1, len(index) // 25)]], rotation=90)
        style_axes(ax, "measurement (label)", "position error |Δr| (mm)",
                   f"{self.mechanism}: calibration residuals at {self.frame}", legend=True)
        return figure

    def report(self, mechanism: Mechanism | None = None, **context: object) -> Report:
        """The HTML report (:mod:`mechatron.report.html`): the identified unknowns, the method, the
        identifiability, the residuals of every measurement before and after, and their chart."""
        import sys

        import pandas as pd

        from ..report.html import Chart, Method, Report, Section, Table, Text

        ident = self.identifiability
        stats = pd.DataFrame([{"quantity": key, "value": value} for key, value in self.statistics().items()])
        solver = sys.modules.get("mechatron.accuracy.calibration")  # the module that ran it (it imports this one)
        apart = "; ".join(" and ".join(group) for group in ident.groups) or "none"
        summary = (f"rank {ident.rank} of {ident.unknowns}, condition number {ident.condition:.4g}; RMS position "
                   f"error {self.statistics()['rms_position_before'] * 1e3:.4g} mm → "
                   f"{self.statistics()['rms_position_after'] * 1e3:.4g} mm")
        sections = [
            Section("Unknowns", [Table(self.to_frame(), "nominal, identified, change and standard error (SI)",
                                       "unknowns")]),
            Section("Method", [Method(solver.__doc__)] if solver is not None and solver.__doc__ else []),
            Section("Identifiability", [Text(summary), Text(f"cannot be told apart: {apart}"),
                                        *(Text(f"note: {note}") for note in self.notes)]),
            Section("Residuals", [Table(stats, "RMS and largest error before and after (m, rad)", "statistics"),
                                  Table(self.residuals(), "every measurement (m, rad)", "residuals"),
                                  Chart(self.plot())]),
        ]
        return Report(str(self).splitlines()[0], sections, summary)

    def __str__(self) -> str:
        ident = self.identifiability
        stats = self.statistics()
        lines = [f"calibration of {self.mechanism} from {len(self.measurements)} measurements of {self.frame}"
                 f"{' (position and orientation)' if self.oriented else ' (position)'}"
                 + (f", {self.measurements.file}" if self.measurements.file else ""),
                 f"Levenberg–Marquardt: {self.iterations} iterations, "
                 f"{'converged' if self.converged else 'NOT converged (the step did not fall below its tolerance)'}",
                 "", f"{'unknown':<10} {'kind':<13} {'nominal':>12} {'identified':>12} {'change':>11} "
                 f"{'std error':>10}  unit"]
        for u in self.unknowns:
            nominal, unit = _shown(u.nominal, u.unit)
            identified, change = _shown(u.identified, u.unit)[0], _shown(u.change, u.unit)[0]
            error = "-" if u.std_error is None else readable(_shown(u.std_error, u.unit)[0])
            lines.append(f"{u.name:<10} {u.kind:<13} {readable(nominal, 7):>12} {readable(identified, 7):>12} "
                         f"{readable(change):>11} {error:>10}  {unit}")
        condition = readable(ident.condition) if math.isfinite(ident.condition) else "inf"
        lines += ["", f"identifiability: rank {ident.rank} of {ident.unknowns}, condition number {condition} "
                      "(Jacobian with unit-norm columns)"]
        for group in ident.groups:
            lines.append(f"  cannot be told apart: {' and '.join(group)} (minimum-norm change; no standard error)")
        lines += ["", "position error (mm)        RMS        max",
                  f"  nominal model      {stats['rms_position_before'] * 1e3:>10.4f} "
                  f"{stats['max_position_before'] * 1e3:>10.4f}",
                  f"  calibrated model   {stats['rms_position_after'] * 1e3:>10.4f} "
                  f"{stats['max_position_after'] * 1e3:>10.4f}"]
        if self.oriented:
            lines += ["rotation error (deg)", *(f"  {label:<18} {math.degrees(stats[f'rms_rotation_{w}']):>10.5f} "
                                               f"{math.degrees(stats[f'max_rotation_{w}']):>10.5f}"
                                               for label, w in (("nominal model", "before"),
                                                                ("calibrated model", "after")))]
        lines.append(f"σ̂ = {readable(self.sigma)} (the residuals over their σ: 1 when the σ given are right; "
                     "without σ columns, in mm)")
        table = self.residuals()
        shown = table.head(SHOWN_ROWS)
        lines += ["", "measurement        |Δr| nominal (mm)  |Δr| calibrated (mm)"]
        lines += [f"  {label:<16} {before * 1e3:>17.4f} {after * 1e3:>21.4f}"
                  for label, before, after in zip(shown["label"], shown["dr_before"], shown["dr_after"])]
        if len(table) > SHOWN_ROWS:
            lines.append(f"  … {len(table) - SHOWN_ROWS} more (--csv or --json for all)")
        lines += [f"note: {note}" for note in self.notes]
        return "\n".join(lines)

    # ------------------------------------------------------------------------------------------ the file
    def write(self, path: str | Path) -> list[Path]:
        """Write the calibrated mechanism (:func:`~mechatron.accuracy.calibrated_file.write_calibrated`): a robot
        file (.toml) of a DH arm, a mechanism file (.toml) of a linkage, or a URDF (.urdf)."""
        from .calibrated_file import write_calibrated

        header = (f"Calibrated by mechatron calibrate from {self.measurements.file or 'measurements'} "
                  f"({len(self.measurements)} rows); RMS position error "
                  f"{self.statistics()['rms_position_before'] * 1e3:.4g} mm -> "
                  f"{self.statistics()['rms_position_after'] * 1e3:.4g} mm.")
        return write_calibrated(self.calibrated, self.offsets(), path, header)
