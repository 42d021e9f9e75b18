"""What the sizing of one driven coordinate reports: the base of
:class:`~mechatron.drives.sizing.JointSizing` (motor and converter) and
:class:`~mechatron.drives.cylinders.CylinderSizing` (hydraulic cylinder).

Both follow the result protocol (:class:`~mechatron.report.result.Result`): ``to_frame()`` is one row per check
(SI units, the ``unit`` column names the unit of ``value`` and ``limit``), ``str()`` the check table printed by
``mechatron size`` (speeds in rpm and pressures in MPa there, for people), ``plot()`` the chosen drive's chart and
``chart_frame()`` that chart's data.

Both explain the choice (:meth:`DriveSizing.explanation`): the deciding check (the smallest margin), the runners-up
with why they lost — a check they fail, or the objective (heavier, costlier, less margin) — and the drive's mass and
price.
"""

from __future__ import annotations

import math
from abc import abstractmethod
from collections.abc import Callable
from dataclasses import MISSING
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from ..report.result import Result
from .checks import Check

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd

    from .duty import JointDuty

#: rad/s → rpm.
RPM = 60 / (2 * math.pi)
#: Number of alternatives (and of closest pairs when none is feasible) kept in reports.
REPORTED = 5
#: The columns of a sizing table (:meth:`DriveSizing.to_frame`): one row per check.
COLUMNS = ("joint", "motor", "converter", "ratio", "check", "value", "limit", "unit", "margin", "pass")
#: Runners-up reported of each kind: the nearest better-ranked candidates that fail a check, the next feasible ones.
RUNNERS_UP = 2
#: The columns of a chart's data (:meth:`DriveSizing.chart_frame`) by the kind of coordinate: speed, force (a
#: cylinder's: :meth:`~mechatron.drives.cylinders.CylinderSizing.chart_frame`, per cylinder).
CHART_COLUMNS = {"revolute": ("speed_rad_s", "torque_Nm"), "prismatic": ("speed_m_s", "force_N")}


class Later:
    """A value made when first read: ``function(*args)`` (a module-level function and picklable arguments, so that
    a result holding it pickles)."""

    def __init__(self, function: Callable[..., Any], *args: Any):
        self.function, self.args = function, args

    def __call__(self) -> Any:
        return self.function(*self.args)


class Deferred:
    """A dataclass field that may be given a :class:`Later`: its value is made when the field is first read, then
    kept, so that a result builds the tables (DataFrames, catalog rows) no caller asks for never. Without
    ``default`` the field is a required one."""

    def __init__(self, default: Any = MISSING):
        self.default = default

    def __set_name__(self, owner: type, name: str) -> None:
        self.name = name

    def __get__(self, obj: Any, owner: type | None = None) -> Any:
        if obj is None:  # the dataclass asks for the default
            if self.default is MISSING:
                raise AttributeError(self.name)
            return self.default
        value = obj.__dict__[self.name]
        if isinstance(value, Later):
            value = obj.__dict__[self.name] = value()
        return value

    def __set__(self, obj: Any, value: Any) -> None:
        obj.__dict__[self.name] = value


def shown(check: Check) -> tuple[str, str, str]:
    """A check's value, limit and unit as shown to people: speeds in rpm, pressures in MPa."""
    value, limit, unit = check.value, check.limit, check.unit
    if unit == "rad/s":
        value, limit, unit = value * RPM, limit * RPM, "rpm"
    elif unit == "Pa":
        value, limit, unit = value / 1e6, limit / 1e6, "MPa"
    return f"{value:.4g}", f"{limit:.4g}", unit


