r"""Closed-loop position, velocity and acceleration analysis compiled to machine code with CasADi, run over samples.

The loop equations Φ(q) = 0 of a mechanism (:mod:`mechatron.model.symbolic`) and their exact derivatives become three
CasADi functions of one sample:

- ``newton``: from a guess q⁽⁰⁾ (its actuated entries the inputs), up to :data:`STEPS` Newton steps on the
  dependent coordinates, q_d ← q_d − J_d⁻¹ Φ(q), unrolled: as :meth:`~mechatron.kinematics.loops.LoopSolver.newton`
  with ``polish``, a step while max |Φ| ≥ :data:`~mechatron.kinematics.loops.TOLERANCE`, one more at the first
  iterate below it and none after (``if_else`` keeps the rest); outputs q, whether it converged and the dependent
  velocity maps S_d = −J_d⁻¹ J_a at the iterate of the polishing step;
- ``step``: one of those steps, with max |Φ(q)| and S_d at q;
- ``analyse``: at an assembled q with actuated rates q̇_a and accelerations q̈_a: q̇ = S q̇_a, q̈_d = −J_d⁻¹
  (J_a q̈_a + J̇ q̇) ([Egorov, 4.2–4.16]), max |J_d⁻¹| (the singularity measure of
  :data:`~mechatron.kinematics.loops.SINGULAR_RATIO`), and of every reported frame its origin p, its angle about z,
  the velocity ṗ = J_p q̇, the angular velocity ω_z = (Ṙ Rᵀ)₁₀, the classical acceleration p̈ = J_p q̈ + J̇_p q̇ and
  the angular acceleration α_z = ω̇_z (J̇ q̇ as the second directional derivative of the expressions along q̇).

They are generated as C (``casadi.CodeGenerator``), compiled once with the system's C compiler (``cc``, or the one
in ``CC``; :data:`mechatron.io.native.FLAGS`) into shared libraries kept in a cache folder (``MECHATRON_CACHE``, else
``$XDG_CACHE_HOME/mechatron`` or ``~/.cache/mechatron``) under the hash of their source and options, and evaluated
over chunks of samples by ``Function.map`` (:meth:`LoopKernel.newton`, :meth:`LoopKernel.analyse`).

The sweep's fast path is a driver in C compiled with ``step`` and ``analyse`` into their library (:data:`DRIVER`,
called through ``ctypes`` once per chunk of samples, :class:`DriverRun`): the sequential continuation of
:class:`mechatron.kinematics.sweeps._Continuation` over the samples — each sample's guess the polynomial through the
last solutions one input step on (or, where the step changed, along the velocity maps for steps up to the solver's
continuation step), ``step`` until the residual is below the tolerance plus the polishing step, accepted only if
the solution moved less than half the predicted change (the first sample: Newton's method with halved steps, as
:meth:`~mechatron.kinematics.loops.LoopSolver.newton`) —, then ``analyse`` of every :data:`LANES` solutions at once
(:func:`blocked`: each operation on a vector of samples, with the numbers of the scalar function), written straight
into the rows of the sweep's table. A sample it does not accept is left to the caller. There is no CasADi map with
its argument buffers (about 0.1 µs a call of a mapped function), no second pass and no copy into the table: a
sample costs one or two ``step``\ s and its share of ``analyse``, a few hundred floating-point operations and two or
three sine-cosine pairs (the CSE of CasADi leaves little: a canonical ordering of commutative operations would
remove ~8 %; compiler options matter by ~10 %, the vector lanes by ~20 %).

Without a working compiler, or with ``MECHATRON_COMPILE=0``, the functions run in CasADi's virtual machine and
there is no driver. Mechanisms with joints or closures that have no symbolic form get no kernel (:func:`loop_kernel`
returns None) and the NumPy path of :mod:`mechatron.kinematics.batch` is used.
"""

from __future__ import annotations

import ctypes
import os
from collections.abc import Hashable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..io.native import compiling, settings, shared_library
from ..model.symbolic import Unsupported, angle_about_z, closure_residual, frame_placements, joint_placements
from .loops import TOLERANCE

if TYPE_CHECKING:
    from ..model.symbolic import Geometry
    from .loops import LoopSolver

#: Unrolled Newton steps of the compiled solve (``newton``), and the most steps of the driver's: from guesses
#: interpolated between anchors (up to ~1e-3 off), the third step reaches ~1e-12 (Newton's error squares) and the
#: fourth rounding level.
STEPS = 4
#: The most Newton steps of the driver's first sample (no solution before it: from the sweep's start), as
#: :meth:`~mechatron.kinematics.loops.LoopSolver.newton`'s iterations.
FIRST_STEPS = 50
#: Samples per call of a mapped function, per chunk of the sweep's batched solve with a kernel (its working
#: storage is ~100 B a sample) and per call of the driver (the sweep's progress is reported between them).
CHUNK = 16384
#: A solution the driver accepts moved from its guess by at most this fraction of the change it predicted, plus
#: :data:`SLACK` (m or rad): as :meth:`mechatron.kinematics.sweeps._Continuation._compiled_newton`.
ACCEPT, SLACK = 0.5, 1e-9

