r"""The periodic steady state of the two-node winding network in machine code: per row, one pass that makes each
interval's exact map and composes the cycle's map, its fixed point, one pass down the intervals — a few dozen
floating-point operations an interval, no Python per interval.

Per row (a motor on a cycle): the exact map θ ↦ E_k θ + g_k of each of the N intervals
(:func:`mechatron.drives.thermal.interval_maps`, the same formulas: the 2 × 2 matrix exponential from the two real
eigenvalues; the interval's squared current the mean of its two samples times the row's scale s, its speed loss
the mean of its two samples), composed to the cycle's map θ ↦ M θ + G (M ← E_k M, G ← E_k G + g_k, k = 0 … N − 1);
its fixed point θ₀ = (1 − M)⁻¹ G is the state at the cycle's start, θ_k+1 = E_k θ_k + g_k the state at the start of
every later interval, and ⟨θ_h⟩ = Σ_k h_k (θ_h,k + θ_h,k+1) / (2 T) the housing's trapezoidal time mean over the
cycle (θ_h,N = θ_h,0). NaN (the whole row) where M has an eigenvalue of modulus ≥ 1 or the fixed point is not
finite: no steady state (thermal runaway). :func:`mechatron.drives.thermal.tree_states` is the NumPy form of the
same fixed point (a balanced tree of pairwise compositions of :func:`~mechatron.drives.thermal.interval_maps`),
which this equals to rounding and which runs where no C compiler is at hand (the kernel is compiled once,
:func:`mechatron.io.native.shared_library`).
"""

from __future__ import annotations

import ctypes

import numpy as np
from numpy.typing import NDArray

from ..io.native import settings, shared_library

#: The columns of a row's parameters: R_wh, R_ha (K/W), τ_w, τ_h (s), R(T_a) (Ω), R₂₅ α (Ω/K), the scale s of I².
PARAMETERS = 7

SOURCE = r"""
#include <math.h>
#include <stdlib.h>

/* The exact map (E11, E12, E21, E22, g1, g2) of one interval of step h, squared current q and speed loss f, for the
   row's network p = (R_wh, R_ha, tau_w, tau_h, R(T_a), R25 alpha): thermal.interval_maps, operation for operation. */
static void interval_map(double h, double q, double f, const double *p, double *m)
{
    const double c_w = p[2] / p[0], c_h = p[3] / p[1];
    const double a12 = 1.0 / p[2], a21 = 1.0 / (p[0] * c_h), a22 = -a21 - 1.0 / p[3];
    const double a11 = p[5] / c_w * q - a12;
    const double b1 = q * (p[4] / c_w) + f / c_w;
    const double half = 0.5 * (a11 - a22), root = sqrt(half * half + a12 * a21);
    const double l1 = 0.5 * (a11 + a22) - root, l2 = (a11 * a22 - a12 * a21) / l1, span = -2.0 * root;
    double f1 = expm1(l1 * h);
    const double e1 = f1 + 1.0;
    f1 /= l1;
    const double x2 = l2 * h;
    double f2 = expm1(x2);
    const double e2 = f2 + 1.0;
    f2 = x2 == 0.0 ? h : f2 / l2;
    const double p11 = (a11 - l2) / span, de = (e1 - e2) / span, df = (f1 - f2) / span;
    m[0] = e2 + (e1 - e2) * p11; m[1] = de * a12; m[2] = de * a21; m[3] = e2 + de * (a22 - l2);
    m[4] = (f2 + (f1 - f2) * p11) * b1; m[5] = df * a21 * b1;
}

/* The periodic states (w, c), rows x n, at the start of each of the n intervals between the n + 1 samples t of each
   row, and the housing's time mean (rows): q and f the squared current and the speed loss at the samples, rows x
   (n + 1); p the rows' parameters, rows x 7 (the network, R(T_a), R25 alpha, the scale of q); all row-major.
   Returns 0, or 1 where no memory was to be had. */
int mechatron_periodic(long long rows, long long n, const double *t, const double *q, const double *f,
                       const double *p, double *w, double *c, double *mean)
{
    double *maps = malloc(6 * (size_t)(n > 0 ? n : 1) * sizeof(double));
    if (!maps) return 1;
    const double duration = t[n] - t[0];
    for (long long r = 0; r < rows; ++r) {
        const double *pr = p + 7 * r, *qr = q + (n + 1) * r, *fr = f + (n + 1) * r;
        const double scale = pr[6];
        double m11 = 1.0, m12 = 0.0, m21 = 0.0, m22 = 1.0, h1 = 0.0, h2 = 0.0;
        for (long long k = 0; k < n; ++k) {  /* M <- E_k M, G <- E_k G + g_k */
            double *e = maps + 6 * k;
            interval_map(t[k + 1] - t[k], 0.5 * (qr[k] + qr[k + 1]) * scale, 0.5 * (fr[k] + fr[k + 1]), pr, e);
            const double a11 = e[0] * m11 + e[1] * m21, a12 = e[0] * m12 + e[1] * m22;
            const double a21 = e[2] * m11 + e[3] * m21, a22 = e[2] * m12 + e[3] * m22;
            const double b1 = e[0] * h1 + e[1] * h2 + e[4], b2 = e[2] * h1 + e[3] * h2 + e[5];
            m11 = a11; m12 = a12; m21 = a21; m22 = a22; h1 = b1; h2 = b2;
        }
        const double i11 = 1.0 - m11, i22 = 1.0 - m22, det = i11 * i22 - m12 * m21;
        double x1 = (i22 * h1 + m12 * h2) / det, x2 = (i11 * h2 + m21 * h1) / det;
        const double tr = m11 + m22, dm = m11 * m22 - m12 * m21, disc = tr * tr / 4 - dm;
        const double radius = disc >= 0 ? fabs(tr) / 2 + sqrt(disc) : sqrt(fabs(dm));
        double *wr = w + n * r, *cr = c + n * r;
        if (!(radius < 1.0) || !isfinite(x1) || !isfinite(x2)) {
            for (long long k = 0; k < n; ++k) { wr[k] = NAN; cr[k] = NAN; }
            mean[r] = NAN;
            continue;
        }
        double sum = 0.0;
        const double first = x2;
        for (long long k = 0; k < n; ++k) {
            const double *e = maps + 6 * k;
            wr[k] = x1; cr[k] = x2;
            const double y1 = e[0] * x1 + e[1] * x2 + e[4], y2 = e[2] * x1 + e[3] * x2 + e[5];
            sum += (t[k + 1] - t[k]) * (x2 + (k + 1 < n ? y2 : first));
            x1 = y1; x2 = y2;
        }
        mean[r] = 0.5 * sum / duration;
    }
    free(maps);
    return 0;
}
"""

