"""The motion converters a joint can be driven through, as arrays: direct drive, the gearboxes of a catalog for a
revolute joint, the linear drives of a catalog (ball screws, racks and pinions) for a prismatic one (ratio
u = 2π / lead, rad/m, with the lead the travel per turn of the motor-side shaft).

A linear drive also carries what its own checks need (:mod:`mechatron.drives.screws`): the length used, dynamic
load rating, root diameter and end fixing of a screw, the permitted tooth force of a rack, the longest one made.
A gearbox carries its duty ratings (:mod:`mechatron.drives.checks`): the rule its maker gives for its peak torque
(``peak_rule``, :data:`PEAK_RULES`: a table of shock factors by cycles per hour, a strain-wave gear's repeated peak
torque, or only the cycle rate it is rated up to), the cycles per hour its peak torque is rated for (``cycle_rating``,
default :data:`CYCLE_RATING`) and the number of emergency stops its emergency torque is allowed in its life
(``emergency_stops``, default :data:`EMERGENCY_STOPS`)."""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from .duty import JointDuty
from .motor import catalog_column
from .shafts import fixing_factors

#: Length of a screw or rack beyond the stroke, for bearings and nut (m): its inertia and mass per length count
#: over stroke + LENGTH_ALLOWANCE.
LENGTH_ALLOWANCE = 0.2
#: The cycle rate a gearbox's peak (acceleration) torque T2B holds up to where its catalog does not say (1/s): the
#: gearbox makers' 1,000 cycles per hour.
CYCLE_RATING = 1000 / 3600
#: How many times a gearbox's emergency torque T2Stop is allowed in its life where its catalog does not say: 1,000.
EMERGENCY_STOPS = 1000.0
#: The rules a gearbox's peak torque T2B (``peak_torque``) is checked by, the catalog's ``peak_rule`` (empty:
#: ``shock_factors`` where the row gives that table, else ``cycle_rating``), in the words of a report.
PEAK_RULES = {
    "shock_factors": "the maker's shock factors by cycles per hour (the catalog's shock_factors): the peak torque "
                     "asked for × f_s against T2B",
    "repeated_peak": "the maker's repeated peak torque (a strain-wave gear's limit of the torque of every start and "
                     "stop): T2B at any rate",
    "cycle_rating": "T2B up to the catalog's cycle rating; no maker rule given above it",
}


@dataclass(frozen=True)
class Converters:
    """Converters of one joint, one array entry each: key, kind, ratio u (motor speed / joint speed; rad/rad, or
    rad/m for a screw or rack), efficiency η, motor-side inertia J_c (kg·m²), output torque limits (N·m; rated
    T2N, peak T2B, emergency T2Stop), input speed limits (rad/s; max n1max, rated mean n1N), mass (kg) and price;
    a limit that does not apply is inf.

    A linear drive also has its length L = stroke + :data:`LENGTH_ALLOWANCE` (m), the dynamic load rating C (N),
    the root diameter d_r (m) and the end fixing's effective-length factor K and eigenvalue λ of a screw
    (:mod:`mechatron.drives.shafts`), the permitted tooth force of a rack (N) and the longest one made
    (``max_length``, m); NaN (C, d_r, K, λ, L) or inf (the limits) where they do not apply.

    A gearbox has the rule of its peak torque T2B (``peak_rule``, a key of :data:`PEAK_RULES`; ``""`` for the other
    converters), the table of its maker's shock factors f_s at the load cycle rates of ``shock_rates`` (1/s; rows
    padded with NaN, all NaN without a table; :func:`~mechatron.drives.checks.peak_torque_factor`), the cycle rate
    its peak torque is rated for (``cycle_rating``, 1/s) and the number of emergency stops its T2Stop is allowed
    (``emergency_stops``); inf and NaN for the other converters."""

    key: NDArray[np.str_]
    kind: NDArray[np.str_]
    ratio: NDArray[np.float64]  # rad/rad, rad/m
    efficiency: NDArray[np.float64]  # 0…1
    inertia: NDArray[np.float64]  # kg·m²
    rated_torque: NDArray[np.float64]  # N·m
    peak_torque: NDArray[np.float64]  # N·m
    emergency_torque: NDArray[np.float64]  # N·m
    max_input_speed: NDArray[np.float64]  # rad/s
    rated_input_speed: NDArray[np.float64]  # rad/s
    mass: NDArray[np.float64]  # kg
    price: NDArray[np.float64]
    length: NDArray[np.float64]  # m
    dynamic_load: NDArray[np.float64]  # N
    root_diameter: NDArray[np.float64]  # m
    buckling_factor: NDArray[np.float64]  # K
    whirl_factor: NDArray[np.float64]  # λ
    permitted_force: NDArray[np.float64]  # N
    max_length: NDArray[np.float64]  # m
    cycle_rating: NDArray[np.float64]  # 1/s
    emergency_stops: NDArray[np.float64]  # count
    peak_rule: NDArray[np.str_]
    shock_rates: NDArray[np.float64]  # (N_c, K) 1/s
    shock_factors: NDArray[np.float64]  # (N_c, K)

    def __len__(self) -> int:
        return len(self.key)

    def subset(self, index: ArrayLike) -> Converters:
        """The converters at ``index`` (an index array or a boolean mask)."""
        return Converters(**{f.name: getattr(self, f.name)[index] for f in fields(self)})