#: Samples the driver analyses together: each operation of ``analyse`` on a vector of this many lanes
#: (:func:`blocked`), its results written into the table in runs of as many; compiled for AVX2 and AVX-512 besides
#: (chosen when the library is loaded) where ``analyse`` has at most :data:`CLONED` operations, else on two lanes
#: and for the baseline instruction set only (the compiler's time grows faster than the code: 3 s for the delta's
#: 5,800 operations on two lanes, 25 s on eight with the clones).
LANES, CLONED = 8, 1000
#: The driver, in C, appended to the generated ``step`` and ``analyse`` (see the module docstring). Sizes, indices
#: and the blocked ``analyse`` are filled in per mechanism; the table is (rows, n) row-major: T[r, k] at
#: ``table[r * n + k]``; motion (3, n, nq) holds q, q̇ and q̈ sample by sample.
DRIVER = r"""
/* mechatron: the continuation over samples by the generated mechatron_step and mechatron_analyse */
#include <math.h>
#include <stdlib.h>
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
#define M_L %(lanes)d
#define M_WORK %(work)d
typedef long long m_int;
static const int M_ACT[M_NA] = {%(act)s};
static const int M_DEP[M_ND] = {%(dep)s};
typedef struct {
  const casadi_real* arg[%(sz_arg)d];
  casadi_real* res[%(sz_res)d];
  casadi_int iw[%(sz_iw)d + 1];
  casadi_real w[%(sz_w)d + 1];
  const double* P; /* the geometry's parameters (Geometry) */
} m_work;

/* mechatron_analyse over M_L lanes: q (M_NQ, M_L), r and a (M_NA, M_L), the parameters P to out (M_NOUT, M_L);
   w: M_WORK doubles;
   with vector types where the compiler has them (GCC's extension), cloned for the vector units there are (chosen
   when the library is loaded; -ffp-contract=off: the same numbers as the scalar function) */
#if %(cloned)d && defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && defined(__GLIBC__)
#define M_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#define M_CLONES
#endif
#if defined(__GNUC__) && %(vector)d
typedef double m_v __attribute__((vector_size(sizeof(double) * M_L)));
#define M_SPLAT(c) ((m_v){0} + (c))
M_CLONES %(block)s
#else
%(scalar)s
#endif

/* One Newton step at q: the dependent coordinates after it (next), the maps S_d at q; returns max |Phi(q)|. */
static double m_step(m_work* s, const double* q, double* next, double* maps) {
  double out[M_NSTEP];
  s->arg[0] = q;
  s->arg[1] = s->P;
  s->res[0] = out;
  mechatron_step(s->arg, s->res, s->iw, s->w, 0);
  memcpy(next, out, sizeof(double) * M_ND);
  memcpy(maps, out + M_ND + 1, sizeof(double) * M_ND * M_NA);
  return out[M_ND];
}

/* Newton's method on q in place, as LoopSolver.newton with polish from a close guess: a step while max |Phi| >= M_TOL,
   one more at the first iterate below it; 1 if that happened within M_STEPS evaluations (maps: S_d there). */
static int m_newton(m_work* s, double* q, double* maps) {
  double next[M_ND];
  for (int i = 0; i < M_STEPS; ++i) {
    double error = m_step(s, q, next, maps);
    if (!isfinite(error)) return 0;
    for (int d = 0; d < M_ND; ++d) q[M_DEP[d]] = next[d];
    if (error < M_TOL) return 1;
  }
  return 0;
}

/* LoopSolver.newton with polish from a far guess, on q in place: up to M_FIRST steps, each halved while it does not
   decrease max |Phi| (down to 1/1024), the polishing step below M_TOL; 1 if it converged. */
static int m_far(m_work* s, double* q, double* maps) {
  double next[M_ND], step[M_ND], trial[M_NQ];
  double error = m_step(s, q, next, maps);
  for (int i = 0; i < M_FIRST; ++i) {
    if (error < M_TOL) {
      if (error > 0.0)
        for (int d = 0; d < M_ND; ++d) q[M_DEP[d]] = next[d];
      return 1;
    }
    double t = 1.0, reached;
    for (int d = 0; d < M_ND; ++d) step[d] = next[d] - q[M_DEP[d]];
    while (1) {
      memcpy(trial, q, sizeof(double) * M_NQ);
      for (int d = 0; d < M_ND; ++d) trial[M_DEP[d]] += t * step[d];
      reached = m_step(s, trial, next, maps);
      if (reached < error || t < 1e-3) break;
      t /= 2;
    }
    memcpy(q, trial, sizeof(double) * M_NQ);
    error = reached;
  }
  return error < M_TOL;
}

/* The analysis of `count` (<= M_L) samples, k0 + l or index[l] (index not NULL), at their q in motion: q, q' and q''
   into motion, q and the outputs into the table's rows (-1: not kept). */
static void m_analyse(const m_int* index, m_int k0, int count, m_int n, const double* R, const double* A,
                      const double* P, double* table, double* motion, const m_int* rows, double* w) {
  double q[M_NQ * M_L], r[M_NA * M_L], a[M_NA * M_L], out[M_NOUT * M_L];
  m_int at[M_L];
  for (int l = 0; l < M_L; ++l) {
    m_int k = at[l] = index ? index[l < count ? l : count - 1] : k0 + (l < count ? l : count - 1);
    for (int i = 0; i < M_NQ; ++i) q[i * M_L + l] = motion[k * M_NQ + i];
    for (int b = 0; b < M_NA; ++b) {
      r[b * M_L + l] = R[k * M_NA + b];
      a[b * M_L + l] = A[k * M_NA + b];
    }
  }
  m_block(q, r, a, P, out, w);
  for (int l = 0; l < count; ++l)
    for (int i = 0; i < M_NQ; ++i) {
      motion[(n + at[l]) * M_NQ + i] = out[i * M_L + l];
      motion[(2 * n + at[l]) * M_NQ + i] = out[(M_NQ + i) * M_L + l];
    }
  for (int j = 0; j < M_NQ + M_NOUT; ++j) {
    if (rows[j] < 0) continue;
    double* row = table + rows[j] * n;
    const double* value = j < M_NQ ? q + j * M_L : out + (j - M_NQ) * M_L;
    if (!index && count == M_L)
      memcpy(row + k0, value, sizeof(double) * M_L);
    else
      for (int l = 0; l < count; ++l) row[at[l]] = value[l];
  }
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

/* The position of sample k into q: 1 if solved (see mechatron_continue), history and state updated. */
static int m_position(m_work* s, m_int k, const double* U, const unsigned char* same, const double* begin,
                      const double* reach, double* history, m_int* state, double* maps, double* q) {
  double trial[M_NQ], fresh[M_ND * M_NA + 1], next[M_ND + 1], limit = INFINITY;
  m_int m = state[0];
  if (m > 1 && !same[k]) {
    memmove(history, history + (m - 1) * M_NQ, sizeof(double) * M_NQ);
    m = state[0] = 1;
  }
  if (m == 1 && !state[1]) {
    m_step(s, history, next, maps);
    state[1] = 1;
  }
  if (m) {
    double change = m_guess(history, m, maps, U + k * M_NA, reach, trial);
    if (change < 0.0) return 0;
    limit = M_ACCEPT * change + M_SLACK;
  } else {
    memcpy(trial, begin, sizeof(double) * M_NQ);
  }
  for (int a = 0; a < M_NA; ++a) trial[M_ACT[a]] = U[k * M_NA + a];
  memcpy(q, trial, sizeof(double) * M_NQ);
  if (!(m ? m_newton(s, q, fresh) : m_far(s, q, fresh))) return 0;
  for (int i = 0; i < M_NQ; ++i)
    if (!(fabs(q[i] - trial[i]) <= limit)) return 0;
  if (m == 4) {
    memmove(history, history + M_NQ, sizeof(double) * 3 * M_NQ);
    m = 3;
  }
  memcpy(history + m * M_NQ, q, sizeof(double) * M_NQ);
  state[0] = m + 1;
  memcpy(maps, fresh, sizeof(double) * M_ND * M_NA);
  state[1] = 1;
  return 1;
}

/* Samples start ... stop-1 by continuation; returns the first one not solved here (stop when all were): an invalid
   input, no convergence, or a solution farther from its guess than allowed (with no solution before, Newton's
   method from `begin` (M_NQ) as LoopSolver.newton). state: the number of solutions in history (0 to 4) and whether
   maps belong to the last one; both updated. The solved samples are analysed M_L at a time. */
m_int mechatron_continue(m_int start, m_int stop, m_int n, const double* U, const double* R, const double* A,
                         const unsigned char* same, const unsigned char* valid, const double* begin,
                         const double* reach, double* history, m_int* state, double* maps, double* table,
                         double* motion, const m_int* rows, const double* P) {
  m_work s;
  double* w = malloc(sizeof(double) * M_WORK);
  m_int k = start, first = start;
  if (!w) return start;
  s.P = P;
  for (; k < stop; ++k) {
    if (!valid[k] || !m_position(&s, k, U, same, begin, reach, history, state, maps, motion + k * M_NQ)) break;
    if (k + 1 - first == M_L) {
      m_analyse(NULL, first, M_L, n, R, A, P, table, motion, rows, w);
      first = k + 1;
    }
  }
  if (k > first) m_analyse(NULL, first, (int)(k - first), n, R, A, P, table, motion, rows, w);
  free(w);
  return k;
}

/* The analysis of the samples index[0 ... count-1] at their coordinates in motion. */
void mechatron_analyse_rows(m_int count, const m_int* index, m_int n, const double* R, const double* A,
                            double* table, double* motion, const m_int* rows, const double* P) {
  double* w = malloc(sizeof(double) * M_WORK);
  if (!w) return;
  for (m_int c = 0; c < count; c += M_L)
    m_analyse(index + c, 0, (int)(count - c < M_L ? count - c : M_L), n, R, A, P, table, motion, rows, w);
  free(w);
}

/* Newton's method with halved steps from the guess q (M_NQ, in place: the last iterate), as m_far; 1 if it
   converged. */
int mechatron_far(double* q, const double* P) {
  m_work s;
  double maps[M_ND * M_NA + 1];
  s.P = P;
  return m_far(&s, q, maps);
}

/* The velocity maps S_d = -J_d^-1 J_a (M_ND x M_NA, column-major) at each of the `count` configurations Q
   (count, M_NQ) into out (count, M_ND * M_NA). */
void mechatron_maps(m_int count, const double* Q, const double* P, double* out) {
  m_work s;
  double next[M_ND + 1];
  s.P = P;
  for (m_int k = 0; k < count; ++k) m_step(&s, Q + k * M_NQ, next, out + k * M_ND * M_NA);
}
"""
#: ``analyse`` over lanes where an operation has no lane-wise form here: one sample after the other.
SCALAR_BLOCK = r"""static void m_block(const double* q, const double* r, const double* a, const double* P, double* out,
                    double* w) {
  const casadi_real* arg[%(sz_arg)d];
  casadi_real* res[%(sz_res)d];
  casadi_int iw[%(sz_iw)d + 1];
  double qs[M_NQ], rs[M_NA], as[M_NA], o[M_NOUT];
  for (int l = 0; l < M_L; ++l) {
    for (int i = 0; i < M_NQ; ++i) qs[i] = q[i * M_L + l];
    for (int b = 0; b < M_NA; ++b) {
      rs[b] = r[b * M_L + l];
      as[b] = a[b * M_L + l];
    }
    arg[0] = qs;
    arg[1] = rs;
    arg[2] = as;
    arg[3] = P;
    res[0] = o;
    mechatron_analyse(arg, res, iw, w, 0);
    for (int j = 0; j < M_NOUT; ++j) out[j * M_L + l] = o[j];
  }
}"""


