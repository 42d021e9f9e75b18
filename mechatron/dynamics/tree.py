r"""Dynamics of the kinematic tree of a :class:`~mechatron.model.Mechanism`, from Pinocchio.

Equation of motion of the tree: M(q) q̈ + C(q, q̇) q̇ + g(q) = τ + Σ J_pᵀ F_p, with M from CRBA, the bias
h = C q̇ + g from ``nonLinearEffects``, inverse dynamics from RNEA and forward dynamics from ABA. The rotor and gear
inertia of a drive is reflected into its joint once, as Pinocchio's ``armature`` J_rotor·u² (see
:mod:`mechatron.model.dh`); efficiency and friction act outside Pinocchio, on the motor side
(:mod:`mechatron.drives.transmission`).

Every function takes one state or a batch: q of shape (nq,) or (N, nq), v and a of shape (nv,) or (N, nv).
Batched RNEA and ABA run in Pinocchio's compiled loops over the samples (``rneaInParallel``/``abaInParallel``), CRBA
is ``pin.crba`` mapped over the samples; the thread count is ``threads=``, else the environment variable
``MECHATRON_THREADS``, else chosen by the batch size and the idle cores (:func:`thread_count`: serial below
:data:`SAMPLES_PER_THREAD` samples a thread). Every thread count gives the same bits.

One state — (nq,), or a batch of one (1, nq) — of float64 arrays takes a lean path (:func:`_one_state`,
:func:`_one_configuration`): Pinocchio's call plus ~1–1.5 µs of shape and finiteness checks (a plain loop's indexing
and row writes cost ~1 µs; measured by benchmarks/dynamics.py). Every path refuses non-finite inputs with the same
:class:`InputError` naming the argument, and a result that overflows (finite inputs too large for the model) instead
of returning inf.
Units: N·m for revolute and N for prismatic joints, J for energies, SI everywhere.
"""

from __future__ import annotations

import functools
import math
import os
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from ..io.budget import available_cores
from ..io.values import number
from ..kinematics.frames import lean_samples, samples
from ..model.batched import REVOLUTE
from ..model.loads import Load, Loads, as_loads
from ..model.mechanism import Mechanism

Array = NDArray[np.float64]


def external_forces(mech: Mechanism, q: ArrayLike, loads: Loads) -> list[pin.Force] | None:
    """Pinocchio's per-joint external forces (local frames, N and N·m about the joint origin) at the configuration
    q for :class:`~mechatron.model.loads.Load` s: world forces (N) and moments (N·m) applied at frames' origins;
    ``None`` without loads."""
    loads = as_loads(loads)
    if not loads:
        return None
    model, data = mech.model, mech.data
    pin.forwardKinematics(model, data, q)
    out = [pin.Force.Zero() for _ in range(model.njoints)]
    for load in loads:
        fid = frame_index(mech, load.frame)
        joint = model.frames[fid].parentJoint
        placement = pin.updateFramePlacement(model, data, fid)
        oMi = data.oMi[joint]
        # a world force f at point p and moment m, expressed in the joint frame about its origin: m + r × f
        r = placement.translation - oMi.translation
        out[joint] += pin.Force(oMi.rotation.T @ load.force,
                                oMi.rotation.T @ (load.moment + pin.skew(r) @ load.force))
    return out


def _load_frames(mech: Mechanism, loads: tuple[Load, ...]):
    """The batched kinematics (:func:`~mechatron.model.batched.batched_frames`) of the loads' frames, in the order
    of their names' first appearance, built once per mechanism and frames; None where it does not know a joint."""
    from ..model.batched import batched_frames

    names = tuple(dict.fromkeys(load.frame for load in loads))

    def build():
        try:
            return names, batched_frames(mech.model, [frame_index(mech, n) for n in names])
        except NotImplementedError:
            return None

    return mech.cached(("load_frames", names), build)


