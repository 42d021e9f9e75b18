r"""The joint reactions of N states at once, in NumPy: what :func:`~mechatron.dynamics.tree.transmitted_wrenches`
and :func:`~mechatron.dynamics.constrained.reactions` give state by state, without Python work per sample.

The wrench a joint j transmits from its parent body to its child subtree balances everything the subtree carries
(Newton–Euler for every body i beyond j, world axes, moments about the world origin O, [Egorov, 5.1–5.2]):

.. math::

    W_j = \sum_{i \in \mathrm{sub}(j)} \begin{bmatrix} f_i \\ c_i \times f_i + I_i α_i + ω_i \times I_i ω_i
    \end{bmatrix} - \sum_{p \in \mathrm{sub}(j)} \begin{bmatrix} F_p \\ r_p \times F_p + M_p \end{bmatrix},
    \qquad f_i = m_i (\ddot c_i - g),

with c_i the body's centre of mass, c̈_i = a_i + α_i × ρ_i + ω_i × (ω_i × ρ_i) (ρ_i = c_i − p_i, a_i the classical
acceleration of the joint origin p_i), I_i = R_i I_{c,i} R_iᵀ its inertia about c_i in world axes, and the forces F_p
and moments M_p (N, N·m) applied at the points r_p of the subtree's bodies: the external loads and the closures'
forces. The moment is then taken about the joint's origin: M_j = M_O − p_j × F_j. These are RNEA's ``data.f`` in
world axes (the armature enters the joint torque only, not the wrench).

A closure's forces are its generalized force Jᵀλ as forces on the frames it joins (:meth:`~mechatron.model.closures.
Closure.loads`). By virtual work, the force and moment (world axes, at the frame's origin) that frame k receives are
w_k = (∂Φ/∂ξ_k)ᵀ λ, ξ_k the frame's world-aligned twist: the closures' own Jacobians (``closure.jacobian``) evaluated
with the identity for the frames' twists give every frame's w_k for all samples at once. A closure without frames (a
gear between two coordinates) puts no force on a body: its Jᵀλ are joint torques, which the wrenches carry like an
actuator's.

The multipliers of a closed loop whose closures are independent, n_act + n_rows = n_v, solve [B Jᵀ][τ_a; λ] = need
(need = M q̈ + h − Q, batched RNEA): the dependent rows alone read J_dᵀ λ = need_d (the state-by-state least squares
of :func:`~mechatron.dynamics.constrained.inverse` has this unique solution). The kinematics come from
:mod:`mechatron.model.batched` on a copy of the model with a frame at every joint's origin.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

import numpy as np
import pinocchio as pin
from numpy.typing import NDArray

from ..model.batched import BatchedFrames, BatchedStates, cross
from ..model.loads import Loads, as_loads
from ..model.mechanism import Mechanism

Array = NDArray[np.float64]


@dataclass(frozen=True)
class _Frames:
    """The batched kinematics of the closures' frames (first, in the closure system's order), the loads' frames and
    a frame at every joint's origin (last, joint 1 … njoints − 1), on a copy of the model."""

    frames: BatchedFrames
    closure_frames: int
    load_names: tuple[str, ...]
    parent_joint: NDArray[np.int_]  # (F,): the joint each closure or load frame moves with


def _frames(mech: Mechanism, load_names: tuple[str, ...]) -> _Frames | None:
    """:class:`_Frames` of ``mech`` for loads at ``load_names``, built once per mechanism and names; None where the
    batched kinematics does not know a joint."""
    from ..model.batched import batched_frames

    def build() -> _Frames | None:
        from ..kinematics.loops import loop_solver

        model = mech.model
        system = loop_solver(mech).system if mech.closures else None
        closure_ids = list(system.states.frame_ids) if system is not None else []
        load_ids = [mech.frame_id(name) for name in load_names]
        copy = model.copy()
        joint_ids = [copy.addFrame(pin.Frame(f"__reaction_joint_{j}", j, pin.SE3.Identity(), pin.FrameType.OP_FRAME),
                                   False) for j in range(1, model.njoints)]
        try:
            frames = batched_frames(copy, closure_ids + load_ids + joint_ids)
        except NotImplementedError:
            return None
        parents = np.array([model.frames[f].parentJoint for f in closure_ids + load_ids], dtype=int)
        return _Frames(frames, len(closure_ids), load_names, parents)

    return mech.cached(("batched_reactions", load_names), build)