def _lane_operations() -> dict[int, str]:
    """C of CasADi's scalar operations on one lane (``{0}``, ``{1}`` the arguments), as its code generator writes
    them (``fmin`` and ``fmax`` as comparisons: the other argument where one is NaN)."""
    import casadi as ca

    return {ca.OP_ASSIGN: "{0}", ca.OP_ADD: "{0}+{1}", ca.OP_SUB: "{0}-{1}", ca.OP_MUL: "{0}*{1}",
            ca.OP_DIV: "{0}/{1}", ca.OP_NEG: "-{0}", ca.OP_SQ: "{0}*{0}", ca.OP_TWICE: "2.*{0}",
            ca.OP_INV: "1./{0}", ca.OP_SQRT: "sqrt({0})", ca.OP_SIN: "sin({0})", ca.OP_COS: "cos({0})",
            ca.OP_TAN: "tan({0})", ca.OP_ASIN: "asin({0})", ca.OP_ACOS: "acos({0})", ca.OP_ATAN: "atan({0})",
            ca.OP_EXP: "exp({0})", ca.OP_LOG: "log({0})", ca.OP_FABS: "fabs({0})", ca.OP_FLOOR: "floor({0})",
            ca.OP_CEIL: "ceil({0})", ca.OP_FMIN: "({0}<{1} || {1}!={1}) ? {0} : {1}",
            ca.OP_FMAX: "({0}>{1} || {1}!={1}) ? {0} : {1}",
            ca.OP_ATAN2: "atan2({0},{1})", ca.OP_POW: "pow({0},{1})", ca.OP_CONSTPOW: "pow({0},{1})",
            ca.OP_FMOD: "fmod({0},{1})", ca.OP_COPYSIGN: "copysign({0},{1})", ca.OP_HYPOT: "hypot({0},{1})",
            ca.OP_LT: "{0}<{1}", ca.OP_LE: "{0}<={1}", ca.OP_EQ: "{0}=={1}", ca.OP_NE: "{0}!={1}",
            ca.OP_NOT: "!{0}", ca.OP_AND: "{0}&&{1}", ca.OP_OR: "{0}||{1}", ca.OP_IF_ELSE_ZERO: "{0}?{1}:0."}


