r"""Derivatives of a mechanism's model with respect to its named geometric parameters.

A parameter l_k (a DH a, d, α, θ; a URDF origin; a linkage length or pin coordinate) moves the constant placements of
the Pinocchio model and the mass properties of its bodies. To first order every joint placement M_j and frame
placement M_f turns into M exp(ξ Δl_k) — a local twist ξ ([v; ω] order) per placement and parameter — and every
body's dynamic parameters π = [m, m c, I] (Pinocchio's ``toDynamicParameters``, in the joint frame) into
π + ∂π/∂l_k Δl_k. These are the derivatives the sensitivities of positions, velocities and forces are built on.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pinocchio as pin
from numpy.typing import NDArray

from ..errors import InputError
from .mechanism import Mechanism, unknown_name_error


@dataclass(frozen=True)
class PlacementDerivatives:
    """Local twists ξ with M(l + h e_k) = M(l) exp(ξ h) + O(h²) for every parameter k: ``joints`` (n_l, njoints, 6)
    for the joint placements, ``frames`` (n_l, nframes, 6) for the frame placements ([v; ω] order); and
    ``inertias`` (n_l, njoints, 10), the derivatives of every joint's dynamic parameters
    [m, m c_x, m c_y, m c_z, I_xx, I_xy, I_yy, I_xz, I_yz, I_zz] (joint frame, about the joint's origin)."""

    names: tuple[str, ...]
    joints: NDArray[np.float64]
    frames: NDArray[np.float64]
    inertias: NDArray[np.float64]


def placements(model: pin.Model) -> list[pin.SE3]:
    """Every constant placement of ``model``: the joint placements, then the frame placements."""
    return list(model.jointPlacements) + [f.placement for f in model.frames]


def _structure(model: pin.Model) -> tuple:
    return (tuple(model.names), tuple(f.name for f in model.frames),
            tuple(j.shortname() for j in model.joints), tuple(f.parentJoint for f in model.frames))


def placement_derivatives(mech: Mechanism, names: Sequence[str] | None = None) -> PlacementDerivatives:
    """The placement twists and inertia derivatives of ``names`` (default every parameter); kept in the
    mechanism's cache."""
    names = tuple(mech.parameters) if names is None else tuple(names)
    for name in names:
        if name not in mech.parameters:
            raise unknown_name_error(f"parameter of {mech.name}", name, list(mech.parameters))
    cache = mech.cached("model.placement_derivatives", dict)
    if names not in cache:
        cache[names] = _by_differences(mech, names)
    return cache[names]


def _by_differences(mech: Mechanism, names: tuple[str, ...]) -> PlacementDerivatives:
    """Central differences of the rebuilt model's placements and inertias (step 1e-6 of max(1, |l|))."""
    model = mech.model
    nominal = placements(model)
    nj, nf = model.njoints, model.nframes
    joints, frames, inertias = np.zeros((len(names), nj, 6)), np.zeros((len(names), nf, 6)), np.zeros((len(names),
                                                                                                       nj, 10))
    values = mech.parameter_values()
    for k, name in enumerate(names):
        h = 1e-6 * max(1.0, abs(values[name]))
        twists, dynamic = [], []
        for sign in (1.0, -1.0):
            other = mech.with_parameters({name: values[name] + sign * h}).model
            if _structure(other) != _structure(model):
                raise InputError(f"{mech.name}: changing {name} changes the model's structure; its sensitivity "
                                 "cannot be taken")
            twists.append(np.array([pin.log6(m.actInv(p)).vector for m, p in zip(nominal, placements(other))]))
            dynamic.append(np.array([inertia.toDynamicParameters() for inertia in other.inertias]))
        xi = (twists[0] - twists[1]) / (2 * h)
        joints[k], frames[k] = xi[:nj], xi[nj:]
        inertias[k] = (dynamic[0] - dynamic[1]) / (2 * h)
    return PlacementDerivatives(names, joints, frames, inertias)
