"""Denavit–Hartenberg arms as mechanisms: :func:`dh_mechanism` (the :class:`~mechatron.model.mechanism.Mechanism` of a
DH table, :mod:`mechatron.model.dh_table`: the link matrices of [Egorov, section 4.3], the table and its Pinocchio
model) and the exact derivatives of its placements and inertias with respect to the table's parameters
(:func:`dh_derivatives`). The table's names are importable from here too."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pinocchio as pin

from .derivatives import PlacementDerivatives, empty, inertia_variation
from .dh_table import (
    CONVENTIONS,
    JOINT_KINDS,
    Convention,
    DHLink,
    DHTable,
    Drive,
    Inertial,
    JointKind,
    inertial_problem,
    placement_matrix,
    rot_x,
    rot_z,
    se3,
    trans,
)
from .mechanism import Mechanism

__all__ = ["CONVENTIONS", "JOINT_KINDS", "Convention", "DHLink", "DHTable", "Drive", "Inertial", "JointKind",
           "dh_derivatives", "dh_mechanism", "factor_twists", "inertial_problem", "placement_matrix", "rot_x", "rot_z",
           "se3", "trans"]


def factor_twists(factors: Sequence[tuple[str | None, np.ndarray, np.ndarray]]) -> dict[str, np.ndarray]:
    """The local twist of each named factor of a product M = F_1 F_2 … F_n, where F_k = F_k⁰ exp(e_k δ_k):
    M(δ_k) = M exp(Ad(S_k⁻¹) e_k δ_k) with S_k = F_{k+1} … F_n, so ξ_k = Ad(S_k⁻¹) e_k."""
    out: dict[str, np.ndarray] = {}
    suffix = np.eye(4)
    for name, matrix, generator in reversed(factors):
        if name is not None:
            out[name] = se3(suffix).inverse().act(pin.Motion(generator)).vector
        suffix = matrix @ suffix
    return out


def dh_derivatives(table: DHTable, model: pin.Model, names: Sequence[str]) -> PlacementDerivatives:
    """The exact derivatives of the placements and inertias of a DH arm's model (:meth:`DHTable.build_model`) with
    respect to its parameters ``names``, from the factors of every row (:meth:`DHTable.constant_factors`,
    :func:`factor_twists`). Standard convention: the link frame L_i moves the frame ``link{i}``, the placement of
    joint i + 1, the frame ``tool`` (L_n T: its twist is Ad(T⁻¹) ξ) and the link's inertia, L_i·I_i, whose
    derivative along ξ is the variation of L_i·I_i along Ad(L_i) ξ. Modified convention: the row moves the placement
    of joint i only."""
    out = empty(model, names)
    column = {name: k for k, name in enumerate(names)}
    tool = model.getFrameId("tool", pin.FrameType.OP_FRAME)
    for i in range(1, table.n + 1):
        twists = {n: xi for n, xi in factor_twists(table.constant_factors(i)).items() if n in column}
        if table.convention != "standard":
            for n, xi in twists.items():
                out.joints[column[n], i] = xi
            continue
        link = se3(table._constant_parts(i)[1])
        for n, xi in twists.items():
            k = column[n]
            out.frames[k, model.getFrameId(f"link{i}", pin.FrameType.BODY)] = xi
            if i < table.n:
                out.joints[k, i + 1] = xi
            else:
                out.frames[k, tool] = se3(table.tool).inverse().act(pin.Motion(xi)).vector
            out.inertias[k, i] = inertia_variation(model.inertias[i], link.act(pin.Motion(xi)).vector)
    return out


def dh_mechanism(table: DHTable, name: str = "dh_arm", *, description: str = "", source: str | None = None,
                 link_masses_include_drives: bool = False) -> Mechanism:
    """A :class:`Mechanism` for the arm described by ``table``; its parameters are the table's a, α, d, θ
    (``link_masses_include_drives``: :attr:`Mechanism.link_masses_include_drives`)."""
    model = table.build_model()
    model.name = name

    def rebuild(values: dict[str, float]) -> Mechanism:
        return dh_mechanism(table.with_values(values), name, description=description, source=source,
                            link_masses_include_drives=link_masses_include_drives)

    return Mechanism(
        name=name,
        model=model,
        parameters=table.parameters(),
        description=description,
        source=source,
        dh=table,
        drives={link.name: link.drive for link in table.links if link.drive is not None},
        rebuild=rebuild,
        derivatives=lambda names: dh_derivatives(table, model, names),
        link_masses_include_drives=link_masses_include_drives,
    )