def blocked(function) -> str | None:
    """C of the SX ``function`` (arguments q, rates, accelerations; one output) on vectors of ``M_L`` samples,
    ``m_block`` of :data:`DRIVER`: each of its operations, in its order, on local variables of GCC's vector type
    ``m_v`` (one per slot of CasADi's work: the compiler keeps them as it keeps the scalar code's), the arithmetic
    as vector operations, the others lane by lane, every operation as CasADi's code generator writes it, so that
    each lane gives the numbers of the scalar function; a sine and a cosine of one value are taken together (one
    ``sincos``, :func:`_trigonometric_pairs`). None where an operation or a constant has no form here."""
    import casadi as ca

    arithmetic = {ca.OP_ASSIGN: "{0}", ca.OP_ADD: "{0}+{1}", ca.OP_SUB: "{0}-{1}", ca.OP_MUL: "{0}*{1}",
                  ca.OP_DIV: "{0}/{1}", ca.OP_NEG: "-{0}", ca.OP_SQ: "{0}*{0}", ca.OP_TWICE: "2.*{0}",
                  ca.OP_INV: "1./{0}"}
    operations, pairs = _lane_operations(), _trigonometric_pairs(function)
    first = function.sz_w()
    second = {k: f"w{first + j}" for j, k in enumerate(sorted(set(pairs.values())))}  # each pair's other value
    variables = [f"w{i}" for i in range(first)] + list(second.values())
    lines = ["static void m_block(const double* restrict in0, const double* restrict in1, "
             "const double* restrict in2, const double* restrict in3, double* restrict out, double* restrict w) {",
             f"  m_v {', '.join(variables)};", "  double x0[M_L], x1[M_L], y0[M_L], y1[M_L];", "  (void)w;"]
    for k in range(function.n_instructions()):
        op, args, result = function.instruction_id(k), function.instruction_input(k), function.instruction_output(k)
        if op == ca.OP_INPUT and args[0] == 3:  # a parameter: the same in every lane
            lines.append(f"  w{result[0]} = M_SPLAT(in3[{args[1]}]);")
        elif op == ca.OP_INPUT:
            lines.append(f"  memcpy(&w{result[0]}, in{args[0]} + {args[1]} * M_L, sizeof(m_v));")
        elif op == ca.OP_OUTPUT:
            lines.append(f"  memcpy(out + {result[1]} * M_L, &w{args[0]}, sizeof(m_v));")
        elif op == ca.OP_CONST:
            value = float(function.instruction_constant(k))
            if not np.isfinite(value):
                return None
            lines.append(f"  w{result[0]} = M_SPLAT({value!r});")
        elif k in pairs and pairs[k] < k:  # the second of a pair: taken with the first
            lines.append(f"  w{result[0]} = {second[pairs[k]]};")
        elif k in pairs:  # the first of a pair: both
            names = ("sin", "cos") if op == ca.OP_SIN else ("cos", "sin")
            lines.append(f"  memcpy(x0, &w{args[0]}, sizeof(m_v)); for (int l = 0; l < M_L; ++l) "
                         f"{{ y0[l] = {names[0]}(x0[l]); y1[l] = {names[1]}(x0[l]); }} "
                         f"memcpy(&w{result[0]}, y0, sizeof(m_v)); memcpy(&{second[k]}, y1, sizeof(m_v));")
        elif op in arithmetic:
            lines.append(f"  w{result[0]} = {arithmetic[op].format(*(f'w{i}' for i in args))};")
        elif op in operations:
            loads = " ".join(f"memcpy(x{j}, &w{i}, sizeof(m_v));" for j, i in enumerate(args))
            expression = operations[op].format(*(f"x{j}[l]" for j in range(len(args))))
            lines.append(f"  {loads} for (int l = 0; l < M_L; ++l) y0[l] = {expression}; "
                         f"memcpy(&w{result[0]}, y0, sizeof(m_v));")
        else:
            return None
    return "\n".join([*lines, "}"])