_LOADED: dict[tuple, object] = {}


def _kernel():
    """The compiled ``mechatron_periodic`` (``ctypes``), once per process and compile settings; None where it cannot
    be compiled or loaded."""
    key = settings()
    if key not in _LOADED:
        path = shared_library("mechatron_periodic", lambda _: SOURCE.encode())
        function = None
        if path is not None:
            try:
                function = ctypes.CDLL(str(path)).mechatron_periodic
                function.restype = ctypes.c_int
                function.argtypes = [ctypes.c_longlong] * 2 + [ctypes.c_void_p] * 7
            except OSError:
                function = None
        _LOADED[key] = function
    return _LOADED[key]


def available() -> bool:
    """Whether the compiled kernel runs here."""
    return _kernel() is not None


def native_states(t: NDArray[np.float64], current_sq: NDArray[np.float64], speed_loss: NDArray[np.float64],
                  parameters: NDArray[np.float64]
                  ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]] | None:
    """(θ_w, θ_h), each (R, N − 1), at the start of every interval of the periodic steady state, and the housing's
    time mean ⟨θ_h⟩ (R,) (K), by the compiled kernel (the module docstring): the N ≥ 2 samples ``t`` (s), the squared
    current ``current_sq`` (A²) and speed loss ``speed_loss`` (W) at the samples, (R, N) each, and the rows'
    ``parameters`` (R, :data:`PARAMETERS`). None where the kernel is not available."""
    function = _kernel()
    if function is None:
        return None
    t = np.ascontiguousarray(t, dtype=np.float64)
    q, f, p = (np.ascontiguousarray(x, dtype=np.float64) for x in (current_sq, speed_loss, parameters))
    rows, n = q.shape[0], len(t) - 1
    w, c, mean = np.empty((rows, n)), np.empty((rows, n)), np.empty(rows)
    if rows and function(rows, n, *(x.ctypes.data for x in (t, q, f, p, w, c, mean))):
        raise MemoryError("the periodic kernel found no memory for its interval maps")
    return w, c, mean
