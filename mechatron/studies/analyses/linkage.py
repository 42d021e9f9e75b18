"""The ``linkage`` analysis of a study: a closed-loop mechanism swept over the strokes of its inputs.

The sweep (:func:`mechatron.kinematics.sweeps.sweep`, ``samples`` positions, every input from its lower to its upper
limit together, a full turn of an unlimited crank) gives the path of a point (the mechanism's tool point, or
``point``): its reach (largest x), height (largest y), depth (largest −y) and its travels along x and y (m), and
along z for a spatial loop. With
``working_range = true`` (a three-cylinder working device) the extremes are over the whole stroke box instead
(:func:`mechatron.machines.excavator.working_range`, ``samples`` per side). For a central crank-slider the slider's
x travel is 2 l1 [Egorov, fig. 4.18]: x_C = l1 cos q1 + √(l2² − l1² sin² q1) is largest at q1 = 0 and smallest at
q1 = π.

The smallest transmission angle over the sweep is of the mechanism's transmission-angle measures (deg). A mechanism
with cylinders gets the static force of each cylinder holding it at every position of the sweep against gravity and
the optional ``load`` (Fx, Fy) on the point (closed-loop inverse dynamics at rest,
:func:`mechatron.dynamics.trajectory.holding_forces`), its largest magnitude (N), and with a ``cylinders`` table
(bore, rod in m, count) its largest pressure (Pa: force over the piston or the annulus area).

A design with a position that cannot be assembled fails with the first such position's reason.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ...errors import InputError, MechatronError
from ...io.values import number, numbers

OUTPUTS = ("reach_m", "height_m", "depth_m", "x_travel_m", "y_travel_m", "z_travel_m", "min_transmission_angle_deg",
           "CYLINDER_max_force_N", "CYLINDER_max_pressure_Pa")

#: The options and their defaults.
DEFAULTS = {"samples": 73, "point": None, "working_range": False, "load": None, "cylinders": None}


def _options(mech, options: dict[str, Any]) -> dict[str, Any]:
    unknown = sorted(set(options) - set(DEFAULTS))
    if unknown:
        raise InputError(f"unknown option {unknown[0]!r} (options: {', '.join(DEFAULTS)})", field=unknown[0])
    out = {**DEFAULTS, **options}
    out["samples"] = _field("samples", lambda: number("samples", out["samples"], integer=True, minimum=2,
                                                      maximum=100_000))
    point = out["point"] or mech.tool_frame
    if point not in mech.points:
        raise InputError(f"no point {point!r} in {mech.name} (points: {', '.join(mech.points)})", field="point")
    out["point"] = point
    if not isinstance(out["working_range"], bool):
        raise InputError("expected true or false", field="working_range")
    if out["working_range"] and len(mech.cylinders) != 3:
        raise InputError(f"the working range is of a three-cylinder working device; {mech.name} has "
                         f"{len(mech.cylinders)} cylinders", field="working_range")
    if out["load"] is not None:
        out["load"] = _field("load", lambda: numbers("load", out["load"], shape=(2,), unit="N"))
    out["cylinders"] = _cylinders(mech, out["cylinders"])
    return out


def _field(name: str, read):
    """``read()``, its error naming the option ``name``."""
    try:
        return read()
    except InputError as exc:
        raise InputError(exc.message, field=name) from None


def _cylinders(mech, table: Any) -> dict[str, Any]:
    from ...machines.excavator import CylinderSpec

    if table is None:
        return {}
    if not isinstance(table, dict):
        raise InputError("expected a table NAME = { bore = …, rod = …, count = … }", field="cylinders")
    out = {}
    for name, data in table.items():
        where = f"cylinders.{name}"
        if name not in mech.cylinders:
            raise InputError(f"{mech.name} has no cylinder {name!r} (cylinders: {', '.join(mech.cylinders)})",
                             field=where)
        if not isinstance(data, dict) or not {"bore", "rod"} <= set(data) or set(data) - {"bore", "rod", "count"}:
            raise InputError("expected { bore = m, rod = m, count = n }", field=where)
        bore = _field(f"{where}.bore", lambda: number("bore", data["bore"], positive=True, unit="m"))
        rod = _field(f"{where}.rod", lambda: number("rod", data["rod"], positive=True, unit="m"))
        count = _field(f"{where}.count", lambda: number("count", data.get("count", 1), integer=True, minimum=1))
        out[name] = _field(where, lambda: CylinderSpec(bore, rod, count))
    return out


def check(mech, options: dict[str, Any]) -> None:
    """Refuse a mechanism without closed loops or wrong options (see the module docstring)."""
    if not mech.closures:
        raise InputError(f"{mech.name} has no closed loops: the linkage analysis sweeps closed-loop mechanisms")
    _options(mech, options)


def output_names(mech, options: dict[str, Any]) -> list[str]:
    """The names of the outputs for ``options`` without running: the point's extents (z too in a spatial loop),
    the smallest transmission angle (of a mechanism with such measures), each cylinder's largest force and, with its
    bore and rod given, its largest pressure."""
    opts = _options(mech, options)
    names = ["reach_m", "height_m", "depth_m", "x_travel_m", "y_travel_m"]
    if _spatial(mech):
        names.append("z_travel_m")
    if any(m.kind == "transmission_angle" for m in mech.measures):
        names.append("min_transmission_angle_deg")
    for name in (n for n in mech.actuated if n in mech.cylinders):
        names.append(f"{name}_max_force_N")
        if name in opts["cylinders"]:
            names.append(f"{name}_max_pressure_Pa")
    return names


def _spatial(mech) -> bool:
    """Whether a closure of ``mech`` is spatial (its sweep has z coordinates)."""
    return any(not getattr(c, "planar", True) for c in mech.closures)


def input_files(mech, options: dict[str, Any]) -> list:
    """The files the analysis of one design reads: none (the mechanism's file aside)."""
    return []


def outputs(mech, options: dict[str, Any], seed: int) -> dict[str, float]:
    """The outputs of one design (m, deg, N, Pa; see the module docstring). ``seed`` is not used (no random
    draw)."""
    from ...kinematics.sweeps import sweep

    opts = _options(mech, options)
    point = opts["point"]
    result = sweep(mech, samples=opts["samples"], frames=[point])
    if len(result.failures):
        first = result.failures.iloc[0]
        raise MechatronError(f"{len(result.failures)} of {opts['samples']} positions cannot be assembled; first: "
                             f"{first['reason']}")
    x, y = result.table[f"{point}_x"].to_numpy(), result.table[f"{point}_y"].to_numpy()
    if opts["working_range"]:
        from ...machines.excavator import working_range

        cloud = working_range(mech, samples=opts["samples"])
        x, y = np.concatenate([cloud.cloud[:, 0], *[a[:, 0] for a in cloud.arcs]]), \
            np.concatenate([cloud.cloud[:, 1], *[a[:, 1] for a in cloud.arcs]])
    out = {"reach_m": float(x.max()), "height_m": float(y.max()), "depth_m": float(-y.min()) + 0.0,
           "x_travel_m": float(x.max() - x.min()), "y_travel_m": float(y.max() - y.min())}
    if f"{point}_z" in result.table:  # a spatial loop: the travel along z too
        z = result.table[f"{point}_z"].to_numpy()
        out["z_travel_m"] = float(z.max() - z.min())
    angles = [m.name for m in mech.measures if m.kind == "transmission_angle"]
    if angles:
        out["min_transmission_angle_deg"] = float(np.degrees(result.table[angles].to_numpy().min()))
    if mech.cylinders:
        out.update(_cylinder_outputs(mech, result.q, point, opts))
    return out


def _cylinder_outputs(mech, Q: np.ndarray, point: str, opts: dict[str, Any]) -> dict[str, float]:
    from ...dynamics.trajectory import holding_forces
    from ...model.loads import Load

    loads = [Load(point, [*opts["load"], 0.0])] if opts["load"] is not None else None
    forces = holding_forces(mech, Q, loads)
    out = {}
    for j, name in enumerate(mech.actuated):
        if name not in mech.cylinders:
            continue
        out[f"{name}_max_force_N"] = float(np.abs(forces[:, j]).max())
        if name in opts["cylinders"]:
            spec = opts["cylinders"][name]
            out[f"{name}_max_pressure_Pa"] = float(max(spec.pressure(f) for f in forces[:, j]))
    return out
