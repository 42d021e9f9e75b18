r"""Hydraulic cylinders of a closed-loop mechanism chosen from a catalog.

For a cylinder coordinate with force F(t) (N, > 0 pushes: extends the cylinder), speed v(t) (m/s) and pin-to-pin
length L(t) (m) shared by ``count`` cylinders side by side, a hydraulic system of relief pressure p_s, and a
catalog cylinder of bore D, rod d (piston area A_p = π D²/4, annulus A_a = A_p − π d²/4) and rated pressure p_r,
each check a value against a limit (load factor = value/limit, margin = 1 − value/limit):

- rated pressure  p_s ≤ p_r: the relief pressure reaches the cylinder whenever the pump works against it (at a
  stroke end, when the load stalls), whatever the task's forces. A **filter** (:data:`FILTERS`): a row passes or
  fails it; its "margin" 1 − p_s/p_r says how far the rating is above the system, not how much load the cylinder
  could still take, and it is 0 for every row rated at the system pressure — so it never decides a feasible
  cylinder (:meth:`CylinderSizing.deciding`);
- push pressure   p = max F⁺ / (count A_p)  ≤ min(p_r, p_s), the pose of the largest push;
- pull pressure   p = max F⁻ / (count A_a)  ≤ the same, the pose of the largest pull;
- stroke          L_max − L_min ≤ the catalog's maximum stroke. A **filter** too: the task's stroke fits the row
  or not; its "margin" is the fraction of the row's longest stroke left, no load the cylinder could still take;
- rod buckling    at every pose, F⁺/count ≤ F_E(L) / S with F_E(L) = π² E (π d⁴/64) / (K L)² (Euler, buckling length
  K L with the end fixing's factor K, :mod:`mechatron.drives.shafts`; the whole cylinder taken as a rod of
  diameter d — the makers' conservative simplification), S = 3.5. Reported at the pose of the largest F⁺ (K L)²,
  the largest load factor (value: the force there, limit: the allowed force at that length). Without the lengths
  of the task, every pose is taken fully extended (L = L_max).

The push, pull and buckling checks are load checks: p = F/A is linear in the force, so their margin is the fraction
of the force the cylinder could still carry at that pose (1 − F/(p_lim A), 1 − F/(F_E/S)). These three are the
checks that can bind (:data:`BINDING`): the deciding check of a feasible cylinder is the one of them with the
smallest margin, and its smallest margin (the ``margin`` objective's score) is taken over them; a cylinder that fails
a check is decided by its worst one, the filters included. Each binds at a pose of the task
(:meth:`CylinderSizing.binding_sample`): the largest push, the largest pull, the largest F⁺ (K L)².

The end fixing is the catalog row's (``end_fixing``, default pinned at both ends: an eye or clevis at each end) or
the one given to :func:`size_cylinder`. Each cylinder says whether its bore and rod belong to the metric series of
[ISO 3320] (:data:`ISO_3320_BORES`, :data:`ISO_3320_RODS`). The feasible cylinders are ranked by mass
(``mass + mass_per_stroke · stroke``), cost or margin; the rows ranked before the chosen one (lighter; cheaper for
``cost``) fail a check, and are reported with the checks they fail and their load factors
(:attr:`CylinderSizing.rivals`). The flow a cylinder takes, Q(t) = count · (A_p v⁺ + A_a v⁻) (m³/s), the pressure
its load needs, p(t) = max(F v, 0) / Q(t) ≤ p_s (:meth:`CylinderSizing.pressure_needed`), and the pump flow and
hydraulic power over the cycle are in :mod:`mechatron.drives.hydraulics`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from ..model.mechanism import Cylinder
from ..report.result import json_ready
from .checks import PASS_TOLERANCE, Check, _load_factor, failures
from .duty import JointDuty
from .options import PRESSURE
from .report import REPORTED, DriveSizing
from .shafts import END_FIXINGS, STEEL_MODULUS, end_fixing, euler_load, fixing_factors

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..dynamics.motion import Trajectory
    from ..model.mechanism import Mechanism

BUCKLING_SAFETY = 3.5
CYLINDER_CHECKS = ("rated pressure", "push pressure", "pull pressure", "stroke", "rod buckling")
CYLINDER_UNITS = ("Pa", "Pa", "Pa", "m", "N")
#: The pass/fail filters among :data:`CYLINDER_CHECKS`: satisfied or not by the catalog row and the task's stroke,
#: whatever the load; never the deciding check of a feasible cylinder (the module docstring).
FILTERS = ("rated pressure", "stroke")
#: The checks that can bind: the load checks (push and pull pressure, rod buckling).
BINDING = tuple(name for name in CYLINDER_CHECKS if name not in FILTERS)
_BINDING = [CYLINDER_CHECKS.index(name) for name in BINDING]
#: The cylinder bores of [ISO 3320] (mm): the preferred ones (the R10 series) and, in brackets in the standard,
#: the non-preferred 90, 110, 140, 180, 220, 280, 360 and 450.
ISO_3320_BORES = (8, 10, 12, 16, 20, 25, 32, 40, 50, 63, 80, 90, 100, 110, 125, 140, 160, 180, 200, 220, 250, 280,
                  320, 360, 400, 450, 500)
#: The piston rod diameters of [ISO 3320] (mm): the R20 series from 4 to 360 mm.
ISO_3320_RODS = (4, 5, 6, 8, 10, 12, 14, 16, 18, 20, 22, 25, 28, 32, 36, 40, 45, 50, 56, 63, 70, 80, 90, 100, 110,
                 125, 140, 160, 180, 200, 220, 250, 280, 320, 360)


def iso_3320(bore: ArrayLike, rod: ArrayLike) -> NDArray[np.bool_]:
    """Whether a bore D and rod d (m) both belong to the series of [ISO 3320] (to 1 µm)."""
    def member(diameter: ArrayLike, series: tuple[int, ...]) -> NDArray[np.bool_]:
        mm = np.asarray(diameter, dtype=float) * 1e3
        return np.isin(np.round(mm, 3), np.asarray(series, dtype=float))

    return member(bore, ISO_3320_BORES) & member(rod, ISO_3320_RODS)


def cylinder_lengths(mech: Mechanism, trajectory: Trajectory) -> dict[str, NDArray[np.float64] | None]:
    """The pin-to-pin length L(t) (m) of every hydraulic cylinder of ``mech`` along a trajectory of its actuated
    coordinates (None for a cylinder that is not one of them)."""
    q = np.atleast_2d(np.asarray(trajectory.q, dtype=float))
    actuated = list(mech.actuated) if mech.closures else []
    return {name: q[:, actuated.index(name)].copy() if name in actuated and q.shape[1] == len(actuated) else None
            for name in mech.cylinders}



def cylinder_areas(bore: ArrayLike, rod: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The piston area A₁ = π D²/4 and the annulus area A₂ = π (D² − d²)/4 (m²) of a cylinder of bore D and rod d
    (m; arrays of rows alike): the push force is p A₁, the pull force p A₂."""
    bore, rod = np.asarray(bore, dtype=float), np.asarray(rod, dtype=float)
    piston = math.pi * bore**2 / 4
    return piston, piston - math.pi * rod**2 / 4