def batched_wrenches(mech: Mechanism, Q: Array, V: Array, A: Array, loads: Loads = None,
                     multipliers: Array | None = None) -> Array | None:
    """(N, njoints − 1, 6): [force; moment] (N, N·m, world axes, about the joint's origin) that each tree joint
    transmits to its child subtree at the states (Q, V, A) (N, nq / nv), under gravity, the constant world
    ``loads`` and, for a closed loop, the closures' forces of ``multipliers`` λ (N, n_rows) (the module
    docstring); None where the batched kinematics does not know a joint of ``mech``."""
    from ..kinematics import batch

    applied = as_loads(loads)
    built = _frames(mech, tuple(dict.fromkeys(load.frame for load in applied)))
    if built is None:
        return None
    model = mech.model
    nj = model.njoints
    per_frame = np.zeros((len(built.load_names), 6))  # Σ [F; M] of the loads at each of their frames
    for load in applied:
        k = built.load_names.index(load.frame)
        per_frame[k, :3] += load.force
        per_frame[k, 3:] += load.moment
    inertias = [model.inertias[j] for j in range(1, nj)]
    mass = np.array([i.mass for i in inertias])[:, None]
    lever = np.array([i.lever for i in inertias])
    inertia = np.array([i.inertia for i in inertias])
    gravity = np.asarray(model.gravity.linear, dtype=float)
    joints = slice(built.closure_frames + len(built.load_names), None)  # the frames at the joints' origins
    out = np.empty((len(Q), nj - 1, 6))
    for part in batch.chunks(len(Q)):
        states = built.frames.placements(Q[part], jacobians=False)
        built.frames.motion(states, V[part], A[part])
        assert states.velocity is not None and states.acceleration0 is not None  # filled by motion
        p, R = states.position[:, joints], states.rotation[:, joints]
        w, alpha = states.velocity[:, joints, 3:], states.acceleration0[:, joints, 3:]
        rho = (R @ lever[..., None])[..., 0]  # c − p (N, nj − 1, 3)
        f = mass * (states.acceleration0[:, joints, :3] + cross(alpha, rho) + cross(w, cross(w, rho)) - gravity)
        Iw = R @ inertia @ np.swapaxes(R, -1, -2)
        total = np.concatenate([f, cross(p + rho, f) + (Iw @ alpha[..., None])[..., 0]
                                + cross(w, (Iw @ w[..., None])[..., 0])], axis=-1)
        received = np.concatenate([_closure_forces(mech, states, multipliers[part], built.closure_frames)
                                   if multipliers is not None and built.closure_frames else
                                   np.zeros((len(p), built.closure_frames, 6)),
                                   np.broadcast_to(per_frame, (len(p), *per_frame.shape))], axis=1)
        at = states.position[:, :built.closure_frames + len(built.load_names)]
        about_origin = np.concatenate([received[..., :3], received[..., 3:] + cross(at, received[..., :3])], axis=-1)
        for k, joint in enumerate(built.parent_joint):
            if joint > 0:
                total[:, joint - 1] -= about_origin[:, k]
        for j in range(nj - 1, 1, -1):  # children after parents: sum each subtree into its parent
            if model.parents[j] > 0:
                total[:, model.parents[j] - 1] += total[:, j - 1]
        total[..., 3:] -= cross(p, total[..., :3])
        out[part] = total
    return out


def _closure_forces(mech: Mechanism, states: BatchedStates, multipliers: Array, count: int) -> Array:
    """(n, count, 6): the force (N) and moment (N·m, world axes) that each closure frame receives from the
    multipliers λ (n, n_rows), w_k = (∂Φ/∂ξ_k)ᵀ λ (module docstring)."""
    from ..kinematics.loops import loop_solver

    n = len(multipliers)
    # the frames' states with the identity for their twists; Any: the closures' formulas, typed for FrameStates,
    # broadcast over the samples of BatchedStates
    probe: Any = dataclasses.replace(states, jacobian=np.broadcast_to(
        np.eye(6 * count).reshape(count, 6, 6 * count), (n, count, 6, 6 * count)))
    out = np.zeros((n, 6 * count))
    row = 0
    for closure in loop_solver(mech).system.closures:
        if closure.frames:
            rows = np.broadcast_to(closure.jacobian(probe), (n, closure.nrows, 6 * count))
            out += np.einsum("nr,nrk->nk", multipliers[:, row:row + closure.nrows], rows)
        row += closure.nrows
    return out.reshape(n, count, 6)


def closed_loop_multipliers(mech: Mechanism, Q: Array, V: Array, A: Array, loads: Loads = None) -> Array | None:
    """λ (N, n_rows) (N per pin row) of the constrained inverse dynamics at the states (Q, V, A) of a closed loop
    whose closures are independent: J_dᵀ λ = need_d (module docstring), all samples at once; None where the
    closures are redundant or the batched kinematics does not know a joint. The states are regular positions (the
    loops' sweep refuses singular ones, where J_d is not invertible)."""
    from ..kinematics import batch
    from ..kinematics.loops import loop_solver
    from .tree import inverse_dynamics

    solver = loop_solver(mech)
    system = solver.system
    if system.nrows != len(solver.dep) or len(solver.act) + len(solver.dep) != mech.nv:
        return None
    try:
        frames = system.batched()
    except NotImplementedError:
        return None
    need = np.atleast_2d(inverse_dynamics(mech, Q, V, A, loads))  # M q̈ + h − Q (N, nv)
    out = np.empty((len(Q), system.nrows))
    for part in batch.chunks(len(Q)):
        _, J = system.stack(frames.placements(Q[part]))
        out[part] = batch.solve(np.swapaxes(J[:, :, solver.dep], 1, 2), need[part][:, solver.dep, None])[..., 0]
    return out


def reactions_at(mech: Mechanism, Q: Array, V: Array, A: Array, loads: Loads = None
                 ) -> tuple[Array, dict[str, Array]] | None:
    """The reactions at N states (Q, V, A) (N, nq / nv; a closed loop's states satisfy its closures) under gravity
    and ``loads``, all at once: the joints' wrenches (N, njoints − 1, 6) of :func:`batched_wrenches` and each
    closure's multipliers (N, its rows) by name (a pin's: the force, N, that its point ``a`` receives); None where
    the closures are redundant or the batched kinematics does not know a joint."""
    from ..kinematics.loops import loop_solver

    if not mech.closures:
        wrenches = batched_wrenches(mech, Q, V, A, loads)
        return None if wrenches is None else (wrenches, {})
    lam = closed_loop_multipliers(mech, Q, V, A, loads)
    wrenches = None if lam is None else batched_wrenches(mech, Q, V, A, loads, lam)
    if lam is None or wrenches is None:
        return None
    pins, row = {}, 0
    for closure in loop_solver(mech).system.closures:
        pins[closure.name] = lam[:, row:row + closure.nrows].copy()
        row += closure.nrows
    return wrenches, pins
