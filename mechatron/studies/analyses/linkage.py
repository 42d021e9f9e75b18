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

**The load case** of every force output (``CYLINDER_max_force_N``, ``CYLINDER_max_pressure_Pa``, here and at the
poses): static, at rest — gravity on the mechanism's bodies, plus, with a ``task`` (a task TOML or trajectory CSV,
:func:`mechatron.dynamics.task.read_task`), the task's payload (its mass and centre on the body that carries
``payload_at``) and its ``[[loads]]``, plus the ``load`` (Fx, Fy) on the point: the forces are those of the
``dynamics`` analysis of the same task and payload wherever the motion is at rest (v = a = 0). The task's motion is
not used: the positions are the sweep's. A payload the task carries on part of its motion only (``payload_from``,
``payload_until``, :mod:`mechatron.dynamics.segments`) gives two load cases, with and without it, since a position
of the sweep has no time in the task: at each position the force is that of the case of the larger magnitude and
the largest pressure that of either case (our rule: the envelope of the static forces the task can see there).

**Held inputs and named poses.** ``hold = { INPUT = value }`` (m or rad, within the input's limits) keeps those
inputs at their values while the others sweep from their lower to their upper limit together (a sweep of one input
with the others held). ``poses`` is a list of named poses, each ``{ name, inputs = { INPUT = value }, point,
lowest | highest }``: the inputs named are held, the others sweep (``samples`` positions) and the pose's outputs are
this analysis' outputs over those positions for the pose's ``point`` (default the analysis' point), each named
``POSE.OUTPUT`` (``boom down.height_m``). Where every input is held, or with ``lowest = "OUTPUT"`` (``highest``)
— the one position of the held sweep where that output, taken of the analysis' point at each position alone (x for
``reach_m``, y for ``height_m``, −y for ``depth_m``, the smallest transmission angle, a cylinder's |force| or
pressure), is smallest (largest) — the pose is one position and has no travels. A held sweep starts from the
drawn position and moves every input in 8 equal steps to its first position (the assembly branch kept by
continuation); those steps are not part of the outputs.

A design with a position that cannot be assembled fails with the first such position's reason (the sweep ends
there; a pose's reason names it).

**Exact gradients** (:func:`gradients`, for the optimiser's exact-derivative route): the outputs of one sweep and
their derivatives with respect to named geometric parameters l of the mechanism. Each output is an extreme over the
samples (a max, a min, or max − min), so by Danskin's theorem its derivative is that of the sampled quantity at the
extremal sample, the sample held: the inputs (the actuated coordinates) stay at their sample's values — they run
between the joints' limits (a cylinder's stroke, a crank's limits) or over a full turn from the reference angle,
data of the mechanism that its parameters do not move (a rebuilt linkage holds its inputs where the original held
them), so dq_a/dl = 0 — while the passive coordinates move to keep the loops closed (implicit-function theorem,
dq/dl = −(∂Φ/∂q_d)⁻¹ ∂Φ/∂l, :func:`mechatron.accuracy.sensitivity.loop_derivatives`) and a point moves by
dr/dl = J_r dq/dl + ∂r/∂l|_q (frame Jacobian and placement twists,
:func:`mechatron.accuracy.sensitivity.frame_parameter_twists`; the placements' exact derivatives are the
mechanism's, :func:`mechatron.model.derivatives.placement_derivatives`). Hence d reach/dl = dx/dl at the sample of
largest x, d x_travel/dl = dx/dl there minus dx/dl at the sample of smallest x, and so on; for the crank-slider
d reach/d l1 = d reach/d l2 = 1, d x_travel/d l1 = 2, d x_travel/d l2 = 0. The smallest transmission angle
μ = atan2(|u × w|, |u · w|) of the lines u = b − a and w = d − c is differentiated through its four points at its
sample (deg per unit of l); a cylinder's largest force |f| by sign(f) df/dl at its sample and its largest pressure
by the pressure's slope (1 / (count × piston area) pushing, −1 / (count × annulus area) pulling) times df/dl, with
df/dl the exact derivative of the holding force (closed-loop inverse dynamics at rest,
:func:`mechatron.dynamics.sensitivity.parameter_sensitivities`). With ``working_range`` the extremal tip position of
the stroke box is assembled again at its inputs and differentiated there. Where two samples tie for an extreme the
output has only one-sided derivatives; the first sample's is given. No finite difference is taken.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ...errors import InputError, MechatronError
from ...io.values import number, numbers

OUTPUTS = ("reach_m", "height_m", "depth_m", "x_travel_m", "y_travel_m", "z_travel_m", "min_transmission_angle_deg",
           "CYLINDER_max_force_N", "CYLINDER_max_pressure_Pa")

#: The options and their defaults.
DEFAULTS = {"samples": 73, "point": None, "working_range": False, "load": None, "cylinders": None, "task": None,
            "hold": None, "poses": None}

#: The steps of a held sweep from the drawn position to its first position (continuation along the inputs).
RAMP = 8
#: The outputs of a pose that is one position: all but the travels.
_TRAVELS = ("x_travel_m", "y_travel_m", "z_travel_m")


@dataclass(frozen=True)
class Pose:
    """A named pose (module docstring): the inputs held (m, rad), the point measured and the pick (``lowest`` or
    ``highest``, an output's name) of one position of the held sweep, or None."""

    name: str
    inputs: dict[str, float]
    point: str
    pick: tuple[str, str] | None = None

    def single(self, mech) -> bool:
        """Whether the pose is one position (every input held, or a pick)."""
        return self.pick is not None or set(self.inputs) == set(mech.actuated)


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
    if out["task"] is not None and not isinstance(out["task"], str):
        raise InputError("expected the path of a task TOML or trajectory CSV", field="task")
    if out["hold"] is not None and out["working_range"]:
        raise InputError("the working range moves every cylinder; give hold or working_range, not both", field="hold")
    out["hold"] = _held(mech, out["hold"] or {}, "hold")
    out["poses"] = _poses(mech, out)
    return out


def _held(mech, values: Any, where: str) -> dict[str, float]:
    """``{INPUT = value}`` checked: actuated inputs of ``mech``, finite values (m, rad) within their limits."""
    from ...kinematics.loops import loop_solver

    if not isinstance(values, dict):
        raise InputError("expected a table INPUT = value (m or rad)", field=where)
    solver = loop_solver(mech)
    lower, upper = mech.model.lowerPositionLimit, mech.model.upperPositionLimit
    out = {}
    for name, value in values.items():
        if name not in mech.actuated:
            raise InputError(f"{name!r} is not an input of {mech.name} (inputs: {', '.join(mech.actuated)})",
                             field=f"{where}.{name}")
        v = _field(f"{where}.{name}", lambda: number(name, value, unit="m or rad", maximum=None))
        lo, hi = lower[solver.index[name]], upper[solver.index[name]]
        if np.isfinite(lo) and np.isfinite(hi) and not lo <= v <= hi:
            raise InputError(f"{v:g} is outside the input's limits [{lo:g}, {hi:g}]", field=f"{where}.{name}")
        out[name] = v
    return out


def _pickable(mech, opts: dict[str, Any]) -> list[str]:
    """The outputs a pose may pick its position by: those with a value at one position."""
    return [n for n in _names(mech, opts) if n not in _TRAVELS]


def _poses(mech, opts: dict[str, Any]) -> tuple[Pose, ...]:
    """The ``poses`` option checked: a list of tables ``{ name, inputs, point, lowest | highest }``."""
    given = opts["poses"]
    if given is None:
        return ()
    if not isinstance(given, (list, tuple)):
        raise InputError("expected a list of poses { name = ..., inputs = { INPUT = value } }", field="poses")
    out: list[Pose] = []
    for k, data in enumerate(given):
        where = f"poses[{k + 1}]"
        if isinstance(data, Pose):
            out.append(data)
            continue
        if not isinstance(data, dict) or set(data) - {"name", "inputs", "point", "lowest", "highest"}:
            raise InputError("expected { name, inputs, point, lowest or highest }", field=where)
        name = data.get("name")
        if not isinstance(name, str) or not name.strip() or "." in name:
            raise InputError(f"a pose needs a name without dots, got {name!r}", field=f"{where}.name")
        if any(p.name == name for p in out):
            raise InputError(f"two poses are named {name!r}", field=f"{where}.name")
        point = data.get("point", opts["point"])
        if point not in mech.points:
            raise InputError(f"no point {point!r} in {mech.name} (points: {', '.join(mech.points)})",
                             field=f"{where}.point")
        picks = [(key, data[key]) for key in ("lowest", "highest") if key in data]
        if len(picks) > 1:
            raise InputError("give lowest or highest, not both", field=f"{where}.highest")
        if picks and picks[0][1] not in _pickable(mech, opts):
            raise InputError(f"{picks[0][0]}: {picks[0][1]!r} has no value at one position; choose from: "
                             f"{', '.join(_pickable(mech, opts))}", field=f"{where}.{picks[0][0]}")
        out.append(Pose(name, _held(mech, data.get("inputs", {}), f"{where}.inputs"), point,
                        picks[0] if picks else None))
    return tuple(out)


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
    """Refuse a mechanism without closed loops or wrong options (see the module docstring); a task file is read
    once."""
    if not mech.closures:
        raise InputError(f"{mech.name} has no closed loops: the linkage analysis sweeps closed-loop mechanisms")
    opts = _options(mech, options)
    if opts["task"] is not None:
        from ...dynamics.task import read_task

        read_task(opts["task"], mech)


def output_names(mech, options: dict[str, Any]) -> list[str]:
    """The names of the outputs for ``options`` without running: the point's extents (z too in a spatial loop),
    the smallest transmission angle (of a mechanism with such measures), each cylinder's largest force and, with its
    bore and rod given, its largest pressure."""
    opts = _options(mech, options)
    names = _names(mech, opts)
    for pose in opts["poses"]:
        names += [f"{pose.name}.{n}" for n in _names(mech, opts) if not (pose.single(mech) and n in _TRAVELS)]
    return names


def _names(mech, opts: dict[str, Any]) -> list[str]:
    """The outputs of one set of positions (the sweep's, a pose's)."""
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
    """The files the analysis of one design reads: the task's and the trajectory CSV it names, if a task is
    given."""
    from .dynamics import task_files

    opts = _options(mech, options)
    return task_files(opts["task"], mech) if opts["task"] is not None else []


def outputs(mech, options: dict[str, Any], seed: int) -> dict[str, float]:
    """The outputs of one design (m, deg, N, Pa; see the module docstring). ``seed`` is not used (no random
    draw)."""
    return _evaluate(mech, _options(mech, options))[0]


@dataclass
class _Sweep:
    """What :func:`_evaluate` computed the outputs from: the positions (``result``: its ``table`` and ``q``), the
    point measured, the extents' coordinates (``x``, ``y``, ``z`` or None; over the stroke box with
    ``working_range``), the holding forces (or None) and, for the analysis' sweep, each pose's ``_Sweep``."""

    result: Any
    x: np.ndarray
    y: np.ndarray
    z: np.ndarray | None
    forces: np.ndarray | None
    point: str = ""
    poses: dict[str, _Sweep] | None = None


@dataclass(frozen=True)
class _Positions:
    """Assembled positions: their table (a sweep's columns) and configurations (n, nq)."""

    table: Any
    q: np.ndarray

    def at(self, i: int) -> _Positions:
        return _Positions(self.table.iloc[[i]].reset_index(drop=True), self.q[[i]])


def _positions(mech, opts: dict[str, Any], held: dict[str, float], frames: list[str], pose: str | None = None
               ) -> _Positions:
    """The positions of the sweep with the inputs ``held`` (all of them: one position; none: the analysis' sweep),
    the others from their lower to their upper limit together; reached from the drawn position in :data:`RAMP`
    steps when an input is held."""
    from ...kinematics.loops import loop_solver
    from ...kinematics.sweeps import default_inputs, sweep

    n = opts["samples"]
    if not held:
        result = sweep(mech, samples=n, frames=frames, stop_on_failure=True)
        ramp = 0
    else:
        solver = loop_solver(mech)
        free = [name for name in mech.actuated if name not in held]
        count = n if free else 1
        swept = default_inputs(mech, n)
        values = {name: np.full(count, held[name]) if name in held else swept[name] for name in mech.actuated}
        drawn = np.asarray(mech.reference_q, dtype=float)
        ramp = RAMP
        inputs = {name: np.concatenate([np.linspace(drawn[solver.index[name]], v[0], ramp + 1)[:-1], v])
                  for name, v in values.items()}
        result = sweep(mech, inputs, frames=frames, stop_on_failure=True)
        n = count
    if len(result.failures):  # the sweep ends there: a design that cannot be assembled fails at once
        first = result.failures.iloc[0]
        k = int(first["sample"]) - ramp
        where = f"pose {pose!r}: " if pose is not None else ""
        what = f"position {k + 1} of {n}" if k >= 0 else "the way from the drawn position to its first position"
        raise MechatronError(f"{where}{what} cannot be assembled: {first['reason']}")
    if not ramp:
        return _Positions(result.table, result.q)
    return _Positions(result.table.iloc[ramp:].reset_index(drop=True), result.q[ramp:])


def _load_case(mech, opts: dict[str, Any]) -> tuple[tuple[Any, ...], list | None]:
    """(the mechanisms the forces are of, the loads): the task's payload on ``mech`` — with a payload carried on
    part of the task, ``mech`` with it and without it — and its loads with the ``load`` on the point (module
    docstring, "The load case")."""
    loads = list(_loads(opts["point"], opts) or [])
    cases: tuple[Any, ...] = (mech,)
    if opts["task"] is not None:
        from ...dynamics.task import read_task

        task = read_task(opts["task"], mech)
        cases = (task.mechanism,) if task.schedule is None else (task.mechanism, task.unloaded)
        loads = [*task.loads, *loads]
    return cases, loads or None


def _evaluate(mech, opts: dict[str, Any]) -> tuple[dict[str, float], _Sweep]:
    """The outputs for checked options ``opts`` (:func:`_options`) and what they were computed from."""
    point = opts["point"]
    case = _load_case(mech, opts)
    positions = _positions(mech, opts, opts["hold"], [point])
    cloud = None
    if opts["working_range"]:
        from ...machines.excavator import working_range

        box = working_range(mech, samples=opts["samples"])
        cloud = np.concatenate([box.cloud[:, 0], *[a[:, 0] for a in box.arcs]]), \
            np.concatenate([box.cloud[:, 1], *[a[:, 1] for a in box.arcs]])
    out, swept = _measured(mech, positions, point, opts, case, cloud)
    swept.poses = {}
    for pose in opts["poses"]:
        values, swept.poses[pose.name] = _pose(mech, opts, pose, case)
        out.update({f"{pose.name}.{k}": v for k, v in values.items()})
    return out, swept


def _pose(mech, opts: dict[str, Any], pose: Pose, case) -> tuple[dict[str, float], _Sweep]:
    """The outputs of a pose (module docstring) and what they were computed from."""
    point = opts["point"]
    positions = _positions(mech, opts, pose.inputs, list(dict.fromkeys([point, pose.point])), pose.name)
    if pose.pick is not None:
        kind, name = pose.pick
        values = _per_position(mech, name, positions, point, opts, case)
        positions = positions.at(int(np.argmin(values) if kind == "lowest" else np.argmax(values)))
    out, swept = _measured(mech, positions, pose.point, opts, case)
    if pose.single(mech):
        out = {k: v for k, v in out.items() if k not in _TRAVELS}
    return out, swept


def _per_position(mech, name: str, positions: _Positions, point: str, opts: dict[str, Any], case) -> np.ndarray:
    """The output ``name`` of each position alone, of ``point``: x, y or −y, the smallest transmission angle
    (deg), a cylinder's |force| or pressure."""
    table = positions.table
    if name in ("reach_m", "height_m", "depth_m"):
        values = table[f"{point}_{'x' if name == 'reach_m' else 'y'}"].to_numpy()
        return -values if name == "depth_m" else values
    if name == "min_transmission_angle_deg":
        angles = [m.name for m in mech.measures if m.kind == "transmission_angle"]
        return np.degrees(table[angles].to_numpy().min(axis=1))
    forces, _ = _cylinder_outputs(mech, positions.q, opts, case)
    cylinder, kind = name.rsplit("_max_", 1)
    f = forces[:, mech.actuated.index(cylinder)]
    return np.abs(f) if kind == "force_N" else np.array([opts["cylinders"][cylinder].pressure(v) for v in f])


def _measured(mech, positions: _Positions, point: str, opts: dict[str, Any], case, cloud=None
              ) -> tuple[dict[str, float], _Sweep]:
    """The outputs of ``positions`` for ``point`` (the extents over ``cloud``, (x, y), where given) and what they
    were computed from."""
    table = positions.table
    x, y = (table[f"{point}_x"].to_numpy(), table[f"{point}_y"].to_numpy()) if cloud is None else cloud
    out = {"reach_m": float(x.max()), "height_m": float(y.max()), "depth_m": float(-y.min()) + 0.0,
           "x_travel_m": float(x.max() - x.min()), "y_travel_m": float(y.max() - y.min())}
    z = None
    if f"{point}_z" in table:  # a spatial loop: the travel along z too
        z = table[f"{point}_z"].to_numpy()
        out["z_travel_m"] = float(z.max() - z.min())
    angles = [m.name for m in mech.measures if m.kind == "transmission_angle"]
    if angles:
        out["min_transmission_angle_deg"] = float(np.degrees(table[angles].to_numpy().min()))
    forces = None
    if mech.cylinders:
        forces, cylinder = _cylinder_outputs(mech, positions.q, opts, case)
        out.update(cylinder)
    return out, _Sweep(positions, x, y, z, forces, point)


def _loads(point: str, opts: dict[str, Any]) -> list | None:
    """The ``load`` option as loads on the point (world Fx, Fy, N), or None."""
    from ...model.loads import Load

    return [Load(point, [*opts["load"], 0.0])] if opts["load"] is not None else None


def _cylinder_outputs(mech, Q: np.ndarray, opts: dict[str, Any], case) -> tuple[np.ndarray, dict[str, float]]:
    """The holding forces (N, n_actuated) of the load case ``case`` (:func:`_load_case`) and each cylinder's largest
    force and pressure."""
    from ...dynamics.trajectory import holding_forces

    mechanisms, loads = case
    each = np.stack([np.atleast_2d(holding_forces(m, Q, loads)) for m in mechanisms])  # (cases, N, n_actuated)
    forces = np.take_along_axis(each, np.argmax(np.abs(each), axis=0)[None], axis=0)[0]
    out = {}
    for j, name in enumerate(mech.actuated):
        if name not in mech.cylinders:
            continue
        out[f"{name}_max_force_N"] = float(np.abs(forces[:, j]).max())
        if name in opts["cylinders"]:
            spec = opts["cylinders"][name]
            out[f"{name}_max_pressure_Pa"] = float(max(spec.pressure(f) for f in each[:, :, j].ravel()))
    return forces, out


# ------------------------------------------------------------------------------------------------ exact gradients
#: The outputs :func:`gradients` differentiates (all of them; ``CYLINDER`` stands for each cylinder's name): every
#: one of :func:`output_names` gets its gradient (:func:`gradient_outputs` names them for a mechanism).
GRADIENT_OUTPUTS = OUTPUTS


def gradient_outputs(mech, options: dict[str, Any]) -> list[str]:
    """The names of the outputs :func:`gradients` gives gradients of for ``options``, without running: every output
    of :func:`output_names`, but the forces and pressures with a ``task`` (a payload's mechanism has no symbolic
    form)."""
    names = output_names(mech, options)
    if _options(mech, options)["task"] is None:
        return names
    return [n for n in names if not n.endswith(("_max_force_N", "_max_pressure_Pa"))]


def gradients(mech, options: dict[str, Any], parameters: list[str]
              ) -> tuple[dict[str, float], dict[str, np.ndarray]]:
    """The outputs of one design (exactly as :func:`outputs` gives them, one sweep) and the exact gradient of each
    output of :func:`gradient_outputs` with respect to the named geometric ``parameters`` of ``mech`` (shape
    (len(parameters),): m per m, m per rad, deg per m for the transmission angle, N and Pa per unit of the
    parameter), the inputs held at their samples (module docstring); a pose's the same at its positions (a picked
    pose's position held).

    Raises:
        InputError: for wrong options or a name that is no parameter of ``mech``; for cylinder outputs of a
            mechanism without a symbolic form (:func:`~mechatron.dynamics.sensitivity.parameter_sensitivities`).
        MechatronError: for a design that cannot be assembled (as :func:`outputs`), one singular at an extremal
            sample, or (``working_range``) an extreme of the stroke box off the reference configuration's branch.
    """
    from ...model.derivatives import placement_derivatives

    opts = _options(mech, options)
    names = tuple(parameters)
    derivatives = placement_derivatives(mech, names)  # refuses unknown names before the sweep
    out, swept = _evaluate(mech, opts)
    if not names:
        return out, {key: np.zeros(0) for key in out}
    at = _PointDerivatives(mech, derivatives)
    extents = _working_range_extents(mech, opts, swept, at) if opts["working_range"] else None
    grad = _gradients_of(mech, names, swept, opts, at, out, extents)
    for pose in opts["poses"]:
        for key, value in _gradients_of(mech, names, swept.poses[pose.name], opts, at, out).items():
            if not (pose.single(mech) and key in _TRAVELS):
                grad[f"{pose.name}.{key}"] = value
    n_l = len(names)
    return out, {key: np.asarray(value, dtype=float).reshape(n_l) + 0.0 for key, value in grad.items()}


def _gradients_of(mech, names: tuple[str, ...], swept: _Sweep, opts: dict[str, Any], at: _PointDerivatives,
                  out: dict[str, float], extents: dict | None = None) -> dict[str, np.ndarray]:
    """The gradients of the outputs of one set of positions (the sweep's or a pose's; ``extents``: those of the
    stroke box with ``working_range``)."""
    point, Q = swept.point, swept.result.q

    def coordinate(values: np.ndarray, axis: int, largest: bool) -> np.ndarray:
        i = int(np.argmax(values) if largest else np.argmin(values))
        return at(Q[i], point)[axis]

    if extents is None:
        extents = {"x": (coordinate(swept.x, 0, True), coordinate(swept.x, 0, False)),
                   "y": (coordinate(swept.y, 1, True), coordinate(swept.y, 1, False))}
    (x_max, x_min), (y_max, y_min) = extents["x"], extents["y"]
    grad = {"reach_m": x_max, "height_m": y_max, "depth_m": -y_min, "x_travel_m": x_max - x_min,
            "y_travel_m": y_max - y_min}
    if swept.z is not None:
        grad["z_travel_m"] = coordinate(swept.z, 2, True) - coordinate(swept.z, 2, False)
    if "min_transmission_angle_deg" in out:
        grad["min_transmission_angle_deg"] = _angle_gradient(mech, swept.result, at)
    if swept.forces is not None and opts["task"] is None:
        grad.update(_cylinder_gradients(mech, names, Q, swept.forces, opts["point"], opts))
    return grad


class _PointDerivatives:
    """dr/dl (3, n_l) of frames at assembled configurations, the inputs held: J_r dq/dl + ∂r/∂l|_q, with
    dq/dl = −(∂Φ/∂q_d)⁻¹ ∂Φ/∂l taken once per configuration."""

    def __init__(self, mech, derivatives) -> None:
        from ...kinematics.loops import loop_solver

        self.mech, self.derivatives = mech, derivatives
        self.solver = loop_solver(mech)
        self._loops: dict[bytes, np.ndarray] = {}

    def __call__(self, q: np.ndarray, frame: str) -> np.ndarray:
        import pinocchio as pin

        from ...accuracy.sensitivity import LWA, frame_parameter_twists, loop_derivatives

        mech, n_l = self.mech, len(self.derivatives.names)
        if not n_l:
            return np.zeros((3, 0))
        q = np.asarray(q, dtype=float)
        key = q.tobytes()
        if key not in self._loops:
            self._loops[key] = loop_derivatives(mech, self.solver, self.derivatives, q)[0]
        fid = mech.frame_id(frame)
        J = pin.computeFrameJacobian(mech.model, mech.data, q, fid, LWA)  # forward kinematics at q too
        pin.updateFramePlacements(mech.model, mech.data)
        return J[:3] @ self._loops[key] + frame_parameter_twists(mech, self.derivatives, fid)[:3]


def _angle_gradient(mech, result, at: _PointDerivatives) -> np.ndarray:
    """d(min μ)/dl (deg per unit of l) at the sample and measure of the smallest transmission angle: μ = atan2(|u ×
    w|, |u · w|) with u = b − a, w = d − c (the angle :func:`mechatron.kinematics.geometry.transmission_angles`
    gives)."""
    import pinocchio as pin

    measures = [m for m in mech.measures if m.kind == "transmission_angle"]
    values = result.table[[m.name for m in measures]].to_numpy()
    i, k = np.unravel_index(int(np.argmin(values)), values.shape)
    q = result.q[i]
    a, b, c, d = (at(q, name)[:2] for name in measures[k].points)
    pin.forwardKinematics(mech.model, mech.data, q)
    pa, pb, pc, pd = (pin.updateFramePlacement(mech.model, mech.data, mech.frame_id(name)).translation[:2]
                      for name in measures[k].points)
    u, w, du, dw = pb - pa, pd - pc, b - a, d - c
    cross, dot = u[0] * w[1] - u[1] * w[0], u @ w
    d_cross = du[0] * w[1] + u[0] * dw[1] - du[1] * w[0] - u[1] * dw[0]
    d_dot = du.T @ w + dw.T @ u
    d_mu = (abs(dot) * np.sign(cross) * d_cross - abs(cross) * np.sign(dot) * d_dot) / (cross ** 2 + dot ** 2)
    return np.degrees(d_mu)


def _cylinder_gradients(mech, names: tuple[str, ...], Q: np.ndarray, forces: np.ndarray, point: str,
                        opts: dict[str, Any]) -> dict[str, np.ndarray]:
    """d/dl of each cylinder's largest force |f| (sign(f) df/dl at its sample) and largest pressure (the pressure's
    slope times df/dl there), df/dl the exact derivative of the holding force
    (:func:`~mechatron.dynamics.sensitivity.parameter_sensitivities`, at those samples only)."""
    from ...dynamics.sensitivity import parameter_sensitivities

    picks: dict[tuple[str, str], int] = {}
    for j, name in enumerate(mech.actuated):
        if name not in mech.cylinders:
            continue
        picks[(name, "force")] = int(np.argmax(np.abs(forces[:, j])))
        if name in opts["cylinders"]:
            spec = opts["cylinders"][name]
            picks[(name, "pressure")] = int(np.argmax([spec.pressure(f) for f in forces[:, j]]))
    samples = sorted(set(picks.values()))
    if not samples:
        return {}
    sens = parameter_sensitivities(mech, Q[samples], frames=(point,), parameters=names, loads=_loads(point, opts))
    out = {}
    for (name, kind), i in picks.items():
        j, row = mech.actuated.index(name), samples.index(i)
        f, df = forces[i, j], sens.d_force[row, j]
        if kind == "force":
            out[f"{name}_max_force_N"] = np.sign(f) * df
        else:
            spec = opts["cylinders"][name]
            slope = 1.0 / (spec.count * spec.piston_area) if f / spec.count >= 0 else \
                -1.0 / (spec.count * spec.annulus_area)
            out[f"{name}_max_pressure_Pa"] = slope * df
    return out


def _stroke_box_inputs(mech, samples: int) -> np.ndarray:
    """The cylinders' lengths (n, 3; ``mech.cylinders`` order) of every tip position of
    :func:`mechatron.machines.excavator.working_range` in the order its extents are taken: the faces' grids (one
    cylinder at a limit, the other two over their strokes), then the edges' arcs."""
    names = list(mech.cylinders)
    strokes = {n: np.linspace(*mech.cylinders[n].stroke, samples) for n in names}
    faces, arcs = [], []
    for fixed in names:
        free = [n for n in names if n != fixed]
        for limit in mech.cylinders[fixed].stroke:
            a, b = np.meshgrid(strokes[free[0]], strokes[free[1]], indexing="ij")
            values = {fixed: np.full(a.size, limit), free[0]: a.ravel(), free[1]: b.ravel()}
            faces.append(np.column_stack([values[n] for n in names]))
        for lo_hi in ((0, 0), (0, 1), (1, 1), (1, 0)):
            values = {n: np.full(samples, mech.cylinders[n].stroke[k]) for n, k in zip(free, lo_hi)}
            values[fixed] = strokes[fixed]
            arcs.append(np.column_stack([values[n] for n in names]))
    return np.vstack(faces + arcs)


def _working_range_extents(mech, opts: dict[str, Any], swept: _Sweep, at: _PointDerivatives
                           ) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """The derivatives of the tip's (x, y) (``V``, the frame the working range is of) at its largest and smallest
    x and y over the stroke box, each position assembled again at its cylinders' lengths from the reference
    configuration (continuation along the inputs) and checked against the working range's.

    Raises:
        MechatronError: when one lands elsewhere (another assembly branch): no gradient rather than a wrong one.
    """
    from ...kinematics.loops import assemble

    inputs = _stroke_box_inputs(mech, opts["samples"])
    if len(inputs) != len(swept.x):  # pragma: no cover - the two layouts are one
        raise MechatronError(f"{mech.name}: the working range has {len(swept.x)} positions, its stroke box "
                             f"{len(inputs)}")
    names = list(mech.cylinders)
    out = {}
    for axis, values in (("x", swept.x), ("y", swept.y)):
        pair = []
        for i in (int(np.argmax(values)), int(np.argmin(values))):
            q = assemble(mech, dict(zip(names, map(float, inputs[i]))), guess=mech.reference_q)
            derivative = at(q, "V")
            tip = mech.data.oMf[mech.frame_id("V")].translation
            if abs(tip[0] - swept.x[i]) + abs(tip[1] - swept.y[i]) > 1e-7 * max(1.0, float(np.abs(tip).max())):
                lengths = ", ".join(f"{n} = {v:.6g}" for n, v in zip(names, inputs[i]))
                raise MechatronError(f"{mech.name}: the working range's extreme at {lengths} is not on the branch "
                                     "of the reference configuration; its gradient cannot be taken")
            pair.append(derivative[:2]["xy".index(axis)])
        out[axis] = (pair[0], pair[1])
    return out