@dataclass
class CylinderSizing(DriveSizing):
    """The chosen catalog cylinder of one cylinder coordinate (or the closest one when none is feasible), a result:
    its table is one row per check, its chart the force per cylinder over the speed with the push and pull limits.

    Attributes:
        joint: the cylinder coordinate's name.
        objective: how the feasible cylinders were ranked (``mass``, ``cost``, ``margin``).
        feasible: whether any catalog cylinder passes every check.
        cylinder, count: the chosen cylinder's key and how many work side by side.
        checks: rated, push and pull pressure (Pa), stroke (m), rod buckling (N).
        peak_flow: Q = count · max(A_p v⁺, A_a v⁻) (m³/s).
        ranking: the feasible cylinders, best first (cylinder, bore, rod, iso_3320, mass, price, smallest margin
            over the checks that can bind (:data:`BINDING`), peak flow, score).
        closest: the cylinders with the smallest worst load factor and the checks they fail.
        rivals: the catalog rows ranked before the chosen one by the objective (lighter for ``mass``, cheaper for
            ``cost``), all of which fail a check, nearest first: cylinder, bore, rod (m), iso_3320, mass (kg) and
            price (× count), worst_load_factor and ``failed`` (``check ×load factor``, ``; ``-joined); empty for
            the ``margin`` objective and when nothing is feasible.
        duty: the coordinate's duty: force (N, > 0 pushes) and speed (m/s) over time.
        cylinder_data: the chosen cylinder's catalog data (SI).
        pressure: the system's relief pressure (Pa).
        end_fixing: the end fixing of the buckling check (a key of :data:`~mechatron.drives.shafts.END_FIXINGS`,
            or ``"K = …"`` for a factor given as a number).
        buckling_length: K L at the pose that decides the buckling check (m).
        length: the pin-to-pin length L(t) along the task (m), if known.
        fixing_factor: the end fixing's effective-length factor K of the chosen row.
    """

    joint: str
    objective: str
    feasible: bool
    cylinder: str
    count: int
    checks: list[Check]
    peak_flow: float
    ranking: pd.DataFrame
    closest: pd.DataFrame
    duty: JointDuty
    cylinder_data: dict
    pressure: float = PRESSURE
    end_fixing: str = "pinned-pinned"
    buckling_length: float = math.nan
    length: NDArray[np.float64] | None = None
    rivals: pd.DataFrame = field(default_factory=pd.DataFrame)
    fixing_factor: float = 1.0

    kind = "cylinder"

    @property
    def areas(self) -> tuple[float, float]:
        """(A_p, A_a): the chosen cylinder's piston area π D²/4 and annulus area A_p − π d²/4 (m²)
        (:func:`cylinder_areas`)."""
        piston, annulus = cylinder_areas(self.cylinder_data["bore"], self.cylinder_data["rod"])
        return float(piston), float(annulus)

    @property
    def standard(self) -> bool:
        """Whether the chosen cylinder's bore and rod belong to the series of [ISO 3320]."""
        return bool(iso_3320(self.cylinder_data["bore"], self.cylinder_data["rod"]))

    def flow(self) -> NDArray[np.float64]:
        """Q(t) = count · (A_p v⁺ + A_a v⁻) (m³/s): the oil the cylinders take in along the task (the piston side
        when extending, the rod side when retracting)."""
        piston, annulus = self.areas
        v = self.duty.speed
        return self.count * np.where(v > 0, piston * v, -annulus * v)

    def pressure_needed(self, relief: float | None = None) -> NDArray[np.float64]:
        r"""p(t) (Pa): the pressure the pump must give the cylinders' inlet side to move their load, at every sample.

        Extending (v > 0) the oil enters the piston side, p = F / (count A_p) where the cylinders push (F > 0);
        retracting (v < 0) it enters the rod side, p = −F / (count A_a) where they pull (F < 0) — in both
        p Q = F v. Where the load drives the cylinder (F v < 0: gravity lowering the load, a push while retracting)
        a counterbalance (meter-out) valve on the outlet side holds the load and the pump only fills the inlet
        side, at no pressure: p = 0; standing still (v = 0) no oil flows, p = 0. At most the relief pressure
        ``relief`` (default :attr:`pressure`). So p(t) Q(t) = min(max(F v, 0), p_s Q(t)), the power the cylinders
        deliver to their load (lossless: no friction in the cylinders and no back pressure on the outlet)."""
        relief = self.pressure if relief is None else relief
        piston, annulus = self.areas
        v, force = self.duty.speed, self.duty.torque
        area = self.count * np.where(v > 0, piston, annulus)
        load = np.where(v > 0, force, np.where(v < 0, -force, 0.0))
        return np.minimum(np.maximum(load, 0.0) / area, relief)

    def is_filter(self, check: Check) -> bool:
        """Whether ``check`` is a pass/fail filter (:data:`FILTERS`: the rated pressure and the stroke), not a check
        that binds."""
        return check.name in FILTERS

    def _pool(self) -> list[Check]:
        """The checks the deciding check and the smallest margin are taken over: those that can bind
        (:data:`BINDING`) when every check passes, else every check (a failing filter decides too)."""
        return self.checks if self.failed else [c for c in self.checks if not self.is_filter(c)]

    def deciding(self) -> Check | None:
        """The check that binds: the smallest margin among the push and pull pressure and rod buckling checks (the
        rated pressure and the stroke, filters, never decide a feasible cylinder); when a check fails, the worst
        one."""
        return min(self._pool(), key=lambda c: c.margin, default=None)

    def smallest_margin(self) -> float:
        """The smallest margin over the checks that can bind (< 0: a check fails, the filter included)."""
        return min((c.margin for c in self._pool()), default=math.inf)

    def binding_sample(self) -> tuple[int, str]:
        """(k, what): the sample where the deciding check (:meth:`deciding`) binds — the largest push F⁺ (push
        pressure), the largest pull F⁻ (pull pressure), the largest F⁺ (K L)² (rod buckling, L the pin-to-pin length
        there) — and the force per cylinder there, as words (N; for ``count`` > 1 also the total); for a deciding
        filter (an infeasible row), the largest |F|."""
        force = self.duty.torque
        deciding = self.deciding()
        name = deciding.name if deciding is not None else ""
        length = self.length if self.length is not None else np.ones_like(force)
        k = {"push pressure": lambda: np.argmax(force), "pull pressure": lambda: np.argmin(force),
             "rod buckling": lambda: np.argmax(np.maximum(force, 0.0) * length**2)}.get(
                 name, lambda: np.argmax(np.abs(force)))()
        k = int(k)
        total = float(force[k])
        kind = "push" if total > 0 else "pull" if total < 0 else "no"
        what = f"{kind} force F = {abs(total) / self.count:.6g} N per cylinder"
        if self.count > 1:
            what += f" ({abs(total):.6g} N for the {self.count} together)"
        if self.length is not None:
            what += f" at L = {self.length[k]:.4g} m"
        return k, (f"binds ({name}, margin {deciding.margin:.1%}): " if deciding is not None else "") + what

    def explanation(self) -> dict:
        """The explanation of :class:`~mechatron.drives.report.DriveSizing` and ``rejected``: the rows of
        :attr:`rivals` (each lighter, or cheaper, row that was rejected and the checks it fails)."""
        return {**super().explanation(), "rejected": self.rivals.to_dict(orient="records")}

    def explanation_lines(self) -> list[str]:
        """The deciding check, the rejected rows ranked before the chosen one (the nearest
        :data:`~mechatron.drives.report.REPORTED`, with the checks they fail and by how much) and the next feasible
        ones."""
        deciding = self.deciding()
        lines = []
        if deciding is not None:
            kind = "" if self.failed else " (the smallest load margin; the rated pressure and the stroke are " \
                "pass/fail filters)"
            lines.append(f"    deciding check: {deciding.name}, margin {deciding.margin:.1%}{kind}")
        if len(self.rivals):
            what = "cheaper" if self.objective == "cost" else "lighter"
            lines.append(f"    {what} rows rejected, nearest first (load factor = value/limit of each check "
                         "failed):")
            lines += [f"      {row['cylinder']} ({row['mass']:.4g} kg, price {row['price']:.4g}): {row['failed']}"
                      for row in self.rivals.head(REPORTED).to_dict(orient="records")]
            if len(self.rivals) > REPORTED:
                lines.append(f"      and {len(self.rivals) - REPORTED} {what} ones more (--json: rejected)")
        elif self.feasible and self.objective != "margin":
            lines.append(f"    no {'cheaper' if self.objective == 'cost' else 'lighter'} row in the catalog")
        runners = [r for r in self.runner_up() if r["lost_on"] == "objective" or not self.feasible]
        return lines + [f"    runner-up {row['candidate']}: {row['reason']}" for row in runners]

    def drive_columns(self) -> dict:
        return {"motor": None, "converter": self.cylinder, "ratio": None}

    def headline(self) -> str:
        c = self.cylinder_data
        series = "ISO 3320" if self.standard else "not of the ISO 3320 series"
        shared = "" if self.count == 1 else f" side by side, each checked with 1/{self.count} of the force"
        return (f"{self.joint}: cylinder {self.cylinder} ×{self.count}{shared} (bore {c['bore'] * 1e3:g} mm, rod "
                f"{c['rod'] * 1e3:g} mm, {series}; {self.end_fixing}), peak flow {self.peak_flow * 6e4:.1f} l/min"
                + ("" if self.count == 1 else f" (all {self.count}); forces below per cylinder"))

    def candidate(self, row: dict) -> str:
        return str(row["cylinder"])

    def as_dict(self) -> dict:
        """joint, kind, feasible, motor/gearbox/ratio (None), cylinder, count, bore and rod (m), iso_3320,
        pressure (Pa), end_fixing, buckling_length (m), peak_flow (m³/s) and peak_flow_l_min, checks (SI; each with
        ``filter``: true for the rated pressure and the stroke, pass/fail filters), alternatives, closest (when none
        is feasible) and the explanation (:meth:`explanation`): deciding_check, runner_up, rejected, drive_mass_kg,
        drive_price."""
        return json_ready({
            "joint": self.joint, "kind": "cylinder", "feasible": self.feasible, "motor": None, "gearbox": None,
            "ratio": None, "cylinder": self.cylinder, "count": self.count,
            "bore": self.cylinder_data["bore"], "rod": self.cylinder_data["rod"], "iso_3320": self.standard,
            "pressure": self.pressure, "end_fixing": self.end_fixing, "buckling_length": self.buckling_length,
            "peak_flow": self.peak_flow, "peak_flow_l_min": self.peak_flow * 60e3,
            "checks": [{**c.as_dict(), "filter": self.is_filter(c)} for c in self.checks],
            "alternatives": self.ranking.head(REPORTED).to_dict(orient="records"),
            "closest": [] if self.feasible else self.closest.to_dict(orient="records"), **self.explanation()})

    def buckling_limit(self) -> NDArray[np.float64]:
        """The push force per cylinder the rod may carry at every sample (N): F_E(L(t)) / S =
        π² E (π d⁴/64) / (K L(t))² / 3.5, L(t) the pin-to-pin length there (fully extended, L_max, where the task's
        lengths are unknown)."""
        length = self.length if self.length is not None else np.full(len(self.duty.t), self.buckling_length
                                                                     / self.fixing_factor)
        return euler_load(self.cylinder_data["rod"], length, self.fixing_factor, STEEL_MODULUS) / BUCKLING_SAFETY

    def chart_frame(self) -> pd.DataFrame:
        """The data of :meth:`plot`, one row per point (SI): ``series`` — ``operating point`` (every sample of the
        task: ``t_s`` (s), the cylinder speed and the force of one cylinder, F/``count``, signed, + pushes) and
        ``rod buckling limit`` (F_E(L)/3.5 at each sample, :meth:`buckling_limit`) —, ``speed_m_s`` (m/s) and
        ``force_per_cylinder_N`` (N: what one catalog cylinder carries, as the checks take it)."""
        n = len(self.duty.t)
        return pd.DataFrame({"series": ["operating point"] * n + ["rod buckling limit"] * n,
                             "t_s": np.tile(self.duty.t, 2), "speed_m_s": np.tile(self.duty.speed, 2),
                             "force_per_cylinder_N": np.concatenate([self.duty.torque / self.count,
                                                                     self.buckling_limit()])})

    def plot(self, ax: Axes | None = None) -> Figure:
        """The force per cylinder (the coordinate's force / ``count``) over the cylinder speed along the task,
        coloured by time (the colour bar), with the push limit p A_p and the pull limit −p A_a at the pressure of
        the push-pressure check and the rod's buckling limit F_E(L)/3.5 at every pose (:meth:`buckling_limit`: one
        mark above each operating point); force in kN, speed in m/s."""
        from ..report.figures import figure_axes, style_axes, time_colour_bar

        figure, ax = figure_axes(ax, 7.5, 5)
        push = next(x for x in self.checks if x.name == "push pressure")
        piston, annulus = self.areas
        each = "force per cylinder" if self.count == 1 else f"force per cylinder (1/{self.count} of the total)"
        points = ax.scatter(self.duty.speed, self.duty.torque / self.count / 1e3, s=6, c=self.duty.t,
                            cmap="viridis", label=f"{each} along the task (colour: time)")
        time_colour_bar(ax, points)
        ax.axhline(push.limit * piston / 1e3, color="tab:red", label="push limit p·A_piston")
        ax.axhline(-push.limit * annulus / 1e3, color="tab:purple", label="pull limit p·A_annulus")
        ax.scatter(self.duty.speed, self.buckling_limit() / 1e3, s=8, marker="_", color="tab:orange",
                   label="rod buckling limit F_E(L)/3.5 at each pose")
        style_axes(ax, "cylinder speed (m/s)", "force per cylinder (kN, + pushes)",
                   f"{self.joint}: {self.count}× {self.cylinder}" + ("" if self.feasible else " — NOT FEASIBLE"),
                   legend=True)
        return figure