def load_forces(mech: Mechanism, Q: ArrayLike, loads: Loads) -> Array:
    r"""The generalized forces of constant world loads at N configurations Q (N, nq): Q_k = Σ_p J_p(q_k)ᵀ [F_p; M_p]
    (N, nv; N·m, N), J_p the LOCAL_WORLD_ALIGNED Jacobian (6 × nv) of the origin of the load's frame, all samples at
    once by the batched kinematics (:mod:`mechatron.model.batched`). By the principle of virtual work these are the
    joint torques the loads hold, so RNEA with the loads as external forces is RNEA without them minus Q_k
    ([Egorov, 6.15]).

    Raises:
        NotImplementedError: where the batched kinematics does not know a joint of ``mech``.
    """
    loads = as_loads(loads)
    Q = np.atleast_2d(np.asarray(Q, dtype=float))
    out = np.zeros((len(Q), mech.nv))
    if not loads:
        return out
    built = _load_frames(mech, loads)
    if built is None:
        raise NotImplementedError(f"batched kinematics of {mech.name}: a joint it does not know")
    names, frames = built
    wrench = np.zeros((len(names), 6))  # Σ [F; M] of the loads at each frame
    for load in loads:
        k = names.index(load.frame)
        wrench[k, :3] += load.force
        wrench[k, 3:] += load.moment
    from ..kinematics import batch

    for part in batch.chunks(len(Q)):
        J = frames.placements(Q[part]).jacobian  # (n, F, 6, nv)
        out[part] = np.einsum("kfiv,fi->kv", J, wrench)
    return out


def frame_index(mech: Mechanism, name: str) -> int:
    """``mech.frame_id(name)``, remembered in the mechanism's cache (the loads of a simulation ask at every
    stage)."""
    known = mech.cached("frame_index", dict)
    if name not in known:
        known[name] = mech.frame_id(name)
    return known[name]


def generalized_forces(mech: Mechanism, q: ArrayLike, forces: Mapping[str, float] | None = None,
                       loads: Loads = None) -> Array:
    """τ + Q (nv,; N, N·m) at the configuration q: forces or torques on named joint coordinates plus the
    generalized forces Q = Σ J_pᵀ [F_p; M_p] of external ``loads``, J_p the Jacobian of the load's frame origin in
    world axes (Q·q̇ is the loads' power, [Egorov, 6.15])."""
    tau = np.zeros(mech.nv)
    for name, value in (forces or {}).items():
        tau[mech.model.joints[mech.joint_id(name)].idx_v] += value
    for load in as_loads(loads):
        J = pin.computeFrameJacobian(mech.model, mech.data, q, frame_index(mech, load.frame),
                                     pin.LOCAL_WORLD_ALIGNED)
        tau += J[:3].T @ load.force + J[3:].T @ load.moment
    return tau


def joint_space_inertia(model: pin.Model, data: pin.Data, q: ArrayLike) -> Array:
    """M(q) (nv, nv; kg, kg·m, kg·m²) from CRBA. Pinocchio's C++ CRBA fills the upper triangle; its Python ``crba``
    zeroes ``data.M``, runs it and copies the upper triangle to the lower one (``make_symmetric``), so the matrix
    it returns is symmetric bit for bit (tests/test_dynamics_fast_path.py checks this)."""
    return pin.crba(model, data, q)


#: Environment variable fixing the thread count of batched RNEA/ABA/CRBA when no ``threads=`` is given: a whole
#: number >= 1 (1 = serial); unset, the count is chosen by the batch size and the idle cores (:func:`thread_count`).
THREADS_VARIABLE = "MECHATRON_THREADS"

#: Samples each thread must get before a second thread is used. Measured on two cores under a load of 1.5–3.5
#: (PUMA 560, compiled RNEA ≈ 1.3–2.3 µs a sample on one thread): two OpenMP threads cost ~2 ms at N = 1 (start-up
#: and hand-over), 0.5–3.2× one thread at N = 1,000 and 0.9–1.2× from 30,000 to 300,000. From 25,000 samples a
#: thread the worst start-up is under 5 % of the serial time, and a second thread is used only on an idle core.
SAMPLES_PER_THREAD = 25_000