def _number(value) -> float:
    return 0.0 if value is None or (isinstance(value, float) and math.isnan(value)) else float(value)


def _optional(value, missing: float) -> float:
    return missing if value is None or (isinstance(value, float) and math.isnan(value)) else float(value)


#: The linear-drive data of a converter that is not one (direct drive, gearbox).
_ROTARY = dict(length=math.nan, dynamic_load=math.nan, root_diameter=math.nan, buckling_factor=math.nan,
               whirl_factor=math.nan, permitted_force=math.inf, max_length=math.inf)
#: The gearbox duty ratings of a converter that is not a gearbox (direct drive, screw, rack): none.
_NO_DUTY = dict(cycle_rating=math.inf, emergency_stops=math.nan, peak_rule="", shock_rates=np.full((1, 1), math.nan),
                shock_factors=np.full((1, 1), math.nan))


def _direct() -> dict:
    inf = math.inf
    return dict(key="direct", kind="direct", ratio=1.0, efficiency=1.0, inertia=0.0, rated_torque=inf,
                peak_torque=inf, emergency_torque=inf, max_input_speed=inf, rated_input_speed=inf, mass=0.0,
                price=0.0, **_ROTARY, **_NO_DUTY)


def _gearboxes(catalog: pd.DataFrame) -> dict:
    """:func:`_gearbox` of every row of a gearbox catalog at once, as arrays (a missing mass or price counts 0)."""
    def column(name: str) -> np.ndarray:
        return catalog[name].to_numpy(dtype=float)

    out = dict(key=catalog["key"].to_numpy(dtype=str), kind=catalog["type"].to_numpy(dtype=str),
               ratio=column("ratio"), efficiency=column("efficiency"), inertia=column("input_inertia"),
               rated_torque=column("rated_torque"), peak_torque=column("peak_torque"),
               emergency_torque=column("emergency_torque"), max_input_speed=column("max_input_speed"),
               rated_input_speed=column("rated_input_speed"), mass=catalog_column(catalog, "mass", 0.0),
               price=catalog_column(catalog, "price", 0.0),
               cycle_rating=catalog_column(catalog, "cycle_rating", CYCLE_RATING),
               emergency_stops=catalog_column(catalog, "emergency_stops", EMERGENCY_STOPS),
               **_peak_rules(catalog))
    return {**out, **{name: np.full(len(catalog), value) for name, value in _ROTARY.items()}}


def _peak_rules(catalog: pd.DataFrame) -> dict:
    """peak_rule, shock_rates and shock_factors (:class:`Converters`) of every row of a gearbox catalog: the tables
    of ``shock_factors`` (((rate 1/s, f_s), …) per row, :func:`~mechatron.drives.catalogs.read_catalog`; NaN or
    empty for none) padded with NaN to the longest."""
    n = len(catalog)
    tables = [t if isinstance(t, (tuple, list)) else () for t in
              (catalog["shock_factors"] if "shock_factors" in catalog else [()] * n)]
    rules = [r if isinstance(r, str) and r else "" for r in (catalog["peak_rule"] if "peak_rule" in catalog else
                                                            [""] * n)]
    rules = [r or ("shock_factors" if t else "cycle_rating") for r, t in zip(rules, tables)]
    width = max([1, *map(len, tables)])
    grid = np.full((2, n, width), math.nan)
    for i, table in enumerate(tables):
        if table:
            grid[:, i, :len(table)] = np.asarray(table, dtype=float).T
    return dict(peak_rule=np.array(rules, dtype=str), shock_rates=grid[0], shock_factors=grid[1])