def _trigonometric_pairs(function) -> dict[int, int]:
    """The sines and cosines of one value in ``function``'s instructions: instruction → the first instruction of its
    pair (itself for the first), where the value's work slot is not written between the two."""
    import casadi as ca

    pairs: dict[int, int] = {}
    waiting: dict[int, tuple[int, int]] = {}  # work slot → (first instruction, its operation)
    for k in range(function.n_instructions()):
        op, args, result = function.instruction_id(k), function.instruction_input(k), function.instruction_output(k)
        if op in (ca.OP_SIN, ca.OP_COS):
            first = waiting.get(args[0])
            if first is not None and first[1] != op:
                pairs[first[0]], pairs[k] = first[0], first[0]
                del waiting[args[0]]
            elif first is None:
                waiting[args[0]] = (k, op)
        if op != ca.OP_OUTPUT:
            waiting = {slot: first for slot, first in waiting.items() if slot != result[0]}
    return pairs


def library(functions: list, extra: str = "") -> Path | None:
    """The shared library of ``functions`` (CasADi ``Function``\\ s, the first naming it) with the C text ``extra``
    appended to their generated code (:func:`mechatron.io.native.shared_library`: compiled once into the cache
    folder); None when compiling is switched off or fails."""
    import casadi as ca

    if not compiling():
        return None
    name = functions[0].name()

    def write(work: Path) -> bytes:
        generator = ca.CodeGenerator(f"{name}.c", {"with_header": False})
        for function in functions:
            generator.add(function)
        generator.generate(str(work) + os.sep)
        return (work / f"{name}.c").read_bytes() + extra.encode()

    return shared_library(name, write)


