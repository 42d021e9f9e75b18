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

- ``step``: one Newton step of one sample, its residual's size max |Φ(q)| and the maps S_d at q.

They are generated as C (``casadi.CodeGenerator``), compiled once with the system's C compiler (``cc``, or the one
in ``CC``) into shared libraries kept in a cache folder (``MECHATRON_CACHE``, else ``$XDG_CACHE_HOME/mechatron`` or
``~/.cache/mechatron``) under the hash of their source, and evaluated over chunks of samples by ``Function.map``
(:meth:`LoopKernel.newton`, :meth:`LoopKernel.analyse`). The ``analyse`` library carries ``step`` and a driver in C
besides (:data:`DRIVER`, called through ``ctypes``, one call per chunk of samples): the sequential continuation of
:class:`mechatron.kinematics.sweep._Continuation` over the samples — each sample's guess extrapolated from the last
solutions (or along the velocity maps where the input step changed), ``step`` until the residual is below the
tolerance plus the polishing step, accepted only if it moved less than half the change from the previous solution,
then ``analyse`` at the solution —, writing the coordinates and the analysis straight into the rows of the sweep's
table (:meth:`LoopKernel.continuation`); a sample it does not accept is left to the caller. Without CasADi's map, its
argument buffers and Python between the two passes, a sample costs its two or three evaluations of the expressions.
Without a working compiler, or with ``MECHATRON_COMPILE=0``, the same functions run in CasADi's virtual machine and
there is no driver. Mechanisms with joints or closures that have no symbolic form get no kernel (:func:`loop_kernel`
returns None) and the NumPy path of :mod:`mechatron.kinematics.batch` is used.
"""

from __future__ import annotations

import ctypes
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

#: Unrolled Newton steps of the compiled solve (``newton``), and the most steps of the driver's: from guesses
#: interpolated between anchors (up to ~1e-3 off), the third step reaches ~1e-12 (Newton's error squares) and the
#: fourth rounding level.
STEPS = 4
#: The most Newton steps of the driver's first sample (no solution before it: from the sweep's start), as
#: :meth:`~mechatron.kinematics.loops.LoopSolver.newton`'s iterations.
FIRST_STEPS = 50
#: Samples per call of a mapped function, and per chunk of the sweep's batched solve with a kernel (its working
#: storage is ~100 B a sample).
CHUNK = 16384
#: Environment variables: the cache folder, and 0 to run the kernels in CasADi's virtual machine.
CACHE_VARIABLE, COMPILE_VARIABLE = "MECHATRON_CACHE", "MECHATRON_COMPILE"
#: A solution the driver accepts moved from its guess by at most this fraction of the change it predicted, plus
#: :data:`SLACK` (m or rad): as :meth:`mechatron.kinematics.sweep._Continuation._compiled_newton`.
ACCEPT, SLACK = 0.5, 1e-9

#: The driver, in C, appended to the generated ``step`` and ``analyse`` (see the module docstring). Sizes and
#: indices are filled in per mechanism; the table is (rows, n) row-major: T[r, k] at ``table[r * n + k]``.
DRIVER = r"""
/* mechatron: the continuation over samples by the generated mechatron_step and mechatron_analyse */
#include <math.h>
#include <string.h>
#define M_NQ %(nq)d
#define M_NA %(na)d
#define M_ND %(nd)d
#define M_NOUT %(nout)d
#define M_NSTEP (M_ND + 1 + M_ND * M_NA)
#define M_STEPS %(steps)d
#define M_FIRST %(first)d
#define M_TOL %(tolerance)r
#define M_ACCEPT %(accept)r
#define M_SLACK %(slack)r
typedef long long m_int;
static const int M_ACT[M_NA] = {%(act)s};
static const int M_DEP[M_ND] = {%(dep)s};
typedef struct {
  const casadi_real* arg[%(sz_arg)d];
  casadi_real* res[%(sz_res)d];
  casadi_int iw[%(sz_iw)d + 1];
  casadi_real w[%(sz_w)d + 1];
} m_work;

