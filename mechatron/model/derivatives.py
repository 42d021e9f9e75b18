r"""Derivatives of a mechanism's model with respect to its named geometric parameters.

A parameter l_k (a DH a, d, α, θ; a URDF origin; a linkage length or pin coordinate) moves the constant placements of
the Pinocchio model, the mass properties of its bodies and a few constants of its closures. To first order every
joint placement M_j and frame placement M_f turns into M exp(ξ Δl_k) — a local twist ξ ([v; ω] order) per placement
and parameter — every body's dynamic parameters π = [m, m c, I] (Pinocchio's ``toDynamicParameters``, in the joint
frame, about its origin) into π + ∂π/∂l_k Δl_k, and a locked slider's angle offset or a gear's offset into
c + ∂c/∂l_k Δl_k. These are the derivatives the sensitivities of positions, velocities and forces are built on.

They are exact: each kind of mechanism differentiates the formulas it is built with (a linkage's shapes and layout
through CasADi, :func:`mechatron.model.linkage.linkage_derivatives`; a DH table's factors, a URDF's origins, a
spatial drawing's points in closed form), kept on the mechanism as ``Mechanism.derivatives``. A mechanism built in
Python with only a ``rebuild`` gets central differences of the rebuilt model instead.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
import pinocchio as pin
from numpy.typing import NDArray

from ..errors import InputError
from .closures import Gear, Slider
from .mechanism import Mechanism, unknown_name_error

Floats = NDArray[np.float64]


@dataclass(frozen=True)
class PlacementDerivatives:
    """Local twists ξ with M(l + h e_k) = M(l) exp(ξ h) + O(h²) for every parameter k: ``joints`` (n_l, njoints, 6)
    for the joint placements, ``frames`` (n_l, nframes, 6) for the frame placements ([v; ω] order); ``inertias``
    (n_l, njoints, 10), the derivatives of every joint's dynamic parameters [m, m c_x, m c_y, m c_z, I_xx, I_xy,
    I_yy, I_xz, I_yz, I_zz] (joint frame, about the joint's origin); and ``constants``, {closure name: {constant:
    ∂c/∂l (n_l,)}} for the closure constants the parameters move (a locked slider's ``angle_offset``, a gear's
    ``offset``; absent ones do not move)."""

    names: tuple[str, ...]
    joints: Floats
    frames: Floats
    inertias: Floats
    constants: Mapping[str, Mapping[str, Floats]] = field(default_factory=dict)


def placements(model: pin.Model) -> list[pin.SE3]:
    """Every constant placement of ``model``: the joint placements, then the frame placements."""
    return list(model.jointPlacements) + [f.placement for f in model.frames]


def placement_derivatives(mech: Mechanism, names: Sequence[str] | None = None) -> PlacementDerivatives:
    """The placement twists, inertia and closure-constant derivatives of ``names`` (default every parameter): the
    mechanism's exact ones (``mech.derivatives``), else central differences of the rebuilt model; kept in the
    mechanism's cache."""
    names = tuple(mech.parameters) if names is None else tuple(names)
    for name in names:
        if name not in mech.parameters:
            raise unknown_name_error(f"parameter of {mech.name}", name, list(mech.parameters))
    cache = mech.cached("model.placement_derivatives", dict)
    if names not in cache:
        exact = getattr(mech, "derivatives", None)
        cache[names] = exact(names) if exact is not None else _by_differences(mech, names)
    return cache[names]


# ------------------------------------------------------------------------------------------------ building blocks
def empty(model: pin.Model, names: Sequence[str]) -> PlacementDerivatives:
    """Zero derivatives of every placement and inertia of ``model`` for ``names``, to be filled in."""
    n = len(names)
    return PlacementDerivatives(tuple(names), np.zeros((n, model.njoints, 6)), np.zeros((n, model.nframes, 6)),
                                np.zeros((n, model.njoints, 10)), {})


def planar_twists(angle: float, dx: Floats, dy: Floats, dangle: Floats) -> Floats:
    """Local twists (n_l, 6) of a planar placement (R_z(θ), (x, y, 0)) from the derivatives of x, y and θ (each
    (n_l,)): ξ = [R_z(θ)ᵀ (dx, dy, 0); (0, 0, dθ)], so that M(l + dl) = M exp(ξ dl) to first order."""
    c, s = math.cos(angle), math.sin(angle)
    out = np.zeros((len(dx), 6))
    out[:, 0], out[:, 1], out[:, 5] = c * dx + s * dy, -s * dx + c * dy, dangle
    return out


