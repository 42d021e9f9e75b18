r"""Positions of a designed front-shovel working device [Shovel] on its designed assembly branch.

A cylinder across its joint is a triangle with the levers a (fixed), b (driven) and the included angle ψ = θ + c, so
its length L gives the joint angle θ = acos((a² + b² − L²)/(2ab)) − c (ψ in (0, π) over the designed range); the
boom, stick and bucket angles give the nose pin Q = C + l1 e(θ1) + l2 e(θ1 + θ2 − π) and the tooth tip
V = Q + l3 e(θ1 + θ2 + θ3). :func:`assembled` solves the closed-loop mechanism at many cylinder lengths at once and
keeps it on that branch: one sweep along a path from the reference position through the positions in their order,
in steps of at most 2 % of each stroke (the positions in a serpentine order keep it short, :func:`serpentine`); a
position whose Q or V is not where the closed form puts them is assembled again by continuation from the reference
position, and refused if it still is not.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from .excavator import FrontShovel

if TYPE_CHECKING:  # pragma: no cover
    from ..model.mechanism import Mechanism

Array = NDArray[np.float64]
#: Largest distance (m) between a point of the model and of the closed form on the designed branch.
BRANCH_TOLERANCE = 1e-6
#: Largest change of a cylinder length between two positions of the path, as a fraction of its stroke.
PATH_STEP = 0.02


def joint_angles(shovel: FrontShovel, lengths: Mapping[str, ArrayLike]) -> tuple[Array, Array, Array]:
    """(θ1, θ2, θ3) (rad) of the cylinder lengths L1, L2, L3 (m): θ = acos((a² + b² − L²)/(2ab)) − c."""
    out = []
    for c in shovel.cylinders:
        a, b = c.lever_fixed, c.lever_driven
        L = np.asarray(lengths[c.name], dtype=float)
        out.append(np.arccos(np.clip((a * a + b * b - L * L) / (2 * a * b), -1.0, 1.0)) - c.offset)
    return out[0], out[1], out[2]


def points(shovel: FrontShovel, theta1: ArrayLike, theta2: ArrayLike, theta3: ArrayLike) -> dict[str, Array]:
    """The nose pin Q and the tooth tip V (N, 2) (m) at the joint angles (rad), in closed form."""
    d = shovel.design
    t1, t12 = np.asarray(theta1, dtype=float), np.asarray(theta1, dtype=float) + np.asarray(theta2, dtype=float)

    def e(angle: Array) -> Array:
        return np.column_stack([np.cos(angle), np.sin(angle)])

    Q = np.asarray(d.boom_foot, dtype=float) + d.boom * e(t1) + d.stick * e(t12 - np.pi)
    return {"Q": Q, "V": Q + d.bucket * e(t12 + np.asarray(theta3, dtype=float))}


def serpentine(n: int, dimensions: int) -> Array:
    """Every combination of ``dimensions`` indices 0 … n−1 (n**dimensions rows), ordered so that consecutive rows
    differ by one in one index (a boustrophedon: every other inner run reversed)."""
    order = np.arange(n)[:, None]
    for _ in range(dimensions - 1):
        rows = [np.column_stack([np.full(len(order), i), order if i % 2 == 0 else order[::-1]]) for i in range(n)]
        order = np.vstack(rows)
    return order


def path(mech: Mechanism, inputs: Array) -> tuple[Array, Array]:
    """(U, rows): the cylinder lengths (M, n_act) of a path from the reference position through the positions
    ``inputs`` (N, n_act, m) in their order, straight in the lengths, in steps of at most :data:`PATH_STEP` of each
    stroke, and the row of U of each position."""
    from ..kinematics.loops import loop_solver

    solver = loop_solver(mech)
    start = np.array([mech.reference_q[solver.index[n]] for n in mech.actuated])
    span = np.array([hi - lo for lo, hi in (mech.cylinders[n].stroke for n in mech.actuated)])
    ends = np.vstack([start, inputs])
    delta = np.diff(ends, axis=0)
    steps = np.maximum(1, np.ceil(np.max(np.abs(delta) / span, axis=1) / PATH_STEP)).astype(int)
    segment = np.repeat(np.arange(len(inputs)), steps)
    rows = np.cumsum(steps) - 1
    fraction = (np.arange(len(segment)) - (rows - steps + 1)[segment] + 1) / steps[segment]
    return ends[segment] + delta[segment] * fraction[:, None], rows


def assembled(mech: Mechanism, shovel: FrontShovel, lengths: Mapping[str, ArrayLike]) -> tuple[Array, dict[str, Array]]:
    """(configurations (N, nq), {"Q", "V": (N, 2) m}) of the mechanism of ``shovel`` at the cylinder lengths (m, N
    each, within the strokes), all on the designed branch (module docstring)."""
    from ..kinematics.frames import frame_placement
    from ..kinematics.loops import assemble
    from ..kinematics.sweeps import sweep

    inputs = {n: np.atleast_1d(np.asarray(lengths[n], dtype=float)) for n in mech.actuated}
    expected = points(shovel, *joint_angles(shovel, inputs))
    n = len(inputs[mech.actuated[0]])
    U, wanted = path(mech, np.column_stack([inputs[name] for name in mech.actuated]))
    result = sweep(mech, dict(zip(mech.actuated, U.T)), frames=["Q", "V"], measures=[], guess=mech.reference_q)
    at = np.full(len(U), -1)
    at[result.table["sample"].to_numpy()] = np.arange(len(result.table))
    rows = at[wanted]
    Q = np.full((n, mech.nq), np.nan)
    found = np.full((n, 4), np.nan)
    ok = rows >= 0
    Q[ok] = result.q[rows[ok]]
    found[ok] = result.table[["Q_x", "Q_y", "V_x", "V_y"]].to_numpy()[rows[ok]]
    target = np.hstack([expected["Q"], expected["V"]])
    for k in np.flatnonzero(~(np.abs(found - target).max(axis=1) < BRANCH_TOLERANCE)):
        q = assemble(mech, {name: float(v[k]) for name, v in inputs.items()})
        found[k] = np.concatenate([frame_placement(mech, q, p).translation[:2] for p in ("Q", "V")])
        if not np.abs(found[k] - target[k]).max() < BRANCH_TOLERANCE:
            raise InputError(f"{mech.name}: the position at "
                             f"{', '.join(f'{m} = {v[k]:.6g} m' for m, v in inputs.items())} is not on the designed "
                             f"branch")
        Q[k] = q
    return Q, expected