/* One Newton step at q: the dependent coordinates after it (next), the maps S_d at q; returns max |Phi(q)|. */
static double m_step(m_work* s, const double* q, double* next, double* maps) {
  double out[M_NSTEP];
  s->arg[0] = q;
  s->res[0] = out;
  mechatron_step(s->arg, s->res, s->iw, s->w, 0);
  memcpy(next, out, sizeof(double) * M_ND);
  memcpy(maps, out + M_ND + 1, sizeof(double) * M_ND * M_NA);
  return out[M_ND];
}

/* Newton's method on q in place, as LoopSolver.newton with polish: a step while max |Phi| >= M_TOL, one more at the
   first iterate below it; 1 if that happened within `steps` evaluations (maps: S_d at that iterate). With
   `decreasing`, also 0 as soon as a step does not decrease max |Phi| (where LoopSolver.newton would halve it). */
static int m_newton(m_work* s, double* q, double* maps, int steps, int decreasing) {
  double next[M_ND], last = INFINITY;
  for (int i = 0; i < steps; ++i) {
    double error = m_step(s, q, next, maps);
    if (!isfinite(error) || (decreasing && !(error < last))) return 0;
    for (int d = 0; d < M_ND; ++d) q[M_DEP[d]] = next[d];
    if (error < M_TOL) return 1;
    last = error;
  }
  return 0;
}

/* The analysis at q (rates r, accelerations a) written with q into the table's rows (-1: not kept) and into
   motion (3, n, M_NQ): q, its rates and accelerations sample by sample. */
static void m_analyse(m_work* s, const double* q, const double* r, const double* a, double* table, double* motion,
                      m_int n, m_int k, const m_int* rows) {
  double out[M_NOUT];
  s->arg[0] = q;
  s->arg[1] = r;
  s->arg[2] = a;
  s->res[0] = out;
  mechatron_analyse(s->arg, s->res, s->iw, s->w, 0);
  for (int i = 0; i < M_NQ; ++i) {
    if (rows[i] >= 0) table[rows[i] * n + k] = q[i];
    motion[k * M_NQ + i] = q[i];
    motion[(n + k) * M_NQ + i] = out[i];
    motion[(2 * n + k) * M_NQ + i] = out[M_NQ + i];
  }
  for (int j = 0; j < M_NOUT; ++j)
    if (rows[M_NQ + j] >= 0) table[rows[M_NQ + j] * n + k] = out[j];
}

/* The guess of sample k from the last m solutions (history, oldest first): the polynomial through them one step on
   (m >= 2, equal steps), else along the maps S_d of the last for input steps up to `reach`; returns the largest
   change it predicts (-1: no guess, the input step is longer). */
static double m_guess(const double* history, m_int m, const double* maps, const double* u, const double* reach,
                      double* trial) {
  const double* h = history + (m - 1) * M_NQ;
  double change = 0.0;
  if (m >= 2) {
    for (int i = 0; i < M_NQ; ++i) {
      double h0 = h[i], h1 = h[i - M_NQ];
      double x = m == 2 ? 2 * h0 - h1
               : m == 3 ? 3 * h0 - 3 * h1 + h[i - 2 * M_NQ]
                        : 4 * h0 - 6 * h1 + 4 * h[i - 2 * M_NQ] - h[i - 3 * M_NQ];
      trial[i] = x;
      if (fabs(h0 - h1) > change) change = fabs(h0 - h1);
    }
    return change;
  }
  memcpy(trial, h, sizeof(double) * M_NQ);
  for (int a = 0; a < M_NA; ++a) {
    double du = u[a] - h[M_ACT[a]];
    if (!(fabs(du) <= reach[a])) return -1.0;
    if (fabs(du) > change) change = fabs(du);
    for (int d = 0; d < M_ND; ++d) trial[M_DEP[d]] += maps[d + a * M_ND] * du;
  }
  for (int d = 0; d < M_ND; ++d)
    if (fabs(trial[M_DEP[d]] - h[M_DEP[d]]) > change) change = fabs(trial[M_DEP[d]] - h[M_DEP[d]]);
  return change;
}