def compiled(function):
    """``function`` (a CasADi ``Function``) as machine code: its generated C compiled into a shared library in the
    cache folder (reused when the same source was compiled before) and loaded with ``casadi.external``;
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


class KernelCode:
    """What a :class:`LoopKernel` compiles, once per structure: the CasADi functions ``newton``, ``step`` and
    ``analyse`` of (q, …, p) with the geometry p as an input (:class:`~mechatron.model.symbolic.Geometry`), their
    shared library with the driver, and the names of the frame columns. Every mechanism whose loops, joints, frames
    and reported frames have the same :attr:`~mechatron.model.symbolic.Geometry.signature` — a design study's
    geometries — shares one (:func:`loop_kernel`)."""

    def __init__(self, solver: LoopSolver, geometry: Geometry, points: list[str], links: list[str],
                 others: Sequence[str] = (), spatial: bool = False) -> None:
        import casadi as ca

        mech, system = solver.mech, solver.system
        model = mech.model
        if len(solver.dep) != system.nrows or not len(solver.dep):
            raise Unsupported("the closures do not determine the dependent coordinates one to one")
        nq, act, dep = model.nq, [int(i) for i in solver.act], [int(i) for i in solver.dep]
        self.nq, self.na, self.nd, self.act, self.dep = nq, len(act), len(dep), act, dep
        self.others = list(others)
        self.size = geometry.size
        q, p = ca.SX.sym("q", nq), ca.SX.sym("p", geometry.size)
        joints, frames, constants = geometry.symbols(ca, p)
        self._placements = lambda names, at: dict(zip(names, frame_placements(
            model, [mech.frame_id(n) for n in names], at, joints=joint_placements(model, at, given=joints),
            given=frames)))
        closing = self._placements(system.frame_names, q)
        phi = closure_residual(system, closing, q, given=constants)
        J = ca.jacobian(phi, q)
        self._newton = compiled(self._newton_function(ca, q, p, phi, J))
        analyse, self.names = self._analyse_function(ca, q, p, phi, J, points, links, others, spatial)
        step = self._step_function(ca, q, p, phi, J)
        path = library([analyse, step], self._driver_source(analyse, step))
        self._analyse = external(analyse, path)
        self._driver = self._load_driver(path) if path is not None and self._analyse is not analyse else None
        self._mapped: dict = {}
        del self._placements  # it holds the first mechanism's model

    def _newton_function(self, ca, q, p, phi, J):
        """``newton``: :data:`STEPS` unrolled steps on q_d, as LoopSolver.newton with polish: a step while the
        residual is at or above TOLERANCE, one more (polishing) step at the first iterate below it, none after."""
        dep, act, nq = self.dep, self.act, self.nq
        residual = ca.Function("residual", [q, p], [phi, J])
        guess = ca.SX.sym("guess", nq)
        qk, done, maps = guess, ca.SX(0), ca.SX.nan(len(dep), len(act))
        for _ in range(STEPS):
            phi_k, J_k = residual(qk, p)
            inverse = ca.inv(J_k[:, dep])
            step = ca.if_else(done, ca.SX.zeros(len(dep)), ca.mtimes(inverse, phi_k))
            maps = ca.if_else(done, maps, -ca.mtimes(inverse, J_k[:, act]))
            qk = ca.vertcat(*[qk[i] - step[dep.index(i)] if i in dep else qk[i] for i in range(nq)])
            done = ca.logic_or(done, ca.mmax(ca.fabs(phi_k)) < TOLERANCE)
        newton = ca.cse(ca.vertcat(qk, done, ca.vec(maps)))  # sin q of an input is shared by every step
        return ca.Function("mechatron_newton", [guess, p], [newton])

    def _step_function(self, ca, q, p, phi, J):
        """``step``: one Newton step of one sample: q_d − J_d⁻¹ Φ(q), max |Φ(q)| and S_d = −J_d⁻¹ J_a at q (column
        by column), as one step of ``newton``."""
        dep, act = self.dep, self.act
        inverse = ca.inv(J[:, dep])
        after = q[dep] - ca.mtimes(inverse, phi)
        outputs = ca.cse(ca.vertcat(after, ca.mmax(ca.fabs(phi)), ca.vec(-ca.mtimes(inverse, J[:, act]))))
        return ca.Function("mechatron_step", [q, p], [outputs])

    def _analyse_function(self, ca, q, p, phi, J, points, links, others, spatial):
        """``analyse`` (velocities, accelerations, max |J_d⁻¹| and the reported frames, see the module docstring)
        and the names of its frame columns."""
        act, dep, nq = self.act, self.dep, self.nq
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
        placements = self._placements(list(dict.fromkeys([*points, *links, *others])), q)
        axes = "xyz" if spatial else "xy"
        for name in points:  # as sweep's frame columns: position, velocity and its size, acceleration and its size
            position = placements[name][1][:len(axes)]
            p_dot = ca.jtimes(position, q, v)
            p_ddot = ca.jtimes(p_dot, state, motion)
            for label, value in (("", position), ("v", p_dot), ("a", p_ddot)):
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
        return ca.Function("mechatron_analyse", [q, rates, accelerations, p], [outputs]), names

    def _driver_source(self, analyse, step) -> str:
        """:data:`DRIVER` with this kernel's sizes and indices and ``analyse`` on vectors of lanes (:func:`blocked`;
        :data:`LANES` and cloned up to :data:`CLONED` operations, else two lanes; :data:`SCALAR_BLOCK` where it has
        no vector form)."""
        def size(name: str) -> int:
            return max(getattr(f, name)() for f in (analyse, step))

        sizes = {"sz_arg": size("sz_arg"), "sz_res": size("sz_res"), "sz_iw": size("sz_iw"), "sz_w": size("sz_w")}
        cloned = analyse.n_instructions() <= CLONED
        block = blocked(analyse)
        return DRIVER % {"nq": self.nq, "na": self.na, "nd": self.nd, "nout": analyse.size1_out(0), "steps": STEPS,
                         "first": FIRST_STEPS, "tolerance": TOLERANCE, "accept": ACCEPT, "slack": SLACK,
                         "lanes": LANES if cloned else 2, "work": sizes["sz_w"] + 1, "cloned": int(cloned),
                         "vector": int(block is not None), "block": block or "", "scalar": SCALAR_BLOCK % sizes,
                         "act": ", ".join(map(str, self.act)), "dep": ", ".join(map(str, self.dep)), **sizes}

    @staticmethod
    def _load_driver(path: Path):
        """The driver's functions in the library ``path`` (``ctypes``), or None where it cannot be loaded."""
        try:
            lib = ctypes.CDLL(str(path))
        except OSError:
            return None
        integer, address = ctypes.c_longlong, ctypes.c_void_p
        lib.mechatron_continue.restype = integer
        lib.mechatron_continue.argtypes = (integer,) * 3 + (address,) * 14
        lib.mechatron_analyse_rows.restype = None
        lib.mechatron_analyse_rows.argtypes = (integer, address, integer) + (address,) * 6
        lib.mechatron_far.restype = ctypes.c_int
        lib.mechatron_far.argtypes = [address, address]
        lib.mechatron_maps.restype = None
        lib.mechatron_maps.argtypes = [integer, address, address, address]
        return lib

    def mapped(self, function, n: int):
        """``function`` mapped over n samples, its last input (the parameters) the same for all, with its argument
        buffer and evaluation (kept per size)."""
        key = (function.name(), n)
        if key not in self._mapped:
            mapped = function.map(function.name(), "serial", n, [function.n_in() - 1], [])
            self._mapped[key] = mapped.buffer()
        return self._mapped[key]


