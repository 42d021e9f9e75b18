r"""The rest of a front-shovel excavator around its working device: the upper structure with its counterweight, the
undercarriage, the tipping lines, the ground's friction and the hydraulic circuits (the ``[machine]`` table of a
front-shovel design file, docs/front_shovel_design.md), and the three limits a load on the working device meets.

Coordinates are those of the design [Shovel]: x forward, y up from the ground (m), the working device in the xy plane;
the slew axis is the vertical line x = ``slew_axis``. A load is taken in the working direction r = x − x_slew, either
with the upper structure facing along the tracks (``over = "front"``) or across them (``"side"``) [ISO 10567].

- **Tipping** about a tipping line on the ground at r = a ahead of the slew axis (over the front: ``a`` the front
  tipping line, behind it the rear one at −b; over the side: ±``a`` the side tipping line). The machine begins to tip
  when the moment of the load about the line equals the restoring moment of its weights,
  M_R = g Σ m_i (a − r_i) (forwards) or g Σ m_i (r_i + b) (backwards), over the upper structure, the undercarriage
  (at r = 0 over the side: the tracks are symmetric) and the working device's bodies in their pose. A force −D·û on
  a point (r_P, y_P) has the moment D·μ about the line's point (a, 0) with μ = −(r_P − a) û_y + y_P û_x, so the
  machine tips forwards at D = M_R/(−μ) where μ < 0, backwards at D = M_R,back/μ_back where μ_back > 0
  (:func:`tipping_force`).
- **Slipping**: with the ground's normal force N = M g + D û_y and friction coefficient μ_f, the machine slides
  when D |û_x| = μ_f N, at D = μ_f M g / (|û_x| − μ_f û_y) where the denominator is > 0 (:func:`slipping_force`).
- **Hydraulics**: each cylinder's force is linear in the load, F(D) = F₀ + D·S (the closed-loop inverse dynamics at
  rest give F₀ under gravity and S for a unit load); a cylinder gives way when it reaches its relief force, pushing
  p_relief·A_piston or pulling p_relief·A_annulus (times the cylinders side by side). The largest load is the
  smallest D ≥ 0 at which any cylinder gets there (:func:`largest_load`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, fields, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from . import plausible
from .excavator import DEFAULT_CYLINDERS, RELIEF_PRESSURE, CylinderSpec, FrontShovelDesign

if TYPE_CHECKING:  # pragma: no cover
    from ..model.mechanism import Mechanism

Array = NDArray[np.float64]

#: The cylinders of the working device by the names of the design file's [machine] tables.
CYLINDER_TABLES = {"boom_cylinder": "L1", "stick_cylinder": "L2", "bucket_cylinder": "L3"}
#: Relief pressures (Pa) outside this range are refused: 1 bar to 100 MPa (a pressure given in bar or MPa, not Pa).
PRESSURE_RANGE = (1e5, 1e8)
OVER = ("front", "side")


@dataclass(frozen=True)
class ShovelMachine:
    """The machine around the working device (SI: kg, m, Pa); the defaults are illustrative values for the 46 t front
    shovel of the design [Shovel], which gives none.

    ``upper_centre`` and ``undercarriage_centre`` are (x, y) in the design's coordinates with the upper structure
    facing along the tracks; the tipping lines are distances from the slew axis (``None``: half the track length
    ``track_length``, idler to sprocket centres, over the front and the rear, and half the gauge ``track_gauge``,
    track centre to track centre, over the side: mechatron's assumption, lines through the idler and sprocket centres
    and along the tracks' centre lines, not a rule quoted from [ISO 10567]). ``friction``: the coefficient μ of the
    ground under the tracks for the slipping limit of the digging capability (default 0.5, a coefficient of traction
    of tracks on wet sand [Caterpillar, traction factors]; that table ranges from 0.12 on ice to 0.90 on firm earth:
    give the site's). ``bores``: (bore, rod) of each cylinder L1, L2, L3 (m;
    default the design's :data:`~mechatron.machines.excavator.DEFAULT_CYLINDERS`); ``reliefs``: the relief pressure
    of a cylinder's circuit where it differs from ``relief_pressure``. ``lift_radii``, ``lift_heights``: the lift
    chart's grid (m; ``None``: every 1 m the lift point reaches, radii from 3 m).
    """

    upper_mass: float = 19000.0
    upper_centre: tuple[float, float] = (-1.4, 1.8)
    undercarriage_mass: float = 16500.0
    undercarriage_centre: tuple[float, float] = (0.0, 0.6)
    slew_axis: float = 0.0
    track_length: float = 4.5
    track_gauge: float = 2.75
    front_tipping_line: float | None = None
    rear_tipping_line: float | None = None
    side_tipping_line: float | None = None
    friction: float = 0.5
    relief_pressure: float = RELIEF_PRESSURE
    bores: Mapping[str, tuple[float, float]] = field(
        default_factory=lambda: {n: (c.bore, c.rod) for n, c in DEFAULT_CYLINDERS.items()})
    reliefs: Mapping[str, float] = field(default_factory=dict)
    lift_radii: tuple[float, ...] | None = None
    lift_heights: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        check_machine(self)

    # ----------------------------------------------------------------------------------------------- geometry
    @property
    def tipping_lines(self) -> dict[str, float]:
        """Distances (m) of the tipping lines from the slew axis: ``front``, ``rear`` and ``side``."""
        return {"front": self.front_tipping_line if self.front_tipping_line is not None else self.track_length / 2,
                "rear": self.rear_tipping_line if self.rear_tipping_line is not None else self.track_length / 2,
                "side": self.side_tipping_line if self.side_tipping_line is not None else self.track_gauge / 2}

    def lines(self, over: str) -> tuple[float, float]:
        """(a, b): the tipping line ahead of the slew axis at r = a and the one behind it at r = −b (m), with the upper
        structure facing ``over`` the front or the side."""
        t = self.tipping_lines
        return (t["front"], t["rear"]) if over == "front" else (t["side"], t["side"])

    def base(self, over: str) -> tuple[float, float]:
        """(mass kg, first moment kg·m about the slew axis in the working direction) of the upper structure and the
        undercarriage, the upper structure facing ``over`` the front or the side (the undercarriage at r = 0 over the
        side)."""
        upper = self.upper_mass * (self.upper_centre[0] - self.slew_axis)
        under = self.undercarriage_mass * (self.undercarriage_centre[0] - self.slew_axis) if over == "front" else 0.0
        return self.upper_mass + self.undercarriage_mass, upper + under

    # ---------------------------------------------------------------------------------------------- hydraulics
    def cylinders(self, design: FrontShovelDesign) -> dict[str, CylinderSpec]:
        """Bore and rod of L1, L2, L3 with the design's number of boom cylinders side by side."""
        return {n: CylinderSpec(bore, rod, design.boom_cylinders if n == "L1" else 1)
                for n, (bore, rod) in self.bores.items()}

    def relief(self, name: str) -> float:
        """Relief pressure (Pa) of cylinder ``name``'s circuit."""
        return self.reliefs.get(name, self.relief_pressure)

    def force_limits(self, design: FrontShovelDesign, names: list[str]) -> tuple[Array, Array]:
        """(push, pull): the relief forces (N, > 0) of the cylinders ``names``: p·A_piston and p·A_annulus times the
        cylinders side by side."""
        specs = self.cylinders(design)
        push = np.array([specs[n].force(self.relief(n), True) for n in names])
        pull = np.array([specs[n].force(self.relief(n), False) for n in names])
        return push, pull

    def as_dict(self) -> dict[str, Any]:
        """The machine data with the tipping lines resolved (SI)."""
        out = {f.name: getattr(self, f.name) for f in fields(self)}
        out.update({f"{k}_tipping_line": v for k, v in self.tipping_lines.items()})
        out["bores"] = {n: list(v) for n, v in self.bores.items()}
        out["reliefs"] = {n: self.relief(n) for n in self.bores}
        return out


def check_machine(m: ShovelMachine) -> None:
    """Refuse machine data outside reason, naming the field: masses ≤ 0, a centre below the ground, the undercarriage's
    centre outside its tracks, the upper structure and undercarriage together not standing on their tracks over the
    front, the rear or the side, tipping lines that do not enclose the slew axis (a distance ≤ 0), a friction
    coefficient outside (0, 2], pressures outside 1 bar … 100 MPa (≤ 0 among them), bore ≤ rod ≤ 0 or a bore over 2 m
    (a bore in mm), a grid radius ≤ 0; and every field within its plausible range (mechatron's,
    :mod:`~mechatron.machines.plausible`: masses up to 2e6 kg, lengths 0.01 … 100 m, coordinates ±100 m, bores
    0.01 … 2 m)."""
    def bad(name: str, message: str) -> InputError:
        return InputError(message, field=name)

    for name in ("upper_mass", "undercarriage_mass"):
        if not getattr(m, name) > 0:
            raise bad(name, f"must be > 0 kg, got {getattr(m, name):g}")
        plausible.BODY_MASS.check(name, getattr(m, name))
    for name in ("upper_centre", "undercarriage_centre"):
        centre = getattr(m, name)
        if len(centre) != 2 or not all(math.isfinite(c) for c in centre):
            raise bad(name, f"needs two finite numbers x, y (m), got {centre!r}")
        if centre[1] < 0:
            raise bad(name, f"the centre is below the ground (y = {centre[1]:g} m < 0)")
        plausible.POSITION.check(name, centre[0])
        plausible.HEIGHT.check(name, centre[1])
    for name in ("track_length", "track_gauge"):
        if not getattr(m, name) > 0:
            raise bad(name, f"must be > 0 m, got {getattr(m, name):g}")
        plausible.LENGTH.check(name, getattr(m, name))
    for name in ("front_tipping_line", "rear_tipping_line", "side_tipping_line"):
        value = getattr(m, name)
        if value is not None and not value > 0:
            raise bad(name, f"the tipping line does not enclose the slew axis: its distance from the axis must be "
                            f"> 0 m, got {value:g}")
        if value is not None:
            plausible.LENGTH.check(name, value)
    if not math.isfinite(m.slew_axis):
        raise bad("slew_axis", f"must be a finite number (m), got {m.slew_axis!r}")
    plausible.POSITION.check("slew_axis", m.slew_axis)
    lines = m.tipping_lines
    x = m.undercarriage_centre[0] - m.slew_axis
    if not -lines["rear"] < x < lines["front"]:
        raise bad("undercarriage_centre", f"the centre ({x:g} m from the slew axis) is not between the rear and the "
                                          f"front tipping lines (−{lines['rear']:g} … {lines['front']:g} m)")
    for over in OVER:
        mass, moment = m.base(over)
        a, b = m.lines(over)
        if not -b < moment / mass < a:
            way = "forwards" if moment / mass >= a else "backwards"
            facing = "along" if over == "front" else "across"
            raise bad("upper_centre", f"the machine without its working device tips {way}, the upper structure "
                                      f"facing {facing} the tracks: the centre of the upper structure and "
                                      f"undercarriage is {moment / mass:g} m from the slew axis, outside its tipping "
                                      f"lines (−{b:g} … {a:g} m)")
    if not 0 < m.friction <= 2:
        raise bad("friction", f"the ground's friction coefficient must be > 0 and <= 2, got {m.friction:g}")
    for name, p in (("relief_pressure", m.relief_pressure), *((f"{n}.relief_pressure", p) for n, p in
                                                              m.reliefs.items())):
        if not PRESSURE_RANGE[0] <= p <= PRESSURE_RANGE[1]:
            raise bad(name, f"must be a pressure in Pa from {PRESSURE_RANGE[0]:g} to {PRESSURE_RANGE[1]:g} "
                            f"(32 MPa is 32e6), got {p:g}")
    if set(m.bores) != set(CYLINDER_TABLES.values()):
        raise bad("bores", f"needs the cylinders L1, L2, L3, got {sorted(m.bores)}")
    for name, (bore, rod) in m.bores.items():
        plausible.BORE.check(f"{name}.bore", bore)
        plausible.ROD.check(f"{name}.rod", rod)
        if not (2 > bore > rod > 0):
            raise bad(f"{name}.bore", f"need 2 m > bore > rod > 0 m, got bore {bore:g}, rod {rod:g}")
    if m.lift_radii is not None and (not m.lift_radii or min(m.lift_radii) <= 0):
        raise bad("lift_radii", f"needs radii > 0 m, got {list(m.lift_radii)}")
    if m.lift_heights is not None and not m.lift_heights:
        raise bad("lift_heights", "needs at least one height (m)")
    for name, plausible_range in (("lift_radii", plausible.LENGTH), ("lift_heights", plausible.POSITION)):
        for value in getattr(m, name) or ():
            plausible_range.check(name, value)


# ------------------------------------------------------------------------------------------------ the file
def read_machine(path: str | Path) -> ShovelMachine:
    """The ``[machine]`` table of a front-shovel design file (docs/front_shovel_design.md): the fields of
    :class:`ShovelMachine` (kg, m, Pa), the cylinders in the tables ``[machine.boom_cylinder]``,
    ``[machine.stick_cylinder]``, ``[machine.bucket_cylinder]`` (``bore``, ``rod`` m, ``relief_pressure`` Pa); the
    fields not given keep the illustrative defaults. No table: the defaults. An error names the file and the field
    (``machine.upper_mass``)."""
    from ..io.schema import FieldReader
    from ..io.toml import read_toml

    top = FieldReader(read_toml(path), file=path)
    reader = top.table("machine", None)
    if reader is None:
        return ShovelMachine()
    values: dict[str, Any] = {}
    default = ShovelMachine()
    for f in fields(ShovelMachine):
        if f.name in ("bores", "reliefs") or not reader.has(f.name):
            continue
        if f.name.endswith("_centre"):
            values[f.name] = tuple(float(x) for x in reader.vector(f.name, 2))
        elif f.name.startswith("lift_"):
            values[f.name] = _grid(reader, f.name)
        else:
            values[f.name] = reader.number(f.name)
    bores, reliefs = dict(default.bores), {}
    for table, name in CYLINDER_TABLES.items():
        sub = reader.table(table, None)
        if sub is None:
            continue
        bores[name] = (sub.number("bore", bores[name][0]), sub.number("rod", bores[name][1]))
        if sub.has("relief_pressure"):
            reliefs[name] = sub.number("relief_pressure")
        sub.finish()
    reader.finish()
    try:
        return replace(default, **values, bores=bores, reliefs=reliefs)
    except InputError as exc:
        field_name = exc.field or ""
        for table, name in CYLINDER_TABLES.items():
            field_name = field_name.replace(f"{name}.", f"{table}.")
        raise InputError(exc.message, file=path, field=f"machine.{field_name}") from None


def _grid(reader: Any, key: str) -> tuple[float, ...]:
    """A list of numbers (m) of the table, sorted, each finite."""
    value = reader.raw(key)
    if not isinstance(value, list):
        raise reader.error(key, f"expected a list of numbers (m), got {type(value).__name__} {value!r}")
    return tuple(sorted({reader.to_float(f"{key}[{i}]", v) for i, v in enumerate(value)}))


# ------------------------------------------------------------------------------------------------ the limits
def device_centres(mech: Mechanism, Q: ArrayLike) -> tuple[float, Array]:
    """(mass kg, x of the centre of mass, m, at each configuration of Q) of the working device's bodies."""
    import pinocchio as pin

    data = mech.model.createData()
    Q = np.atleast_2d(np.asarray(Q, dtype=float))
    x = np.array([pin.centerOfMass(mech.model, data, q)[0] for q in Q]) if mech.total_mass > 0 else np.zeros(len(Q))
    return float(mech.total_mass), x


def restoring_moments(machine: ShovelMachine, over: str, device_mass: float, device_x: ArrayLike,
                      g: float) -> tuple[Array, Array]:
    """(M_front, M_back) (N·m): the moments of the machine's weights that resist tipping about the line ahead of the
    slew axis, g Σ m_i (a − r_i), and about the one behind it, g Σ m_i (r_i + b); the working device's centre at x =
    ``device_x`` (m, design coordinates) with ``device_mass`` (kg)."""
    a, b = machine.lines(over)
    mass, moment = machine.base(over)
    r_device = np.asarray(device_x, dtype=float) - machine.slew_axis
    mass_all = mass + device_mass
    moment_all = moment + device_mass * r_device
    return g * (mass_all * a - moment_all), g * (moment_all + mass_all * b)


def tipping_force(machine: ShovelMachine, over: str, moments: tuple[Array, Array], point_r: ArrayLike,
                  point_y: ArrayLike, direction: ArrayLike) -> tuple[Array, Array]:
    """(D N, which) for a force −D·û on the point (r, y) (m: from the slew axis in the working direction, above the
    ground), û = ``direction`` (N, 2) unit vectors: the smallest D ≥ 0 that tips the machine forwards (``which`` 1)
    or backwards (−1) about its tipping lines, ``inf`` (``which`` 0) where none does; 0 where the weights alone tip
    it. ``moments``: :func:`restoring_moments`."""
    a, b = machine.lines(over)
    r, y = np.asarray(point_r, dtype=float), np.asarray(point_y, dtype=float)
    u = np.atleast_2d(np.asarray(direction, dtype=float))
    front = -(r - a) * u[:, 1] + y * u[:, 0]  # moment of −û about (a, 0); tips forwards where < 0
    back = -(r + b) * u[:, 1] + y * u[:, 0]  # about (−b, 0); tips backwards where > 0
    with np.errstate(divide="ignore", invalid="ignore"):
        d_front = np.where(front < 0, np.maximum(moments[0], 0.0) / -front, np.inf)
        d_back = np.where(back > 0, np.maximum(moments[1], 0.0) / back, np.inf)
    force = np.minimum(d_front, d_back)
    which = np.where(np.isinf(force), 0, np.where(d_front <= d_back, 1, -1))
    return force, which


def slipping_force(friction: float, mass: float, g: float, direction: ArrayLike) -> Array:
    """D (N) at which a force −D·û on the working device slides the machine on the ground: D |û_x| = μ (M g + D û_y),
    D = μ M g / (|û_x| − μ û_y) where that denominator is > 0, else ``inf``; M the whole machine's mass (kg)."""
    u = np.atleast_2d(np.asarray(direction, dtype=float))
    denominator = np.abs(u[:, 0]) - friction * u[:, 1]
    with np.errstate(divide="ignore"):
        return np.where(denominator > 0, friction * mass * g / denominator, np.inf)


def largest_load(F0: ArrayLike, S: ArrayLike, push: ArrayLike, pull: ArrayLike) -> tuple[Array, Array]:
    """(D, cylinder index): per row the largest load D ≥ 0 with every cylinder force F₀ + D·S (N; rows of F0, S: one
    position, columns: the cylinders) within −pull … push (N, the relief forces), and the cylinder that reaches its
    relief force first (−1 where none does: D = ``inf``). A cylinder already beyond its relief force without the load
    gives D = 0."""
    F0, S = np.atleast_2d(F0), np.atleast_2d(S)
    push, pull = np.asarray(push, dtype=float), np.asarray(pull, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        each = np.where(S > 0, (push - F0) / S, np.where(S < 0, (pull + F0) / -S, np.inf))
    each = np.where((F0 > push) | (F0 < -pull), 0.0, np.maximum(each, 0.0))
    index = np.argmin(each, axis=1)
    load = each[np.arange(len(each)), index]
    return load, np.where(np.isinf(load), -1, index)


def gravity(mech: Mechanism) -> float:
    """|g| (m/s²) of the mechanism's model."""
    return float(np.linalg.norm(mech.model.gravity.linear))