/* Samples start ... stop-1 by continuation; returns the first one not solved here (stop when all were): an invalid
   input, no convergence, or a solution farther from its guess than allowed (with no solution before, Newton's
   method from `begin` (M_NQ), as LoopSolver.newton while its full steps decrease the residual). state: the number
   of solutions in history (0 to 4) and whether maps belong to the last one; both updated. */
m_int mechatron_continue(m_int start, m_int stop, m_int n, const double* U, const double* R, const double* A,
                         const unsigned char* same, const unsigned char* valid, const double* begin,
                         const double* reach, double* history, m_int* state, double* maps, double* table,
                         double* motion, const m_int* rows) {
  m_work s;
  double trial[M_NQ], q[M_NQ], fresh[M_ND * M_NA + 1], next[M_ND + 1];
  for (m_int k = start; k < stop; ++k) {
    m_int m = state[0];
    double limit = INFINITY;
    if (!valid[k]) return k;
    if (m > 1 && !same[k]) {
      memmove(history, history + (m - 1) * M_NQ, sizeof(double) * M_NQ);
      m = state[0] = 1;
    }
    if (m == 1 && !state[1]) {
      m_step(&s, history, next, maps);
      state[1] = 1;
    }
    if (m) {
      double change = m_guess(history, m, maps, U + k * M_NA, reach, trial);
      if (change < 0.0) return k;
      limit = M_ACCEPT * change + M_SLACK;
    } else {
      memcpy(trial, begin, sizeof(double) * M_NQ);
    }
    for (int a = 0; a < M_NA; ++a) trial[M_ACT[a]] = U[k * M_NA + a];
    memcpy(q, trial, sizeof(double) * M_NQ);
    if (!m_newton(&s, q, fresh, m ? M_STEPS : M_FIRST, m == 0)) return k;
    for (int i = 0; i < M_NQ; ++i)
      if (!(fabs(q[i] - trial[i]) <= limit)) return k;
    if (m == 4) {
      memmove(history, history + M_NQ, sizeof(double) * 3 * M_NQ);
      m = 3;
    }
    memcpy(history + m * M_NQ, q, sizeof(double) * M_NQ);
    state[0] = m + 1;
    memcpy(maps, fresh, sizeof(double) * M_ND * M_NA);
    state[1] = 1;
    m_analyse(&s, q, R + k * M_NA, A + k * M_NA, table, motion, n, k, rows);
  }
  return stop;
}