def _fixings(catalog: pd.DataFrame, given: str | float | None) -> tuple[NDArray[np.float64], list[str]]:
    """(K, name) of the end fixing of every catalog row: ``given`` (a name or a factor K > 0) for all, else the
    row's ``end_fixing`` (default pinned at both ends)."""
    if given is None:
        names = catalog["end_fixing"].tolist() if "end_fixing" in catalog else [""] * len(catalog)
        factors, _ = fixing_factors(names)
        return factors, [end_fixing(n) if isinstance(n, str) and n.strip() else "pinned-pinned" for n in names]
    if isinstance(given, str):
        name = end_fixing(given)
        return np.full(len(catalog), END_FIXINGS[name][0]), [name] * len(catalog)
    factor = float(given)
    if not (math.isfinite(factor) and factor > 0):
        raise InputError(f"the end-fixing factor K must be a finite number > 0, got {given!r}")
    return np.full(len(catalog), factor), [f"K = {factor:g}"] * len(catalog)


def size_cylinder(duty: JointDuty, spec: Cylinder, catalog: pd.DataFrame, *, pressure: float = PRESSURE,
                  objective: str = "mass", length: ArrayLike | None = None,
                  end_fixing: str | float | None = None) -> CylinderSizing:
    """Choose a catalog cylinder for the coordinate ``spec`` (its stroke and count) doing ``duty``; ``pressure``
    is the system's relief pressure (Pa) (the checks: the module docstring).

    Args:
        length: The pin-to-pin length L(t) (m) at every sample of the duty, for the buckling check at every pose
            (:func:`cylinder_lengths`); default: fully extended, L = L_max of ``spec``, at every pose.
        end_fixing: The end fixing of every cylinder: a name of :data:`~mechatron.drives.shafts.END_FIXINGS` or
            the effective-length factor K; default: each catalog row's ``end_fixing`` (pinned at both ends where
            it gives none).
    """
    if objective not in ("mass", "cost", "margin"):
        raise InputError(f"cylinders are ranked by mass, cost or margin, not {objective!r}")
    if not pressure > 0:
        raise InputError(f"the system pressure must be > 0 Pa, got {pressure!r}")
    if length is None:
        length = np.full(len(duty.t), spec.stroke[1])
    length = np.asarray(length, dtype=float)
    if length.shape != duty.t.shape or not np.all(np.isfinite(length) & (length > 0)):
        raise InputError(f"cylinder {duty.name}: give a length > 0 (m) at each of the {len(duty.t)} samples")
    bore, rod = catalog["bore"].to_numpy(), catalog["rod"].to_numpy()
    piston, annulus = cylinder_areas(bore, rod)
    stroke = spec.stroke[1] - spec.stroke[0]
    force = duty.torque / spec.count  # per cylinder
    push = max(float(force.max()), 0.0)
    pull = max(float(-force.min()), 0.0)
    rated = catalog["max_pressure"].to_numpy()
    limit = np.minimum(rated, pressure)
    K, fixings = _fixings(catalog, end_fixing)
    # buckling at every pose: the pose of the largest F⁺ (K L)² decides, for every cylinder
    pose = int(np.argmax(np.maximum(force, 0.0) * length**2))
    allowed = euler_load(rod, length[pose], K, STEEL_MODULUS) / BUCKLING_SAFETY
    count = len(catalog)
    values = np.stack([np.full(count, pressure), push / piston, pull / annulus, np.full(count, stroke),
                       np.full(count, max(float(force[pose]), 0.0))], axis=1)
    limits = np.stack([rated, limit, limit, catalog["max_stroke"].to_numpy(), allowed], axis=1)
    factors = _load_factor(values, limits)
    worst = factors.max(axis=1)  # every check: feasibility and the closest rows
    binding = factors[:, _BINDING].max(axis=1)  # the checks that can bind: the margin
    feasible = worst <= 1 + PASS_TOLERANCE
    mass = catalog["mass"].fillna(0).to_numpy() if "mass" in catalog else np.zeros(count)
    if "mass_per_stroke" in catalog:
        mass = mass + catalog["mass_per_stroke"].fillna(0).to_numpy() * stroke
    price = catalog["price"].fillna(0).to_numpy() if "price" in catalog else np.zeros(count)
    score = {"mass": mass, "cost": price, "margin": binding}[objective]
    extending, retracting = max(float(duty.speed.max()), 0.0), max(-float(duty.speed.min()), 0.0) + 0.0
    flow = spec.count * np.maximum(piston * extending, annulus * retracting)
    standard = iso_3320(bore, rod)
    index = np.flatnonzero(feasible)
    ranking = pd.DataFrame({"cylinder": catalog["key"].to_numpy()[index], "bore": bore[index], "rod": rod[index],
                            "iso_3320": standard[index], "mass": mass[index] * spec.count,
                            "price": price[index] * spec.count, "smallest_margin": 1 - binding[index],
                            "peak_flow": flow[index], "score": score[index]})
    ranking = ranking.sort_values(["score", "mass"], kind="stable").reset_index(drop=True)
    order = np.argsort(worst, kind="stable")[:REPORTED]
    closest = pd.DataFrame({"cylinder": catalog["key"].to_numpy()[order], "worst_load_factor": worst[order],
                            "failed": [failures(CYLINDER_CHECKS, factors[i]) for i in order]})
    # the ranking's order over every row (score, mass, then catalog order): the rows before the chosen one fail
    ranked = np.lexsort((np.arange(count), mass, score))
    first = ranked[feasible[ranked]]
    i = int(first[0]) if len(first) else int(order[0])
    before = ranked[:int(np.flatnonzero(ranked == i)[0])][::-1] if len(first) and objective != "margin" \
        else np.array([], dtype=int)
    rivals = pd.DataFrame({"cylinder": catalog["key"].to_numpy()[before], "bore": bore[before], "rod": rod[before],
                           "iso_3320": standard[before], "mass": mass[before] * spec.count,
                           "price": price[before] * spec.count, "worst_load_factor": worst[before],
                           "failed": [failures(CYLINDER_CHECKS, factors[k]) for k in before]})
    checks = [Check(name, float(values[i, k]), float(limits[i, k]), CYLINDER_UNITS[k])
              for k, name in enumerate(CYLINDER_CHECKS)]
    return CylinderSizing(duty.name, objective, bool(len(ranking)), str(catalog["key"].iloc[i]), spec.count, checks,
                          float(flow[i]), ranking, closest, duty, catalog.iloc[i].to_dict(), float(pressure),
                          fixings[i], float(K[i] * length[pose]), length, rivals, float(K[i]))