class LoopKernel:
    """The compiled ``newton``, ``analyse`` and ``step`` of a loop solver's closures (see the module docstring) for
    one geometry: a :class:`KernelCode`, shared by every mechanism of its structure, with this mechanism's
    parameters p (:meth:`~mechatron.model.symbolic.Geometry.values`). It reports the columns of a sweep's table: of
    the frames ``points`` the position (x, y and, when ``spatial``, z; m), velocity and its size (m/s), acceleration
    and its size (m/s²); of the frames ``links`` the angle about z in (−π, π], its rate and acceleration (rad,
    rad/s, rad/s²); of the frames ``others`` x and y (m). :meth:`newton`, :meth:`analyse` and :meth:`maps` take and
    return NumPy arrays of N samples; :meth:`run` runs the driver (where :attr:`driven`) over samples into a table,
    :meth:`far` Newton's method with halved steps on one sample."""

    def __init__(self, code: KernelCode, parameters: np.ndarray) -> None:
        self.code = code
        self.parameters = np.ascontiguousarray(parameters, dtype=float)
        if self.parameters.shape != (code.size,):
            raise ValueError(f"the kernel takes {code.size} parameters, got {self.parameters.shape}")
        self.nq, self.na, self.nd, self.act, self.dep = code.nq, code.na, code.nd, code.act, code.dep
        self.names, self.others = code.names, code.others
        self._driver: Any = code._driver  # the driver's ctypes library, or None

    @property
    def driven(self) -> bool:
        """Whether the compiled driver is there (:meth:`run`)."""
        return self._driver is not None

    @property
    def _newton(self):
        """The ``newton`` function (compiled, or CasADi's virtual machine)."""
        return self.code._newton

    @property
    def _analyse(self):
        """The ``analyse`` function (compiled, or CasADi's virtual machine)."""
        return self.code._analyse

    def outputs(self) -> int:
        """The number of ``analyse``'s outputs per sample: q̇, q̈, max |J_d⁻¹| and the frame columns."""
        return 2 * self.nq + 1 + len(self.names)

    def run(self, arrays: dict[str, np.ndarray]) -> DriverRun:
        """The driver over the samples of ``arrays`` (see :class:`DriverRun`)."""
        return DriverRun(self, arrays)

    def far(self, q: np.ndarray) -> bool:
        """Newton's method with halved steps on the dependent coordinates of q (nq,, solved in place: the last
        iterate), as :meth:`~mechatron.kinematics.loops.LoopSolver.newton` with polish: up to
        :data:`FIRST_STEPS` steps, each halved while it does not lower max |Φ| (to 1/1024), the polishing step once
        below :data:`~mechatron.kinematics.loops.TOLERANCE`; whether it converged. Needs the driver."""
        if q.shape != (self.nq,) or q.dtype != np.float64 or not q.flags.c_contiguous:
            raise ValueError(f"the kernel's q: {q.dtype} {q.shape}, not ({self.nq},) C-ordered")
        return bool(self._driver.mechatron_far(q.ctypes.data, self.parameters.ctypes.data))

    def maps(self, Q: np.ndarray) -> np.ndarray:
        """The velocity maps S_d = −J_d⁻¹ J_a (N, n_dep, n_act) at the assembled configurations Q (N, nq): by the
        driver's ``step`` at each q (no Newton step taken), else ``newton`` of CasADi's virtual machine."""
        Q = np.ascontiguousarray(Q, dtype=float)
        out = np.empty((len(Q), self.na, self.nd))
        if self._driver is not None:
            self._driver.mechatron_maps(len(Q), Q.ctypes.data, self.parameters.ctypes.data, out.ctypes.data)
        else:
            out[:] = self._evaluate(self._newton, Q)[:, self.nq + 1:].reshape(len(Q), self.na, self.nd)
        return out.transpose(0, 2, 1)  # vec() is column-major

    def _evaluate(self, function, *arrays: np.ndarray) -> np.ndarray:
        """``function`` at every row of the (N, k) ``arrays`` and these parameters: its outputs (N, m), in chunks of
        :data:`CHUNK`. The arrays are handed over without copies: a C-ordered (n, k) block is CasADi's column-major
        (k, n) matrix."""
        arrays = tuple(np.ascontiguousarray(x, dtype=float) for x in arrays)
        n = len(arrays[0])
        out = np.empty((n, function.size1_out(0)))
        for start in range(0, n, CHUNK):
            stop = min(start + CHUNK, n)
            buffer, evaluate = self.code.mapped(function, stop - start)
            # numpy's stubs give an array the buffer protocol (__buffer__) from Python 3.12 only
            for i, x in enumerate(arrays):
                buffer.set_arg(i, memoryview(x[start:stop]))  # type: ignore[arg-type]
            buffer.set_arg(len(arrays), memoryview(self.parameters))  # type: ignore[arg-type]
            buffer.set_res(0, memoryview(out[start:stop]))  # type: ignore[arg-type]
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