def planar_dynamic_parameters(mass, cx, cy, izz) -> list:
    """Pinocchio's dynamic parameters [m, m c_x, m c_y, m c_z, I_xx, I_xy, I_yy, I_xz, I_yz, I_zz] (about the joint
    origin) of a planar body: mass m at (c_x, c_y, 0), I_zz about its centre and I_xx = I_yy = I_zz/2 (a thin
    plate's, as the planar builder makes it): I_O = I_C + m (|c|² 1 − c cᵀ). Works on numbers and CasADi
    expressions."""
    return [mass, mass * cx, mass * cy, 0.0, izz / 2 + mass * cy * cy, -mass * cx * cy, izz / 2 + mass * cx * cx,
            0.0, 0.0, izz + mass * (cx * cx + cy * cy)]


def inertia_variation(inertia: pin.Inertia, twist: Floats) -> Floats:
    """The derivative of the dynamic parameters of ``inertia`` (in a joint frame) when the body it is attached by
    moves by exp(η δ) in that frame: d/dδ exp(η δ)·Y at δ = 0 = η ×* Y − Y η× (Pinocchio's ``variation``), read
    back as [dm, d(m c), dI_O] (10,)."""
    dY = inertia.variation(pin.Motion(np.asarray(twist, dtype=float)))
    dmc = np.array([dY[5, 1], dY[3, 2], dY[4, 0]])  # m [c]× is the lower-left block
    dI = dY[3:, 3:]
    return np.array([dY[0, 0], *dmc, dI[0, 0], dI[0, 1], dI[1, 1], dI[0, 2], dI[1, 2], dI[2, 2]])


def frame_id(model: pin.Model, name: str, kind: pin.FrameType) -> int:
    """The index of the frame ``name`` of type ``kind``."""
    return model.getFrameId(name, kind)


# ------------------------------------------------------------------------------------------------ differences
def _structure(model: pin.Model) -> tuple:
    return (tuple(model.names), tuple(f.name for f in model.frames),
            tuple(j.shortname() for j in model.joints), tuple(f.parentJoint for f in model.frames))


def _constants(closures: Sequence) -> dict[str, dict[str, float]]:
    out: dict[str, dict[str, float]] = {}
    for c in closures:
        if isinstance(c, Slider) and c.lock_angle:
            out[c.name] = {"angle_offset": c.angle_offset}
        elif isinstance(c, Gear):
            out[c.name] = {"offset": c.offset}
    return out


def _by_differences(mech: Mechanism, names: tuple[str, ...]) -> PlacementDerivatives:
    """Central differences of the rebuilt model's placements, inertias and closure constants (step 1e-6 of
    max(1, |l|)): for mechanisms without exact derivatives."""
    model = mech.model
    nominal = placements(model)
    out = empty(model, names)
    nj = model.njoints
    values = mech.parameter_values()
    constants = {name: {key: np.zeros(len(names)) for key in keys} for name, keys in _constants(mech.closures).items()}
    for k, name in enumerate(names):
        h = 1e-6 * max(1.0, abs(values[name]))
        twists, dynamic, moved = [], [], []
        for sign in (1.0, -1.0):
            other = mech.with_parameters({name: values[name] + sign * h})
            if _structure(other.model) != _structure(model):
                raise InputError(f"{mech.name}: changing {name} changes the model's structure; its sensitivity "
                                 "cannot be taken")
            twists.append(np.array([pin.log6(m.actInv(p)).vector for m, p in zip(nominal, placements(other.model))]))
            dynamic.append(np.array([inertia.toDynamicParameters() for inertia in other.model.inertias]))
            moved.append(_constants(other.closures))
        xi = (twists[0] - twists[1]) / (2 * h)
        out.joints[k], out.frames[k] = xi[:nj], xi[nj:]
        out.inertias[k] = (dynamic[0] - dynamic[1]) / (2 * h)
        for closure, keys in constants.items():
            for key, column in keys.items():
                column[k] = (moved[0][closure][key] - moved[1][closure][key]) / (2 * h)
    return PlacementDerivatives(names, out.joints, out.frames, out.inertias, constants)
