"""What the sizing of one driven coordinate reports: the base of
:class:`~mechatron.drives.sizing.JointSizing` (motor and converter) and
:class:`~mechatron.drives.cylinders.CylinderSizing` (hydraulic cylinder).

Both follow the result protocol (:class:`~mechatron.report.result.Result`): ``to_frame()`` is one row per check
(SI units, the ``unit`` column names the unit of ``value`` and ``limit``), ``str()`` the check table printed by
``mechatron size`` (speeds in rpm and pressures in MPa there, for people), ``plot()`` the chosen drive's chart.
"""

from __future__ import annotations

import math
from abc import abstractmethod
from typing import TYPE_CHECKING

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
        """The text report as lines: the drive, every check with value, limit, margin and PASS/FAIL, and when no
        drive is feasible the closest candidates with the checks they fail (load factor = value/limit)."""
        head = self.headline()
        lines = [head if self.feasible else f"{head}  — NO FEASIBLE DRIVE; the closest one shown"]
        lines.append(f"    {'check':<32}{'value':>11}{'limit':>11}  {'unit':<6}{'margin':>8}  result")
        for c in self.checks:
            value, limit, unit = shown(c)
            lines.append(f"    {c.name:<32}{value:>11}{limit:>11}  {unit:<6}{c.margin:>8.1%}  "
                         f"{'PASS' if c.passed else 'FAIL'}")
        if not self.feasible:
            lines.append("    closest candidates and the checks they fail (load factor = value/limit):")
            lines += [f"      {self.candidate(row)}: {row['failed']}" for row in self.closest.to_dict(orient="records")]
        return lines

    def __str__(self) -> str:
        return "\n".join(self.lines())

    def smallest_margin(self) -> float:
        """The smallest margin over the checks (< 0: a check fails)."""
        return min((c.margin for c in self.checks), default=math.inf)
