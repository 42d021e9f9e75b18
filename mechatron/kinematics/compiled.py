r"""Closed-loop position, velocity and acceleration analysis compiled to machine code with CasADi, mapped over samples.

The loop equations Φ(q) = 0 of a mechanism (:mod:`mechatron.model.symbolic`) and their exact derivatives become two
CasADi functions of one sample:

- ``newton``: from a guess q⁽⁰⁾ (its actuated entries the inputs), up to :data:`STEPS` Newton steps on the
  dependent coordinates, q_d ← q_d − J_d⁻¹ Φ(q), unrolled: as :meth:`~mechatron.kinematics.loops.LoopSolver.newton`
  with ``polish``, a step while max |Φ| ≥ :data:`~mechatron.kinematics.loops.TOLERANCE`, one more at the first
  iterate below it and none after (``if_else`` keeps the rest); outputs q, whether it converged and the dependent
  velocity maps S_d = −J_d⁻¹ J_a at the iterate of the polishing step;
- ``analyse``: at an assembled q with actuated rates q̇_a and accelerations q̈_a: q̇ = S q̇_a, q̈_d = −J_d⁻¹
  (J_a q̈_a + J̇ q̇) ([Egorov, 4.2–4.16]), max |J_d⁻¹| (the singularity measure of
  :data:`~mechatron.kinematics.loops.SINGULAR_RATIO`), and of every reported frame its origin p, its angle about z,
  the velocity ṗ = J_p q̇, the angular velocity ω_z = (Ṙ Rᵀ)₁₀, the classical acceleration p̈ = J_p q̈ + J̇_p q̇ and
  the angular acceleration α_z = ω̇_z (J̇ q̇ as the second directional derivative of the expressions along q̇).

Both are generated as C (``casadi.Function.generate``), compiled once with the system's C compiler (``cc``, or the
one in ``CC``) into a shared library kept in a cache folder (``MECHATRON_CACHE``, else ``$XDG_CACHE_HOME/mechatron``
or ``~/.cache/mechatron``) under the hash of its source, and evaluated over chunks of samples by
``Function.map`` (a loop in C, no Python per sample). Without a working compiler, or with ``MECHATRON_COMPILE=0``,
the same functions run in CasADi's virtual machine. Mechanisms with joints or closures that have no symbolic form
get no kernel (:func:`loop_kernel` returns None) and the NumPy path of :mod:`mechatron.kinematics.batch` is used.
"""

from __future__ import annotations

import hashlib
import os
import subprocess
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..model.symbolic import Unsupported, angle_about_z, closure_residual, frame_placements
from .loops import TOLERANCE

if TYPE_CHECKING:
    from .loops import LoopSolver

#: Unrolled Newton steps of the compiled solve: from guesses interpolated between anchors (up to ~1e-3 off), the
#: third step reaches ~1e-12 (Newton's error squares) and the fourth rounding level.
STEPS = 4
#: Samples per call of a mapped function, and per chunk of the sweep's batched solve with a kernel (its working
#: storage is ~100 B a sample).
CHUNK = 16384
#: Environment variables: the cache folder, and 0 to run the kernels in CasADi's virtual machine.
CACHE_VARIABLE, COMPILE_VARIABLE = "MECHATRON_CACHE", "MECHATRON_COMPILE"


def cache_folder() -> Path:
    """Where compiled kernels are kept: ``MECHATRON_CACHE``, else ``$XDG_CACHE_HOME/mechatron/kernels`` or
    ``~/.cache/mechatron/kernels``."""
    if os.environ.get(CACHE_VARIABLE):
        return Path(os.environ[CACHE_VARIABLE])
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "mechatron" / "kernels"


def compiled(function):
    """``function`` (a CasADi ``Function``) as machine code: its generated C compiled into a shared library in the
    :func:`cache_folder` (reused when the same source was compiled before) and loaded with ``casadi.external``;
    the function itself (CasADi's virtual machine) when compiling is switched off or fails."""
    import casadi as ca

    if os.environ.get(COMPILE_VARIABLE, "1").strip() == "0":
        return function
    try:
        folder = cache_folder()
        folder.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryDirectory(dir=folder) as work:
            source = Path(work) / f"{function.name()}.c"
            generator = ca.CodeGenerator(source.name, {"with_header": False})
            generator.add(function)
            generator.generate(work + os.sep)
            text = source.read_bytes()
            library = folder / f"{function.name()}_{hashlib.sha256(text).hexdigest()[:20]}.so"
            if not library.exists():
                partial = Path(work) / library.name
                compiler = os.environ.get("CC", "cc")
                subprocess.run([compiler, "-O2", "-shared", "-fPIC", "-o", str(partial), str(source), "-lm"],
                               check=True, capture_output=True, timeout=300)
                os.replace(partial, library)  # whole or not at all: concurrent runs may race, both write the same
        return ca.external(function.name(), str(library))
    except (OSError, subprocess.SubprocessError, RuntimeError):
        return function