def idle_cores(cores: int) -> int:
    """Cores of ``cores`` that nobody else uses: ``cores`` minus the one-minute load average, which counts this
    process too (hence + 1), rounded down, at least 1."""
    try:
        load = os.getloadavg()[0]
    except (AttributeError, OSError):  # pragma: no cover - Windows
        return 1
    return max(1, min(cores, int(cores - load + 1)))


def thread_count(samples: int, threads: int | None = None) -> int:
    """Threads for a batch of ``samples`` states: ``threads`` if given, else the environment variable
    :data:`THREADS_VARIABLE`, else the idle cores, at most one per :data:`SAMPLES_PER_THREAD` samples; never more
    than the available cores nor the samples, at least 1 (serial)."""
    if threads is None and os.environ.get(THREADS_VARIABLE, "").strip():
        threads = number(THREADS_VARIABLE, os.environ[THREADS_VARIABLE], minimum=1, integer=True)
    cores = available_cores()
    if threads is None:
        threads = min(idle_cores(cores), samples // SAMPLES_PER_THREAD)
    else:
        threads = number("threads", threads, minimum=1, integer=True)
    return max(1, min(threads, cores, samples))


def _model_pool(mech: Mechanism, threads: int) -> pin.ModelPool:
    """A pool of at least ``threads`` model/data copies for Pinocchio's parallel algorithms, kept in the mechanism's
    cache."""
    pool = mech.cached("model_pool", lambda: pin.ModelPool(mech.model, available_cores()))
    if pool.size() < threads:
        pool.resize(threads)
    return pool


def _compiled(algorithm, mech: Mechanism, threads: int, Q: np.ndarray, V: np.ndarray, X: np.ndarray) -> np.ndarray:
    """Run a batch through Pinocchio's C++ loop ``rneaInParallel``/``abaInParallel`` on ``threads`` OpenMP threads
    (1: a plain compiled loop, no Python per sample). Arrays (N, n) in and out; Pinocchio takes the transposed,
    column-major views. Each sample is the same C++ RNEA/ABA a single call runs, so the results are bit for bit
    those of the loop over ``pin.rnea``/``pin.aba(..., Convention.WORLD)`` at any thread count."""
    out = np.empty((len(Q), mech.nv))
    algorithm(threads, _model_pool(mech, threads), np.ascontiguousarray(Q).T, np.ascontiguousarray(V).T,
              np.ascontiguousarray(X).T, out.T)
    return out


_FLOAT64 = np.dtype(np.float64)


def _one_state(algorithm: Callable[..., Array], mech: Mechanism, q: Any, v: Any, x: Any,
               *options: object) -> Array | None:
    """``algorithm(model, data, q, v, x, *options)`` (``pin.rnea``; ``pin.aba``, world convention) at one state —
    q, v, x float64 arrays, all (n,) or all (1, n) — if q, v and the result are finite; else ``None``
    (the caller then runs the full checks, which name what is wrong, and its general path). Returns (nv,) or
    (1, nv). A finite sum has only finite terms (a sum that overflows only sends finite numbers the long way).

    Why the result's check covers x (q̈ for RNEA, τ for ABA): τ = M(q) q̈ + h(q, q̇) and q̈ = M⁻¹ (τ − h) are
    affine in x with the positive diagonals M_kk and (M⁻¹)_kk of a positive-definite M, so every component of the
    result is computed from the x_k of its joint, and IEEE arithmetic turns any result computed from a NaN into NaN
    and from an inf into inf or NaN (no step divides by x or compares it). q and q̇ are checked themselves: the
    result need not depend on them (g(q) does not depend on a vertical first axis's angle; a translating body has
    no velocity-dependent forces, and Pinocchio gives finite torques for a NaN slider velocity). Wrong lengths
    raise in Pinocchio (``ValueError``), what is not an array in NumPy (``AttributeError``): both return
    ``None``, as do other dtypes and shapes."""
    try:
        if not (type(q) is type(v) is np.ndarray and q.dtype is v.dtype is x.dtype is _FLOAT64):
            return None
        ndim = q.ndim
        if ndim == 2 == v.ndim == x.ndim and len(q) == len(v) == len(x) == 1:
            q, v, x = q[0], v[0], x[0]
        elif not ndim == 1 == v.ndim == x.ndim:
            return None
        out = algorithm(mech.model, mech.data, q, v, x, *options)
    except (AttributeError, TypeError, ValueError):
        return None
    if math.isfinite(sum(q.tolist()) + sum(v.tolist()) + sum(out.tolist())):
        return out if ndim == 1 else out[None]
    return None


def _one_configuration(mech: Mechanism, q: Any) -> Array | None:
    """M(q) (nv, nv), or (1, nv, nv) for a batch of one, by ``pin.crba`` if q is a float64 array (nq,) or (1, nq)
    with finite entries and M is finite; else ``None`` (as :func:`_one_state`)."""
    if type(q) is np.ndarray and q.dtype is _FLOAT64:
        ndim = q.ndim
        if ndim == 2 and len(q) == 1:
            q = q[0]
        elif ndim != 1:
            return None
        try:
            M = pin.crba(mech.model, mech.data, q)
        except (TypeError, ValueError):
            return None
        if math.isfinite(sum(q.tolist())) and (_revolute_only(mech) or math.isfinite(sum(M.ravel().tolist()))):
            return M if ndim == 1 else M[None]
    return None


def _revolute_only(mech: Mechanism) -> bool:
    """Whether every joint of ``mech`` is revolute about one axis with its angle as coordinate: then M(q) depends on
    q only through cos q and sin q and is bounded by the model's masses and lengths, so a finite q cannot make it
    overflow (no check of M needed). Not so for continuous joints, whose coordinates (cos θ, sin θ) are taken as
    given."""
    return mech.cached("revolute_only", lambda: all(mech.model.joints[i].shortname() in REVOLUTE
                                                    for i in range(1, mech.model.njoints)))


def _finite(out: Array, what: str) -> Array:
    """``out`` if all its entries are finite, else an :class:`InputError`: the inputs passed their checks (finite,
    right shapes), so the model's numbers at these inputs overflow double precision (|x| > 1.8e308)."""
    if math.isfinite(out.sum()) or np.isfinite(out).all():
        return out
    raise InputError(f"{what} overflows (beyond 1.8e308) at these finite inputs: check their magnitudes and units")


def inverse_dynamics(mech: Mechanism, q: ArrayLike, v: ArrayLike, a: ArrayLike, loads: Loads = None,
                     threads: int | None = None) -> Array:
    """Joint torques/forces τ = M q̈ + C q̇ + g − Σ J_pᵀ F_p (N·m, N; RNEA), reflected drive inertia included.

    Args:
        q: Configuration(s) (nq,) or (N, nq) (Pinocchio's q: a continuous joint's (cos θ, sin θ)).
        v, a: Joint velocities (rad/s, m/s) and accelerations (rad/s², m/s²), (nv,) or (N, nv).
        loads: External loads acting on the mechanism (:class:`~mechatron.model.loads.Load`: force in N and moment
            in N·m, world axes, at a frame's origin).
        threads: Threads for a batch (1 = serial); default: :func:`thread_count` (the environment variable
            ``MECHATRON_THREADS``, else by size and idle cores).

    Returns:
        (nv,) or (N, nv). A batch runs in Pinocchio's compiled loop ``rneaInParallel`` (one thread unless the batch
        is long and cores are idle), bit for bit the loop over ``pin.rnea``; with loads, their generalized forces
        Σ J_pᵀ [F_p; M_p] are subtracted for all samples at once (:func:`load_forces`: the frames' Jacobians from the
        batched kinematics, no Python per sample), the same numbers as RNEA with the loads as external forces to
        rounding; where the batched kinematics does not know a joint, a Python loop over the samples.
    """
    if loads is None and threads is None:
        tau = _one_state(pin.rnea, mech, q, v, a)
        if tau is not None:
            return tau
    single, Q, (V, A) = lean_samples(mech, q, v, a)
    model, data = mech.model, mech.data
    loads = as_loads(loads)
    if len(Q) > 1 and (not loads or _load_frames(mech, loads) is not None):
        tau = _compiled(pin.rneaInParallel, mech, thread_count(len(Q), threads), Q, V, A)
        if loads:
            tau -= load_forces(mech, Q, loads)
        return _finite(tau, "RNEA")
    if threads is not None:
        thread_count(1, threads)  # checked; one state or loads run serially
    out = np.empty((len(Q), mech.nv))
    for i in range(len(Q)):
        if loads:
            out[i] = pin.rnea(model, data, Q[i], V[i], A[i], external_forces(mech, Q[i], loads))
        else:
            out[i] = pin.rnea(model, data, Q[i], V[i], A[i])
    out = _finite(out, "RNEA")
    return out[0] if single else out


def forward_dynamics(mech: Mechanism, q: ArrayLike, v: ArrayLike, tau: ArrayLike,
                     threads: int | None = None) -> Array:
    """Joint accelerations q̈ = M⁻¹(τ − C q̇ − g) (rad/s², m/s²; ABA) for joint torques/forces τ (N·m, N) at the
    state (q, q̇): (nv,) or (N, nv). A batch runs in Pinocchio's compiled ``abaInParallel`` on ``threads`` threads
    (as :func:`inverse_dynamics`); every state is ABA in its world-frame convention, so one state and any thread
    count give the same bits (within ~1e-13 relative of ``pin.aba``'s default local convention)."""
    if threads is None:
        out = _one_state(pin.aba, mech, q, v, tau, pin.Convention.WORLD)
        if out is not None:
            return out
    single, Q, (V, T) = lean_samples(mech, q, v, tau)
    if len(Q) > 1:
        return _finite(_compiled(pin.abaInParallel, mech, thread_count(len(Q), threads), Q, V, T), "ABA")
    if threads is not None:
        thread_count(1, threads)
    out = _finite(pin.aba(mech.model, mech.data, Q[0], V[0], T[0], pin.Convention.WORLD), "ABA")
    return out if single else out[None]


def mass_matrix(mech: Mechanism, q: ArrayLike, threads: int | None = None) -> Array:
    """Joint-space inertia matrix M(q) (kg, kg·m, kg·m²; CRBA, symmetric: :func:`joint_space_inertia`), including
    the armature: (nv, nv) or (N, nv, nv). ½ q̇ᵀ M q̇ is the kinetic energy [Egorov, 6.2].

    q is checked itself, not through M: M does not depend on the coordinates of a joint on the ground (CRBA in the
    joints' frames gives a finite M for a NaN first angle); M is checked for overflow. A batch is ``pin.crba``
    mapped over the samples straight into the output (``np.fromiter``: no temporary, 0–10 % less than a loop
    writing rows). ``threads`` is checked
    as in :func:`inverse_dynamics` but CRBA always runs on one thread: Pinocchio has no parallel CRBA, its Python
    ``crba`` holds the GIL, and M from nv + 1 parallel RNEA columns costs more than a serial CRBA on fewer than
    four idle cores (7 × 1.3 µs vs 2.1 µs a sample for the PUMA 560), so the result is the same at every count."""
    if threads is None:
        M = _one_configuration(mech, q)
        if M is not None:
            return M
    single, Q, _ = lean_samples(mech, q)
    if threads is not None:
        thread_count(len(Q), threads)
    model, data = mech.model, mech.data
    if len(Q) == 1:
        M = _finite(joint_space_inertia(model, data, Q[0]), "CRBA")
        return M if single else M[None]
    matrix = np.dtype((np.float64, (mech.nv, mech.nv)))
    out: Array = np.fromiter(map(functools.partial(pin.crba, model, data), Q), dtype=matrix, count=len(Q))
    return out if _revolute_only(mech) else _finite(out, "CRBA")


def bias_forces(mech: Mechanism, q: ArrayLike, v: ArrayLike) -> Array:
    """h(q, q̇) = C(q, q̇) q̇ + g(q) (N·m, N): the torques for zero acceleration."""
    single, Q, (V,) = samples(mech, q, v)
    out = np.empty((len(Q), mech.nv))
    for i in range(len(Q)):
        out[i] = pin.nonLinearEffects(mech.model, mech.data, Q[i], V[i])
    return out[0] if single else out


def gravity_torques(mech: Mechanism, q: ArrayLike) -> Array:
    """g(q) (N·m, N): the joint torques that hold the mechanism against gravity, g = ∂V/∂q."""
    single, Q, _ = samples(mech, q)
    out = np.empty((len(Q), mech.nv))
    for i in range(len(Q)):
        out[i] = pin.computeGeneralizedGravity(mech.model, mech.data, Q[i])
    return out[0] if single else out


def kinetic_energy(mech: Mechanism, q: ArrayLike, v: ArrayLike) -> Array | float:
    """T = ½ q̇ᵀ M q̇ (J), rotors included through the armature: [Egorov, 6.2] summed over the links."""
    single, Q, (V,) = samples(mech, q, v)
    out = np.array([pin.computeKineticEnergy(mech.model, mech.data, Q[i], V[i]) for i in range(len(Q))])
    return float(out[0]) if single else out


def potential_energy(mech: Mechanism, q: ArrayLike) -> Array | float:
    """Gravitational potential energy (J), zero at the world origin's height."""
    single, Q, _ = samples(mech, q)
    out = np.array([pin.computePotentialEnergy(mech.model, mech.data, Q[i]) for i in range(len(Q))])
    return float(out[0]) if single else out


def mechanical_energy(mech: Mechanism, q: ArrayLike, v: ArrayLike) -> Array | float:
    """T + V (J): constant along an unforced, undamped motion."""
    return kinetic_energy(mech, q, v) + potential_energy(mech, q)


def joint_wrenches(mech: Mechanism, q: ArrayLike, v: ArrayLike, a: ArrayLike, loads: Loads = None) -> Array:
    """Force (N) and moment (N·m) transmitted through every joint of the tree, from the parent body to the child
    subtree, in world axes about the joint's origin, at one state: array (njoints − 1, 6) = [force; moment] per
    joint (the reactions in the pairs of a serial chain, [Egorov, 5.1–5.2]; the joint's torque is the moment's
    component on its axis)."""
    single, Q, (V, A) = samples(mech, q, v, a)
    if not single:
        raise InputError("joint_wrenches takes one state")
    return transmitted_wrenches(mech, Q[0], V[0], A[0], loads)


def transmitted_wrenches(mech: Mechanism, q: Array, v: Array, a: Array, loads: Loads = None) -> Array:
    """(njoints − 1, 6): [force; moment] (N, N·m, world axes, about the joint origin) that each tree joint transmits
    to its child subtree, from one RNEA pass with the loads as external forces."""
    model, data = mech.model, mech.data
    fext = external_forces(mech, q, loads)
    if fext is None:
        pin.rnea(model, data, q, v, a)
    else:
        pin.rnea(model, data, q, v, a, fext)
    pin.updateGlobalPlacements(model, data)  # RNEA leaves the joints' world placements (oMi) as they were
    out = np.empty((model.njoints - 1, 6))
    for j in range(1, model.njoints):
        R = data.oMi[j].rotation
        out[j - 1, :3] = R @ data.f[j].linear
        out[j - 1, 3:] = R @ data.f[j].angular
    return out