def _linear(row: dict, length: float) -> dict:
    inf = math.inf
    fixing, whirl = fixing_factors([row.get("end_fixing") or ""])
    return dict(key=row["key"], kind=row["type"], ratio=2 * math.pi / row["lead"], efficiency=row["efficiency"],
                inertia=_number(row.get("inertia")) + _number(row.get("inertia_per_length")) * length,
                rated_torque=inf, peak_torque=inf, emergency_torque=inf, max_input_speed=row["max_speed"],
                rated_input_speed=inf, mass=_number(row.get("mass")) + _number(row.get("mass_per_length")) * length,
                price=_number(row.get("price")), length=length,
                dynamic_load=_optional(row.get("dynamic_load"), math.nan),
                root_diameter=_optional(row.get("root_diameter"), math.nan), buckling_factor=float(fixing[0]),
                whirl_factor=float(whirl[0]), permitted_force=_optional(row.get("permitted_force"), inf),
                max_length=_optional(row.get("max_length"), inf), **_NO_DUTY)


def _joined(parts: list) -> np.ndarray:
    """The parts of one field (scalars, arrays, or tables: 2-D arrays padded with NaN to the widest), end to end."""
    parts = [np.atleast_1d(np.asarray(p)) for p in parts]
    if parts[0].ndim == 1:
        return np.concatenate(parts)
    width = max(p.shape[1] for p in parts)
    return np.concatenate([np.pad(p, ((0, 0), (0, width - p.shape[1])), constant_values=math.nan) for p in parts])


def converters_for(duty: JointDuty, gearboxes: pd.DataFrame | None = None, linear: pd.DataFrame | None = None,
                   direct: bool = True, chain_efficiency: float = 1.0) -> Converters:
    """The converters to try on ``duty``'s joint: direct drive (if ``direct``) and every gearbox for a revolute
    joint; every linear drive, ``stroke + LENGTH_ALLOWANCE`` long, for a prismatic joint. ``chain_efficiency``
    and the duty's own :attr:`~mechatron.drives.duty.JointDuty.efficiency` (a robot file's ``drive.efficiency``)
    multiply every converter's efficiency: the rest of the chain between motor and joint (couplings, bearings,
    a belt; the series product η = η_c · η_chain · η_drive, Π η_i [Egorov, 7.53],
    :func:`mechatron.mechanics.efficiency.series`).

    Returns:
        :class:`Converters`: ratio u (rad/rad, or rad/m for a screw or rack: u = 2π / lead), efficiency, motor-side
        inertia (kg·m²), limits (N·m, rad/s), mass (kg) and price of each.
    """
    if not 0 < chain_efficiency <= 1:
        raise InputError(f"the chain efficiency must be in (0, 1], got {chain_efficiency!r}")
    rows: list[dict] = []
    if duty.kind == "revolute":
        if direct:
            rows.append(_direct())
        if gearboxes is not None and len(gearboxes):
            rows.append(_gearboxes(gearboxes))
    elif duty.kind == "prismatic":
        if linear is None:
            raise InputError(f"joint {duty.name} is prismatic: give a catalog of linear drives (screws, racks)")
        rows += [_linear(s, duty.stroke + LENGTH_ALLOWANCE) for s in linear.to_dict(orient="records")]
    else:
        raise InputError(f"joint {duty.name}: cannot size a {duty.kind} joint (only revolute and prismatic)")
    if not rows:
        raise InputError(f"joint {duty.name}: no converter to try (give a gearbox catalog or allow direct drive)")
    columns = {name: _joined([r[name] for r in rows]) for name in rows[0]}
    columns["efficiency"] = columns["efficiency"] * (chain_efficiency * duty.efficiency)
    return Converters(**columns)