/* The analysis of the samples index[0 ... count-1] at their coordinates in motion. */
void mechatron_analyse_rows(m_int count, const m_int* index, m_int n, const double* R, const double* A,
                            double* table, double* motion, const m_int* rows) {
  m_work s;
  double q[M_NQ];
  for (m_int c = 0; c < count; ++c) {
    m_int k = index[c];
    memcpy(q, motion + k * M_NQ, sizeof(double) * M_NQ);
    m_analyse(&s, q, R + k * M_NA, A + k * M_NA, table, motion, n, k, rows);
  }
}
"""


def cache_folder() -> Path:
    """Where compiled kernels are kept: ``MECHATRON_CACHE``, else ``$XDG_CACHE_HOME/mechatron/kernels`` or
    ``~/.cache/mechatron/kernels``."""
    if os.environ.get(CACHE_VARIABLE):
        return Path(os.environ[CACHE_VARIABLE])
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "mechatron" / "kernels"


def library(functions: list, extra: str = "") -> Path | None:
    """The shared library of ``functions`` (CasADi ``Function``\\ s, the first naming it) with the C text ``extra``
    appended to their generated code: compiled into the :func:`cache_folder` (reused when the same source was
    compiled before); None when compiling is switched off or fails."""
    import casadi as ca

    if os.environ.get(COMPILE_VARIABLE, "1").strip() == "0":
        return None
    name = functions[0].name()
    try:
        folder = cache_folder()
        folder.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryDirectory(dir=folder) as work:
            source = Path(work) / f"{name}.c"
            generator = ca.CodeGenerator(source.name, {"with_header": False})
            for function in functions:
                generator.add(function)
            generator.generate(work + os.sep)
            text = source.read_bytes() + extra.encode()
            source.write_bytes(text)
            path = folder / f"{name}_{hashlib.sha256(text).hexdigest()[:20]}.so"
            if not path.exists():
                partial = Path(work) / path.name
                compiler = os.environ.get("CC", "cc")
                subprocess.run([compiler, "-O2", "-shared", "-fPIC", "-o", str(partial), str(source), "-lm"],
                               check=True, capture_output=True, timeout=300)
                os.replace(partial, path)  # whole or not at all: concurrent runs may race, both write the same
        return path
    except (OSError, subprocess.SubprocessError, RuntimeError):
        return None


def compiled(function):
    """``function`` (a CasADi ``Function``) as machine code: its generated C compiled into a shared library in the
    :func:`cache_folder` (reused when the same source was compiled before) and loaded with ``casadi.external``;
    the function itself (CasADi's virtual machine) when compiling is switched off or fails."""
    return external(function, library([function]))


def external(function, path: Path | None):
    """``function`` loaded from the library ``path`` with ``casadi.external``; itself where there is no library or
    it cannot be loaded."""
    import casadi as ca

    if path is None:
        return function
    try:
        return ca.external(function.name(), str(path))
    except RuntimeError:
        return function


def _pointer(array: np.ndarray) -> int:
    """The address of ``array``'s data (for ``ctypes``)."""
    return array.ctypes.data


class LoopKernel:
    """The compiled ``newton``, ``analyse`` and ``step`` of a loop solver's closures, see the module docstring,
    reporting the columns of a sweep's table: of the frames ``points`` the position (x, y and, when ``spatial``, z;
    m), velocity and its size (m/s), acceleration and its size (m/s²); of the frames ``links`` the angle about z in
    (−π, π], its rate and acceleration (rad, rad/s, rad/s²); of the frames ``others`` x and y (m). :meth:`newton` and
    :meth:`analyse` take and return NumPy arrays of N samples; :meth:`continuation` runs the driver (where
    :attr:`driven`) over samples into a table."""

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
        q = ca.SX.sym("q", nq)
        closing = frame_placements(model, [mech.frame_id(n) for n in system.frame_names], q)
        phi = closure_residual(system, dict(zip(system.frame_names, closing)), q)
        J = ca.jacobian(phi, q)
        self._newton = compiled(self._newton_function(ca, q, phi, J))
        analyse, self.names = self._analyse_function(ca, solver, q, phi, J, points, links, others, spatial)
        step = self._step_function(ca, q, phi, J)
        path = library([analyse, step], self._driver_source(analyse, step))
        self._analyse = external(analyse, path)
        self._driver = self._load_driver(path) if self._analyse is not analyse else None
        self._mapped: dict = {}

    def _newton_function(self, ca, q, phi, J):
        """``newton``: :data:`STEPS` unrolled steps on q_d, as LoopSolver.newton with polish: a step while the
        residual is at or above TOLERANCE, one more (polishing) step at the first iterate below it, none after."""
        dep, act, nq = self.dep, self.act, self.nq
        residual = ca.Function("residual", [q], [phi, J])
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
        return ca.Function("mechatron_newton", [guess], [newton])

    def _step_function(self, ca, q, phi, J):
        """``step``: one Newton step of one sample: q_d − J_d⁻¹ Φ(q), max |Φ(q)| and S_d = −J_d⁻¹ J_a at q (column
        by column), as one step of ``newton``."""
        dep, act = self.dep, self.act
        inverse = ca.inv(J[:, dep])
        after = q[dep] - ca.mtimes(inverse, phi)
        outputs = ca.cse(ca.vertcat(after, ca.mmax(ca.fabs(phi)), ca.vec(-ca.mtimes(inverse, J[:, act]))))
        return ca.Function("mechatron_step", [q], [outputs])

    def _analyse_function(self, ca, solver, q, phi, J, points, links, others, spatial):
        """``analyse`` (velocities, accelerations, max |J_d⁻¹| and the reported frames, see the module docstring)
        and the names of its frame columns."""
        mech, model, act, dep, nq = solver.mech, solver.mech.model, self.act, self.dep, self.nq
        v, a = ca.SX.sym("v", nq), ca.SX.sym("a", nq)
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
        return ca.Function("mechatron_analyse", [q, rates, accelerations], [outputs]), names

    def _driver_source(self, analyse, step) -> str:
        """:data:`DRIVER` with this kernel's sizes and indices."""
        def size(name: str) -> int:
            return max(getattr(f, name)() for f in (analyse, step))

        return DRIVER % {"nq": self.nq, "na": self.na, "nd": self.nd, "nout": analyse.size1_out(0), "steps": STEPS,
                         "first": FIRST_STEPS,
                         "tolerance": TOLERANCE, "accept": ACCEPT, "slack": SLACK,
                         "act": ", ".join(map(str, self.act)), "dep": ", ".join(map(str, self.dep)),
                         "sz_arg": size("sz_arg"), "sz_res": size("sz_res"), "sz_iw": size("sz_iw"),
                         "sz_w": size("sz_w")}

    @staticmethod
    def _load_driver(path: Path):
        """The driver's functions in the library ``path`` (``ctypes``), or None where it cannot be loaded."""
        try:
            lib = ctypes.CDLL(str(path))
        except OSError:
            return None
        integer, address = ctypes.c_longlong, ctypes.c_void_p
        lib.mechatron_continue.restype = integer
        lib.mechatron_continue.argtypes = [integer] * 3 + [address] * 13
        lib.mechatron_analyse_rows.restype = None
        lib.mechatron_analyse_rows.argtypes = [integer, address, integer] + [address] * 5
        return lib

    @property
    def driven(self) -> bool:
        """Whether the compiled driver is there (:meth:`continuation`, :meth:`analyse_rows`)."""
        return self._driver is not None

    def outputs(self) -> int:
        """The number of ``analyse``'s outputs per sample: q̇, q̈, max |J_d⁻¹| and the frame columns."""
        return 2 * self.nq + 1 + len(self.names)

    def continuation(self, start: int, stop: int, arrays: dict[str, np.ndarray]) -> int:
        """The driver's continuation over the samples ``start`` … ``stop − 1`` (see :data:`DRIVER`): ``arrays``
        holds the inputs ``U``, rates ``R`` and accelerations ``A`` (N, n_act; C-ordered floats), ``same`` and
        ``valid`` (N, uint8: the input step equals the previous one; the input is in range), ``begin`` (nq: where
        Newton's method starts without a solution before), ``reach`` (n_act: the longest input steps guessed along
        the velocity maps, m or rad), ``history`` (4, nq: the last solutions, oldest first),
        ``state`` (2, int64: how many, whether ``maps`` (n_dep · n_act) are the last one's), ``table`` (rows, N),
        ``motion`` (3, N, nq: q, q̇, q̈ of every sample) and ``rows`` (nq + :meth:`outputs`, int64: the table row of
        each q_i and each output, −1 for none). Returns the first sample not solved (``stop`` when all were)."""
        x = arrays
        return self._driver.mechatron_continue(
            start, stop, len(x["U"]), _pointer(x["U"]), _pointer(x["R"]), _pointer(x["A"]), _pointer(x["same"]),
            _pointer(x["valid"]), _pointer(x["begin"]), _pointer(x["reach"]), _pointer(x["history"]),
            _pointer(x["state"]),
            _pointer(x["maps"]), _pointer(x["table"]), _pointer(x["motion"]), _pointer(x["rows"]))

    def analyse_rows(self, index: np.ndarray, arrays: dict[str, np.ndarray]) -> None:
        """``analyse`` of the samples ``index`` (int64) at their coordinates in ``arrays["motion"][0]``, written
        into the table and ``motion`` (the ``arrays`` of :meth:`continuation`)."""
        index = np.ascontiguousarray(index, dtype=np.int64)
        x = arrays
        self._driver.mechatron_analyse_rows(len(index), _pointer(index), x["table"].shape[1], _pointer(x["R"]),
                                            _pointer(x["A"]), _pointer(x["table"]), _pointer(x["motion"]),
                                            _pointer(x["rows"]))

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