class LoopKernel:
    """The compiled ``newton`` and ``analyse`` of a loop solver's closures, see the module docstring, reporting the
    columns of a sweep's table: of the frames ``points`` the position (x, y and, when ``spatial``, z; m), velocity
    and its size (m/s), acceleration and its size (m/s²); of the frames ``links`` the angle about z in (−π, π], its
    rate and acceleration (rad, rad/s, rad/s²); of the frames ``others`` x and y (m). :meth:`newton` and
    :meth:`analyse` take and return NumPy arrays of N samples."""

    def __init__(self, solver: LoopSolver, points: list[str], links: list[str], others: list[str] = (),
                 spatial: bool = False) -> None:
        import casadi as ca

        mech, system = solver.mech, solver.system
        model = mech.model
        if len(solver.dep) != system.nrows or not len(solver.dep):
            raise Unsupported("the closures do not determine the dependent coordinates one to one")
        nq, act, dep = model.nq, [int(i) for i in solver.act], [int(i) for i in solver.dep]
        self.nq, self.na, self.nd, self.act, self.dep = nq, len(act), len(dep), act, dep
        self.others = list(others)
        q, v, a = ca.SX.sym("q", nq), ca.SX.sym("v", nq), ca.SX.sym("a", nq)
        closing = frame_placements(model, [mech.frame_id(n) for n in system.frame_names], q)
        phi = closure_residual(system, dict(zip(system.frame_names, closing)), q)
        J = ca.jacobian(phi, q)
        residual = ca.Function("residual", [q], [phi, J])

        # newton: STEPS unrolled steps on q_d, as LoopSolver.newton with polish: a step while the residual is at or
        # above TOLERANCE, one more (polishing) step at the first iterate below it, none after
        guess = ca.SX.sym("guess", nq)
        qk, done, maps = guess, ca.SX(0), ca.SX.nan(len(dep), len(act))
        for _ in range(STEPS):
            phi_k, J_k = residual(qk)
            inverse = ca.inv(J_k[:, dep])
            step = ca.if_else(done, ca.SX.zeros(len(dep)), ca.mtimes(inverse, phi_k))
            maps = ca.if_else(done, maps, -ca.mtimes(inverse, J_k[:, act]))
            qk = ca.vertcat(*[qk[i] - step[dep.index(i)] if i in dep else qk[i] for i in range(nq)])
            done = ca.logic_or(done, ca.mmax(ca.fabs(phi_k)) < TOLERANCE)
        newton = ca.cse(ca.vertcat(qk, done, ca.vec(maps)))  # sin q of an input is shared by every step
        self._newton = compiled(ca.Function("mechatron_newton", [guess], [newton]))

        # analyse: velocities, accelerations and the reported frames
        rates, accelerations = ca.SX.sym("rates", len(act)), ca.SX.sym("accelerations", len(act))
        Jd_inverse = ca.inv(J[:, dep])
        S = ca.SX.zeros(nq, len(act))
        for k, i in enumerate(act):
            S[i, k] = 1
        S[dep, :] = -ca.mtimes(Jd_inverse, J[:, act])
        velocity = ca.mtimes(S, rates)
        drift = ca.jtimes(ca.jtimes(phi, q, v), q, v)  # J̇ q̇ at q̇ = v
        drift = ca.substitute(drift, v, velocity)
        acceleration = ca.mtimes(S, accelerations)
        acceleration[dep] = -ca.mtimes(Jd_inverse, ca.mtimes(J[:, act], accelerations) + drift)
        names, expressions = [], []
        state, motion = ca.vertcat(q, v), ca.vertcat(v, a)
        reported = list(dict.fromkeys([*points, *links, *others]))
        placements = dict(zip(reported, frame_placements(model, [mech.frame_id(n) for n in reported], q)))
        axes = "xyz" if spatial else "xy"
        for name in points:  # as sweep's frame columns: position, velocity and its size, acceleration and its size
            p = placements[name][1][:len(axes)]
            p_dot = ca.jtimes(p, q, v)
            p_ddot = ca.jtimes(p_dot, state, motion)
            for label, value in (("", p), ("v", p_dot), ("a", p_ddot)):
                names += [f"{name}_{label}{axis}" for axis in axes]
                expressions += [value[k] for k in range(len(axes))]
                if label:
                    names.append(f"{name}_{label}")
                    expressions.append(ca.norm_2(value))
        for name in links:  # angle about z in (−π, π], ω_z = (Ṙ Rᵀ)₁₀ and its rate
            R = placements[name][0]
            omega = ca.mtimes(ca.jtimes(R, q, v), R.T)[1, 0]
            names += [f"{name}_angle", f"{name}_omega", f"{name}_epsilon"]
            expressions += [angle_about_z(R), omega, ca.jtimes(omega, state, motion)]
        for name in others:  # points of measures only: their position
            names += [f"{name}_x", f"{name}_y"]
            expressions += [placements[name][1][0], placements[name][1][1]]
        columns = ca.substitute(ca.substitute(ca.vertcat(*expressions), a, acceleration), v, velocity) \
            if expressions else ca.SX.zeros(0, 1)
        outputs = ca.cse(ca.vertcat(velocity, acceleration, ca.mmax(ca.fabs(Jd_inverse)), columns))
        self.names = names
        self._analyse = compiled(ca.Function("mechatron_analyse", [q, rates, accelerations], [outputs]))
        self._mapped: dict = {}

    def _map(self, function, n: int):
        """``function`` mapped over n samples, with its argument buffer and evaluation (kept per size)."""
        key = (function.name(), n)
        if key not in self._mapped:
            mapped = function.map(n)
            self._mapped[key] = mapped.buffer()
        return self._mapped[key]

    def _evaluate(self, function, *arrays: np.ndarray) -> np.ndarray:
        """``function`` at every row of the (N, k) ``arrays``: its outputs (N, m), in chunks of :data:`CHUNK`. The
        arrays are handed over without copies: a C-ordered (n, k) block is CasADi's column-major (k, n) matrix."""
        arrays = tuple(np.ascontiguousarray(x, dtype=float) for x in arrays)
        n = len(arrays[0])
        out = np.empty((n, function.size1_out(0)))
        for start in range(0, n, CHUNK):
            stop = min(start + CHUNK, n)
            buffer, evaluate = self._map(function, stop - start)
            for i, x in enumerate(arrays):
                buffer.set_arg(i, memoryview(x[start:stop]))
            buffer.set_res(0, memoryview(out[start:stop]))
            evaluate()
        return out

    def newton(self, Q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The contract of :func:`mechatron.kinematics.batch.newton`: the dependent coordinates of every row of Q
        (N, nq) solved in place from the row as guess; returns which rows converged (max |Φ| below
        :data:`~mechatron.kinematics.loops.TOLERANCE` before the last, polishing step) and their maps S_d
        (N, n_dep, n_act) (NaN where not converged)."""
        out = self._evaluate(self._newton, Q)
        nq = self.nq
        converged = out[:, nq] == 1.0
        Q[converged] = out[converged, :nq]
        maps = out[:, nq + 1:].reshape(len(Q), self.na, self.nd).transpose(0, 2, 1)  # vec() is column-major
        maps[~converged] = np.nan
        return converged, maps

    def analyse(self, Q: np.ndarray, R: np.ndarray, A: np.ndarray
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray, dict[str, np.ndarray]]:
        """At assembled configurations Q (N, nq) with actuated rates R and accelerations A (N, n_act): q̇ (N, nv),
        q̈ (N, nv), max |J_d⁻¹| (N,) and the frames' columns by :attr:`names` (views of one (N, m) array)."""
        out = self._evaluate(self._analyse, Q, R, A)
        nq = self.nq
        first = 2 * nq + 1
        return out[:, :nq], out[:, nq:2 * nq], out[:, 2 * nq], {name: out[:, first + j]
                                                                 for j, name in enumerate(self.names)}


def loop_kernel(solver: LoopSolver, points: list[str], links: list[str], others: list[str], spatial: bool
                ) -> LoopKernel | None:
    """The :class:`LoopKernel` of ``solver``'s mechanism and these frames, built once per mechanism and frame lists
    (kept in the mechanism's cache); None where the joints or closures have no symbolic form or CasADi is
    missing."""
    def build() -> LoopKernel | None:
        try:
            return LoopKernel(solver, points, links, others, spatial)
        except (Unsupported, ImportError):
            return None

    key = ("loop_kernel", tuple(points), tuple(links), tuple(others), spatial)
    return solver.mech.cached(key, build)