class DriverRun:
    """The compiled driver of a :class:`LoopKernel` over the N samples of ``arrays``, checked once (the C code
    trusts their shapes) and their addresses taken once: the inputs ``U``, rates ``R`` and accelerations ``A``
    (N, n_act), ``same`` and ``valid`` (N, uint8: the input step equals the previous one; the input is in range),
    ``begin`` (nq: where Newton's method starts without a solution before), ``reach`` (n_act: the longest input
    steps guessed along the velocity maps, m or rad), ``history`` (4, nq: the last solutions, oldest first),
    ``state`` (2, int64: how many, whether ``maps`` (n_dep · n_act) are the last one's), ``table`` (rows, N),
    ``motion`` (3, N, nq: q, q̇, q̈ of every sample) and ``rows`` (nq + :meth:`LoopKernel.outputs`, int64: the table
    row of each q_i and each output, −1 for none); floats are float64; all C-ordered. The kernel's parameters go
    with them."""

    ORDER = ("U", "R", "A", "same", "valid", "begin", "reach", "history", "state", "maps", "table", "motion", "rows")

    def __init__(self, kernel: LoopKernel, arrays: dict[str, np.ndarray]) -> None:
        n, nq, na, nd = len(arrays["U"]), kernel.nq, kernel.na, kernel.nd
        shapes = {"U": (n, na), "R": (n, na), "A": (n, na), "same": (n,), "valid": (n,), "begin": (nq,),
                  "reach": (na,), "history": (4, nq), "state": (2,), "maps": (nd * na,),
                  "table": (arrays["table"].shape[0], n), "motion": (3, n, nq), "rows": (nq + kernel.outputs(),)}
        types = {"same": np.uint8, "valid": np.uint8, "state": np.int64, "rows": np.int64}
        for key, shape in shapes.items():
            x = arrays[key]
            if x.shape != shape or x.dtype != types.get(key, np.float64) or not x.flags.c_contiguous:
                raise ValueError(f"the driver's {key}: {x.dtype} {x.shape}, not {shape} C-ordered")
        if not arrays["rows"].max(initial=-1) < arrays["table"].shape[0]:
            raise ValueError("the driver's rows reach beyond its table")
        self.kernel, self.arrays, self.n = kernel, arrays, n
        self.addresses = [arrays[key].ctypes.data for key in self.ORDER] + [kernel.parameters.ctypes.data]

    def continuation(self, start: int, stop: int) -> int:
        """The driver's continuation over the samples ``start`` … ``stop − 1`` (see :data:`DRIVER`): positions,
        their analysis into the table and ``motion``; returns the first sample not solved (``stop`` when all
        were)."""
        if not 0 <= start <= stop <= self.n:
            raise ValueError(f"samples {start} … {stop} of {self.n}")
        return self.kernel._driver.mechatron_continue(start, stop, self.n, *self.addresses)

    def analyse_rows(self, index: np.ndarray) -> None:
        """``analyse`` of the samples ``index`` at their coordinates in ``motion[0]``, written into the table and
        ``motion``."""
        index = np.ascontiguousarray(index, dtype=np.int64)
        if len(index) and not (index.min() >= 0 and index.max() < self.n):
            raise ValueError("samples out of range")
        x = self.addresses
        self.kernel._driver.mechatron_analyse_rows(len(index), index.ctypes.data, self.n, x[1], x[2], x[10], x[11],
                                                   x[12], x[13])


#: The compiled code of the structures met in this process, by signature (:func:`loop_kernel`), the most recent
#: last; at most :data:`KEPT` of them.
_CODES: dict[tuple, KernelCode | None] = {}
#: The geometries met per structure that has no code yet (their parameters' bytes).
_MET: dict[tuple, set[bytes]] = {}
KEPT = 32


def loop_kernel(solver: LoopSolver, points: list[str], links: list[str], others: list[str], spatial: bool,
                build: bool = True) -> LoopKernel | None:
    """The :class:`LoopKernel` of ``solver``'s mechanism and these frames: its structure's :class:`KernelCode`
    (compiled once per process and structure, the library kept on disk by its source's hash) with the mechanism's
    parameters, kept in the mechanism's cache; None where the joints or closures have no symbolic form or CasADi is
    missing. With ``build`` False the code is built only once a second geometry of the structure comes (a design
    study, an optimiser), else None is returned while it has none."""
    mech = solver.mech
    key = ("loop_kernel", tuple(points), tuple(links), tuple(others), spatial)
    kept: dict[Hashable, LoopKernel | None] = mech.cached("loop_kernels", dict)
    if key in kept:
        return kept[key]
    try:
        from ..model.symbolic import Geometry

        names = list(dict.fromkeys([*solver.system.frame_names, *points, *links, *others]))
        geometry = Geometry(mech.model, [mech.frame_id(n) for n in names], solver.system)
    except (Unsupported, ImportError):
        kept[key] = None
        return None
    signature = (key, tuple(solver.act), tuple(names), geometry.signature, settings())
    parameters = geometry.values(mech.model, solver.system)
    if signature not in _CODES:
        met = _MET.setdefault(signature, set())
        met.add(parameters.tobytes())
        while len(_MET) > 4 * KEPT:
            del _MET[next(iter(_MET))]
        if not build and len(met) < 2:
            return None
        try:
            _CODES[signature] = KernelCode(solver, geometry, points, links, others, spatial)
        except (Unsupported, ImportError):
            _CODES[signature] = None
        _MET.pop(signature, None)
        while len(_CODES) > KEPT:
            del _CODES[next(iter(_CODES))]
    code = _CODES[signature]
    kept[key] = None if code is None else LoopKernel(code, parameters)
    return kept[key]


def kept_kernel(solver: LoopSolver, points: list[str], links: list[str], others: list[str], spatial: bool
                ) -> LoopKernel | None:
    """The kernel of :func:`loop_kernel` if the mechanism already has it (a sweep built it), else None."""
    key = ("loop_kernel", tuple(points), tuple(links), tuple(others), spatial)
    kept: dict[Hashable, LoopKernel | None] = solver.mech.cached("loop_kernels", dict)
    return kept.get(key)
