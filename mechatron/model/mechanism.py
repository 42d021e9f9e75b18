"""The :class:`Mechanism`: one object for every analysed system.

A mechanism is a Pinocchio kinematic tree (``model``) with its workspace (``data``), named frames (points and links),
a registry of named geometric parameters with nominal values, drive data per joint, and (for closed-loop linkages) the
closure constraints and the actuated coordinates. Serial arms are mechanisms without closures. Every analysis of the
package takes a ``Mechanism``; Pinocchio does all rigid-body computations.

A ``Mechanism`` is data. The analyses are functions of the layers above (:mod:`mechatron.kinematics`,
:mod:`mechatron.dynamics`, …) that take it as their first argument, as Pinocchio's algorithms take a model. What they
build once per mechanism (a loop solver, a pool of model copies) they keep in its declared cache,
:meth:`Mechanism.cached`.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Hashable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any, TypeVar

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike

from ..errors import InputError
from .closures import ClosureSystem
from .parameter import Parameter

if TYPE_CHECKING:  # pragma: no cover
    from .dh_table import DHTable, Drive

T = TypeVar("T")


def unknown_name_error(what: str, name: str, known: list[str], **where: Any) -> InputError:
    """An :class:`InputError` for an unknown name, suggesting the closest known names."""
    import difflib  # imported here: only an error needs it

    close = difflib.get_close_matches(name, known, n=3)
    hint = f"; did you mean {', '.join(close)}?" if close else ""
    listing = ", ".join(known) if len(known) <= 30 else ", ".join(known[:30]) + ", ..."
    return InputError(f"unknown {what} {name!r}{hint} (known: {listing})", **where)


_FRAME_PREFERENCE = (pin.FrameType.OP_FRAME, pin.FrameType.BODY, pin.FrameType.JOINT, pin.FrameType.FIXED_JOINT,
                     pin.FrameType.SENSOR)


def find_frame(model: pin.Model, name: str) -> int | None:
    """Index of the frame called ``name`` (an operational or body frame before a joint frame of the same name)."""
    return frame_index(model).get(name)


def frame_index(model: pin.Model) -> dict[str, int]:
    """Every frame name of ``model`` with the index :func:`find_frame` gives it, in one pass over the frames (a
    model with thousands of points looks each one up in constant time)."""
    index: dict[str, int] = {}
    for i, frame in enumerate(model.frames):
        known = index.get(frame.name)
        if known is None or (_FRAME_PREFERENCE.index(frame.type)
                             < _FRAME_PREFERENCE.index(model.frames[known].type)):
            index[frame.name] = i
    return index


@dataclass(frozen=True)
class SketchLine:
    """A polyline through named points, drawn to show a body (``kind`` "link", "ground" or "cylinder")."""

    name: str
    points: tuple[str, ...]
    kind: str = "link"


@dataclass(frozen=True)
class Cylinder:
    """A hydraulic cylinder of a mechanism: pin ``base`` to pin ``eye``, coordinate ``name`` = its length (m) in
    ``stroke`` = (L_min, L_max); ``count`` cylinders act side by side (a twin boom cylinder has 2)."""

    name: str
    base: str
    eye: str
    stroke: tuple[float, float]
    count: int = 1

    @property
    def ratio(self) -> float:
        """λ = L_max / L_min."""
        return self.stroke[1] / self.stroke[0]


@dataclass(frozen=True)
class Measure:
    """A named geometric quantity reported along a motion.

    ``kind`` is "transmission_angle" (points a, b, c, d: the acute angle between lines ab and cd, rad),
    "lever_arm" (points base, eye, pivot: distance from pivot to the line base–eye, m) or "distance" (points a, b, m).
    ``minimum`` (same unit) makes the value a design check, e.g. a transmission angle of at least 30°.
    """

    name: str
    kind: str
    points: tuple[str, ...]
    minimum: float | None = None


@dataclass
class Mechanism:
    """A mechanism: a Pinocchio model plus everything mechatron knows about it.

    Attributes:
        name: Short name (the robot file's name).
        model: The ``pinocchio.Model`` (kinematic tree, inertias, limits, gravity, armature).
        parameters: Named geometric parameters with their nominal values.
        description: One line for listings.
        source: Where the model came from (file path), if anywhere.
        dh: The DH table the model was built from, for DH arms.
        drives: Drive data (rotor inertia, gear ratio, efficiency) by joint name.
        closures: Closure constraints of closed loops (empty for serial arms), see :mod:`mechatron.closures`.
        actuated: Names of the actuated (input) coordinates; all joints for a serial arm.
        tool_frame: Name of the default output frame.
        rebuild: Function that builds the same mechanism with other parameter values.
        derivatives: Function giving the exact derivatives of the model's placements, inertias and closure
            constants with respect to named parameters (a
            :class:`~mechatron.model.derivatives.PlacementDerivatives`), if the builder knows them.
        reference_q: An assembled configuration (it names the default assembly branch).
        points: Named points (frames) of a linkage, in drawing order.
        sketch: Polylines through points that draw the mechanism.
        notes: Remarks about the model or its source (shown by ``mechatron show``).
        measures: Geometric quantities to report along a motion (transmission angles, lever arms).
        input_rates: Nominal rates of the actuated coordinates (m/s or rad/s) for sweeps; 1 where not given.
        cylinders: Hydraulic cylinders by coordinate name.
        branches: Named assembled configurations, one per assembly branch (``reference`` is always one of them).
        link_masses_include_drives: Whether the bodies' masses already include their drives (motors, gears) — a
            robot file's or URDF's statement (docs/robot_file.md, docs/urdf.md): the sizing then adds no chosen
            drive's mass (:func:`~mechatron.drives.system.size_mechanism`).
    """

    name: str
    model: pin.Model
    parameters: dict[str, Parameter] = field(default_factory=dict)
    description: str = ""
    source: str | None = None
    dh: DHTable | None = None
    drives: dict[str, Drive] = field(default_factory=dict)
    closures: list[Any] = field(default_factory=list)
    actuated: list[str] = field(default_factory=list)
    tool_frame: str = "tool"
    rebuild: Callable[[dict[str, float]], Mechanism] | None = field(default=None, repr=False)
    derivatives: Callable[[tuple[str, ...]], Any] | None = field(default=None, repr=False)
    reference_q: np.ndarray | None = None
    points: list[str] = field(default_factory=list)
    sketch: list[SketchLine] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    measures: list[Measure] = field(default_factory=list)
    input_rates: dict[str, float] = field(default_factory=dict)
    cylinders: dict[str, Cylinder] = field(default_factory=dict)
    branches: dict[str, np.ndarray] = field(default_factory=dict)
    link_masses_include_drives: bool = False
    _cache: dict[Hashable, Any] = field(default_factory=dict, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        self.data = self.model.createData()
        if self.reference_q is not None:
            self.branches = {"reference": np.asarray(self.reference_q, dtype=float), **self.branches}
        if not self.actuated:
            self.actuated = self.joint_names

    # ------------------------------------------------------------------------------------------- structure
    @property
    def nq(self) -> int:
        return self.model.nq

    @property
    def nv(self) -> int:
        return self.model.nv

    @property
    def joint_names(self) -> list[str]:
        """Names of the joints (generalized coordinates), in model order, without the universe."""
        return list(self.model.names)[1:]

    @property
    def frame_names(self) -> list[str]:
        return [f.name for f in self.model.frames]

    @property
    def link_names(self) -> list[str]:
        """One frame per moving body (the first BODY frame attached to each joint), in joint order."""
        names: list[str] = []
        for joint_id in range(1, self.model.njoints):
            for frame in self.model.frames:
                if frame.parentJoint == joint_id and frame.type == pin.FrameType.BODY:
                    names.append(frame.name)
                    break
            else:
                names.append(self.model.names[joint_id])
        return names

    def frame_id(self, name: str) -> int:
        """Index of the frame called ``name``; a clear error listing the frames if there is none."""
        # cached by the frame count too: a frame added to the model in place is found
        index = self.cached(("frames", self.model.nframes), lambda: frame_index(self.model)).get(name)
        if index is None:
            raise unknown_name_error(f"frame of {self.name}", name, self.frame_names)
        return index

    def joint_id(self, name: str) -> int:
        if not self.model.existJointName(name):
            raise unknown_name_error(f"joint of {self.name}", name, self.joint_names)
        return self.model.getJointId(name)

    def joint_kind(self, joint: str | int) -> str:
        """``"revolute"`` or ``"prismatic"`` for one-axis joints (any axis), else Pinocchio's joint type name."""
        index = self.joint_id(joint) if isinstance(joint, str) else joint
        short = self.model.joints[index].shortname()
        if re.fullmatch(r"JointModel(R[XYZ]|RUB[XYZ]|RevoluteUnaligned|RevoluteUnboundedUnaligned)", short):
            return "revolute"
        if re.fullmatch(r"JointModel(P[XYZ]|PrismaticUnaligned)", short):
            return "prismatic"
        return short.removeprefix("JointModel")

    def angular_coordinates(self) -> np.ndarray:
        """(nv,) booleans: which joint coordinates are angles (revolute and continuous joints)."""
        out = np.zeros(self.nv, dtype=bool)
        for j in range(1, self.model.njoints):
            joint = self.model.joints[j]
            out[joint.idx_v:joint.idx_v + joint.nv] = self.joint_kind(j) == "revolute"
        return out

    def mobility(self, q: np.ndarray | None = None) -> int:
        """Degree of mobility W = nv − rank(closure Jacobian) at a regular configuration (default
        :attr:`reference_q`); W = nv for a serial chain."""
        return self.nv - self.closure_rank(q)

    def redundant_closure_equations(self, q: np.ndarray | None = None) -> int:
        """Number of closure equations that repeat others (rows − rank of the closure Jacobian)."""
        if not self.closures:
            return 0
        return self.closure_system().nrows - self.closure_rank(q)

    def with_actuated(self, actuated: list[str]) -> Mechanism:
        """The same mechanism driven by other coordinates (e.g. a crank-slider driven by its slider)."""
        return replace(self, actuated=list(actuated))

    def with_closures(self, closures: list[Any]) -> Mechanism:
        """The same tree with other closures."""
        return replace(self, closures=list(closures))

    def cached(self, key: Hashable, build: Callable[[], T]) -> T:
        """The value kept under ``key`` in this mechanism's cache, built by ``build()`` the first time.

        The cache belongs to this object: a mechanism derived from it (:meth:`with_parameters`, ``replace``) starts
        with an empty one. Analyses use it for what depends only on the mechanism (the loop solver, a model pool).
        """
        try:
            return self._cache[key]
        except KeyError:
            value = self._cache[key] = build()
            return value

    def closure_system(self) -> ClosureSystem:
        """The closures evaluated together (Φ, J, J̇ q̇), built once."""
        return self.cached("closure_system", lambda: ClosureSystem(self.model, self.closures, self.frame_id))

    def closure_rank(self, q: np.ndarray | None = None) -> int:
        """Rank of the closure Jacobian at ``q`` (default :attr:`reference_q`); 0 without closures."""
        if not self.closures:
            return 0
        _, J = self.closure_system().evaluate(np.asarray(self.reference_q if q is None else q, dtype=float))
        if J.size == 0:
            return 0
        return int(np.linalg.matrix_rank(J, tol=1e-9 * max(1.0, np.abs(J).max())))

    @property
    def total_mass(self) -> float:
        return float(sum(inertia.mass for inertia in self.model.inertias))

    # ------------------------------------------------------------------------------------------ parameters
    def parameter_values(self) -> dict[str, float]:
        return {name: p.value for name, p in self.parameters.items()}

    def with_parameters(self, values: Mapping[str, float] | None = None, **kwargs: float) -> Mechanism:
        """The same mechanism built with other values of some geometric parameters (SI units).

        Raises:
            InputError: for an unknown parameter name or a non-finite value.
        """
        overrides = {**(values or {}), **kwargs}
        if not overrides:
            return self
        for key, value in overrides.items():
            if key not in self.parameters:
                raise unknown_name_error(f"parameter of {self.name}", key, list(self.parameters))
            if isinstance(value, bool) or not np.isfinite(value):
                raise InputError(f"parameter {key} must be a finite number, got {value!r}")
        if self.rebuild is None:
            raise InputError(f"{self.name} cannot be rebuilt with other parameters")
        return self.rebuild({**self.parameter_values(), **{k: float(v) for k, v in overrides.items()}})

    # ------------------------------------------------------------------------------------------ configurations
    def neutral(self) -> np.ndarray:
        """The neutral configuration (all joint coordinates zero for revolute and prismatic joints)."""
        return pin.neutral(self.model)

    def random_configuration(self, rng: np.random.Generator | None = None, size: int | None = None) -> np.ndarray:
        """Random configurations within the joint limits, uniform in each joint's coordinates: shape (nq,) or
        (size, nq), drawn from ``rng`` (a numpy generator; a fresh one if not given).

        Joints with one coordinate (revolute, prismatic) are drawn uniformly between their limits, which they must
        have. Joints with more configuration coordinates than velocity coordinates get Pinocchio's
        ``randomConfiguration`` (seeded from ``rng``): a continuous joint a uniform angle as a unit (cos θ, sin θ), a
        free joint a uniform rotation (its translation within its limits, ±1 m where it has none).
        """
        rng = rng or np.random.default_rng()
        count = 1 if size is None else int(size)
        lower, upper = self.model.lowerPositionLimit, self.model.upperPositionLimit
        one_axis = [j for j in range(1, self.model.njoints) if self.model.joints[j].nq == 1]
        unbounded = [self.model.names[j] for j in one_axis
                     if not (np.isfinite(lower[self.model.joints[j].idx_q])
                             and np.isfinite(upper[self.model.joints[j].idx_q]))]
        if unbounded:
            raise InputError(f"{self.name}: random configurations need finite joint limits ({', '.join(unbounded)} "
                             "has none)")
        if len(one_axis) == self.model.njoints - 1:
            # one coordinate per joint: the same uniform law as randomConfiguration, drawn from the numpy generator
            out = rng.uniform(lower, upper, size=(count, self.nq))
        else:
            out = np.empty((count, self.nq))
            pin.seed(int(rng.integers(2**31 - 1)))
            low, high = np.where(np.isfinite(lower), lower, -1.0), np.where(np.isfinite(upper), upper, 1.0)
            for k in range(count):
                out[k] = pin.randomConfiguration(self.model, low, high)
        return out[0] if size is None else out

    # --------------------------------------------------------------------------- coordinates and configurations
    def configuration(self, coordinates: ArrayLike) -> np.ndarray:
        """The configuration q (nq,) or (N, nq) of joint coordinates (nv,) or (N, nv): q = neutral ⊕ coordinates
        (``pin.integrate``). For revolute (also continuous) and prismatic joints a coordinate is the joint angle
        (rad) or displacement (m); a continuous joint's q is (cos θ, sin θ). Identity when nq = nv."""
        values = np.asarray(coordinates, dtype=float)
        if values.shape[-1:] != (self.nv,):
            raise InputError(f"{self.name} needs {self.nv} joint coordinates ({', '.join(self.joint_names)}), "
                             f"got shape {values.shape}")
        return values.copy() if self.nq == self.nv else self._from_neutral(pin.integrate, values)

    def coordinates(self, q: ArrayLike) -> np.ndarray:
        """The joint coordinates (nv,) or (N, nv) (rad, m) of configurations q: q ⊖ neutral (``pin.difference``);
        angles of continuous joints in (−π, π]. Identity when nq = nv."""
        values = self.check_configuration(q)
        return values.copy() if self.nq == self.nv else self._from_neutral(pin.difference, values)

    def _from_neutral(self, operation: Callable[[pin.Model, np.ndarray, np.ndarray], np.ndarray],
                      values: np.ndarray) -> np.ndarray:
        """``operation(model, neutral, x)`` for every row x of ``values`` (one row or (N, n))."""
        neutral = pin.neutral(self.model)
        out = np.array([operation(self.model, neutral, x) for x in np.atleast_2d(values)])
        return out if values.ndim > 1 else out[0]

    def check_configuration(self, q: ArrayLike, what: str = "q") -> np.ndarray:
        """``q`` (nq,) or (N, nq) as a float array, or a clear error (wrong length, not finite)."""
        arr = np.asarray(q, dtype=float)
        if arr.shape[-1:] != (self.nq,):
            raise InputError(f"{what} must have {self.nq} values for {self.name} ({', '.join(self.joint_names)}), "
                             f"got shape {arr.shape}")
        if not np.all(np.isfinite(arr)):
            raise InputError(f"{what} must be finite, got {arr}")
        return arr

    def limit_violations(self, q: ArrayLike, labels: Sequence[str] | Callable[[int], str] | None = None
                         ) -> list[str]:
        """Human-readable list of the joint coordinates of the configuration ``q`` (nq,) outside their limits
        (rad, m; joints with one coordinate: continuous and free joints have none), one line per joint. For
        configurations (N, nq) each joint's line gives its farthest value and where it is (``labels[k]``, default
        ``sample k+1``; ``labels`` may be a function of k) and how many more configurations are outside."""
        q = self.check_configuration(q)
        joints = [j for j in range(1, self.model.njoints) if self.model.joints[j].nq == 1]
        names = [self.model.names[j] for j in joints]
        return self._violations(names, q[..., [self.model.joints[j].idx_q for j in joints]], labels)

    def _violations(self, names: Sequence[str], values: ArrayLike,
                              labels: Sequence[str] | Callable[[int], str] | None = None) -> list[str]:
        """:meth:`limit_violations` of the one-axis joints ``names`` at ``values`` (n,) or (N, n) (rad, m)."""
        values = np.asarray(values, dtype=float)
        batch = values.ndim == 2
        rows = np.atleast_2d(values)
        out = []
        for i, name in enumerate(names):
            index = self.model.joints[self.joint_id(name)].idx_q
            lo, hi = self.model.lowerPositionLimit[index], self.model.upperPositionLimit[index]
            column = rows[:, i]
            outside = ~((column >= lo) & (column <= hi))
            if not outside.any():
                continue
            k = int(np.argmax(np.where(outside, np.maximum(lo - column, column - hi), -np.inf)))
            line = f"{name} = {column[k]:g} outside [{lo:g}, {hi:g}]"
            if batch:
                where = (f"sample {k + 1}" if labels is None else labels(k) if callable(labels) else labels[k])
                more = int(outside.sum()) - 1
                line += f" at {where}" + (f" (and {more} more of {len(column)})" if more else "")
            out.append(line)
        return out

    def warn_limits(self, q: ArrayLike, what: str = "", labels: Sequence[str] | Callable[[int], str] | None = None
                    ) -> list[str]:
        """Warn (:class:`~mechatron.errors.LimitWarning`, one warning per joint) about the coordinates of ``q``
        outside their joint limits (:meth:`limit_violations`). ``what`` says where the values come from. Returns
        the messages."""
        import warnings

        from ..errors import LimitWarning

        messages = self.limit_violations(q, labels)
        for message in messages:
            warnings.warn(f"{what}: {message}" if what else message, LimitWarning, stacklevel=2)
        return messages