class DriveSizing(Result):
    """The chosen drive of one coordinate (or the closest one when none is feasible) with every check.

    Subclasses are dataclasses with ``joint``, ``feasible``, ``checks`` (a list of
    :class:`~mechatron.drives.checks.Check`), ``closest`` (a DataFrame with a ``failed`` column) and ``duty``
    (:class:`~mechatron.drives.duty.JointDuty`), and say how the drive is named (:meth:`drive_columns`,
    :meth:`headline`, :meth:`candidate`).
    """

    joint: str
    feasible: bool
    checks: list[Check]
    closest: pd.DataFrame
    duty: JointDuty

    @abstractmethod
    def drive_columns(self) -> dict:
        """The drive's motor, converter and ratio as the table shows them."""

    @abstractmethod
    def headline(self) -> str:
        """The first line of the text report: the joint and its drive."""

    @abstractmethod
    def candidate(self, row: dict) -> str:
        """The name of one of the closest candidates (a row of ``closest``)."""

    @property
    def failed(self) -> list[Check]:
        """The checks the drive fails."""
        return [c for c in self.checks if not c.passed]

    def rows(self) -> list[dict]:
        """One dict per check: joint, motor, converter, ratio, check, value, limit, unit, margin, pass."""
        head = {"joint": self.joint, **self.drive_columns()}
        return [{**head, **{("check" if k == "name" else k): v for k, v in c.as_dict().items()}} for c in self.checks]

    def to_frame(self) -> pd.DataFrame:
        """One row per check (:data:`COLUMNS`): value and limit in SI, in the row's ``unit``; margin = 1 −
        value/limit."""
        import pandas as pd

        return pd.DataFrame(self.rows(), columns=list(COLUMNS))

    def lines(self) -> list[str]:
        """The text report as lines: the drive, every check with value, limit, margin and PASS/FAIL (a pass/fail
        filter, :meth:`is_filter`, says ``filter`` for its margin; a limit with a count, how many times it is
        allowed), and when no drive is feasible the closest candidates with the checks they fail (load factor =
        value/limit)."""
        head = self.headline()
        lines = [head if self.feasible else f"{head}  — NO FEASIBLE DRIVE; the closest one shown"]
        lines.append(f"    {'check':<32}{'value':>11}{'limit':>11}  {'unit':<6}{'margin':>8}  result")
        for c in self.checks:
            value, limit, unit, margin = self.cells(c)
            lines.append(f"    {c.name:<32}{value:>11}{limit:>11}  {unit:<6}{margin:>8}  "
                         f"{'PASS' if c.passed else 'FAIL'}"
                         + ("" if c.count is None else f"  (allowed {c.count:,.0f} times in its life)"))
        if not self.feasible:
            lines.append("    closest candidates and the checks they fail (load factor = value/limit):")
            lines += [f"      {self.candidate(row)}: {row['failed']}" for row in self.closest.to_dict(orient="records")]
            lines += [f"    {note}" for note in self.closest_notes()]
        return lines + self.explanation_lines()

    def cells(self, check: Check) -> tuple[str, str, str, str]:
        """A check's value, limit, unit (:func:`shown`) and margin as the text table shows them (a pass/fail filter,
        :meth:`is_filter`, says ``filter`` for its margin)."""
        return *shown(check), "filter" if self.is_filter(check) else self.margin_text(check)

    def margin_text(self, check: Check) -> str:
        """A check's margin in words: a percentage."""
        return f"{check.margin:.1%}"

    def closest_notes(self) -> list[str]:
        """Lines after the closest candidates of an infeasible coordinate: how they were ranked where it is not
        plainly by their worst load factor (none here)."""
        return []

    def __str__(self) -> str:
        return "\n".join(self.lines())

    def is_filter(self, check: Check) -> bool:
        """Whether ``check`` is a pass/fail filter whose margin is no load margin (a cylinder's rated pressure and
        stroke: :meth:`CylinderSizing.is_filter <mechatron.drives.cylinders.CylinderSizing.is_filter>`); none of a
        motor's."""
        return False

    def smallest_margin(self) -> float:
        """The smallest margin over the checks (< 0: a check fails)."""
        return min((c.margin for c in self.checks), default=math.inf)

    # ------------------------------------------------------------------------------------- the explanation
    def choice(self) -> str:
        """The drive as one name: ``motor + converter`` (a cylinder: its key)."""
        columns = self.drive_columns()
        return " + ".join(str(columns[k]) for k in ("motor", "converter") if columns.get(k) is not None)

    def deciding(self) -> Check | None:
        """The check with the smallest margin: the one that decided (or, when it fails, rules out) the drive."""
        return min(self.checks, key=lambda c: c.margin, default=None)

    def binding_sample(self) -> tuple[int, str]:
        """(k, what): the sample of :attr:`duty` where the drive is most loaded, the largest |τ| of its coordinate
        (a torque, N·m, for an angle; a force, N, for a length), and what it carries there, as words."""
        k = int(np.argmax(np.abs(self.duty.torque)))
        value = abs(float(self.duty.torque[k]))
        what = f"|τ| = {value:.4g} N·m" if self.duty.kind == "revolute" else f"|F| = {value:.4g} N"
        return k, f"carries its largest {what}"

    def drive_mass(self) -> float | None:
        """The drive's mass (kg): the chosen row of the ranking; ``None`` when unknown."""
        ranking = getattr(self, "ranking", None)
        return float(ranking["mass"].iloc[0]) if self.feasible and ranking is not None and len(ranking) else None

    def drive_price(self) -> float | None:
        """The drive's price (the catalog's currency); ``None`` when unknown."""
        ranking = getattr(self, "ranking", None)
        return float(ranking["price"].iloc[0]) if self.feasible and ranking is not None and len(ranking) else None

    def shaft_power(self) -> NDArray[np.float64]:
        """The power the drive delivers at every sample (W): force × speed of the coordinate (a motor: its shaft,
        :meth:`~mechatron.drives.sizing.JointSizing.shaft_power`); < 0 when the load drives it back."""
        return self.duty.torque * self.duty.speed

    def runner_up(self) -> list[dict]:
        """The candidates that came nearest, and why they lost: the nearest ones ranked before the drive by the
        objective that fail a check (``lost_on`` ``"check"``), then the next feasible ones (``lost_on``
        ``"objective"``: heavier, costlier or with less margin); when nothing is feasible, the next closest ones
        with the checks they fail. Each: candidate, the ranking's columns (motor, converter, ratio or cylinder;
        mass in kg, price), lost_on, reason."""
        out = []
        rivals = getattr(self, "rivals", None)
        ranking = getattr(self, "ranking", None)
        if not self.feasible:
            return [self._runner(row, "check", f"fails {row['failed']}")
                    for row in self.closest.iloc[1:1 + RUNNERS_UP].to_dict(orient="records")]
        best = ranking.iloc[0].to_dict() if ranking is not None and len(ranking) else {}
        if rivals is not None and len(rivals) and best:
            out += [self._runner(row, "check", f"{self._better(row, best)} but fails {row['failed']}")
                    for row in rivals.iloc[:RUNNERS_UP].to_dict(orient="records")]
        if ranking is not None and len(ranking) > 1:
            out += [self._runner(row, "objective", self._worse(row, best))
                    for row in ranking.iloc[1:1 + RUNNERS_UP].to_dict(orient="records")]
        return out

    def _runner(self, row: dict, lost_on: str, reason: str) -> dict:
        keep = {k: row[k] for k in ("motor", "converter", "kind", "ratio", "cylinder", "mass", "price") if k in row}
        return {"candidate": self.candidate(row), **keep, "lost_on": lost_on, "reason": reason}

    def _keys(self, row: dict, best: dict) -> tuple[str, str]:
        """The ranking column that tells ``row`` from ``best`` (the objective's, else the tie-break) and its unit."""
        first, second = ("price", "mass") if getattr(self, "objective", "mass") == "cost" else ("mass", "price")
        key = first if row[first] != best[first] else second
        return key, " kg" if key == "mass" else ""

    def _better(self, row: dict, best: dict) -> str:
        """What a candidate ranked before the chosen one has for it by the objective."""
        key, unit = self._keys(row, best)
        if row[key] == best[key]:
            return f"as light and as cheap ({row['mass']:.4g} kg, {row['price']:.4g})"
        return f"{'lighter' if key == 'mass' else 'cheaper'} ({row[key]:.4g}{unit} against {best[key]:.4g}{unit})"

    def _worse(self, row: dict, best: dict) -> str:
        """How a feasible candidate ranks behind the chosen one by the objective."""
        if getattr(self, "objective", "mass") == "margin":
            return f"less margin: {row['smallest_margin']:.1%} against {best['smallest_margin']:.1%}"
        key, unit = self._keys(row, best)
        if row[key] == best[key]:
            return f"as light and as cheap ({row['mass']:.4g} kg, {row['price']:.4g}): a tie, ranked by catalog order"
        return f"{'heavier' if key == 'mass' else 'costlier'}: {row[key]:.4g}{unit} against {best[key]:.4g}{unit}"

    def explanation(self) -> dict:
        """deciding_check (the check with the smallest margin, as in ``checks``), runner_up (:meth:`runner_up`),
        drive_mass_kg and drive_price (``None`` when unknown)."""
        deciding = self.deciding()
        return {"deciding_check": deciding.as_dict() if deciding else None, "runner_up": self.runner_up(),
                "drive_mass_kg": self.drive_mass(), "drive_price": self.drive_price()}

    def explanation_lines(self) -> list[str]:
        """The deciding check and the runners-up, as text lines."""
        deciding = self.deciding()
        lines = [f"    deciding check: {deciding.name}, margin {self.margin_text(deciding)}"] if deciding else []
        lines += [f"    runner-up {row['candidate']}: {row['reason']}" for row in self.runner_up()]
        return lines

    # ------------------------------------------------------------------------------------ the chart's data
    def chart_frame(self) -> pd.DataFrame:
        """The data of :meth:`plot` as a table: one row per point, ``series`` (here ``operating point``), ``t_s``
        (s) and the coordinate's speed and force in SI (``speed_m_s``, ``force_N`` or ``speed_rad_s``,
        ``torque_Nm``)."""
        import pandas as pd

        speed, force = CHART_COLUMNS.get(self.duty.kind, CHART_COLUMNS["revolute"])
        return pd.DataFrame({"series": "operating point", "t_s": self.duty.t, speed: self.duty.speed,
                             force: self.duty.torque})
