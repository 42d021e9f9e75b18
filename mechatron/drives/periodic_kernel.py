r"""The periodic steady state of a chain of two-state affine maps in machine code: one pass to compose the cycle's map,
its fixed point, one pass down the intervals — a few floating-point operations an interval, no Python per interval.

The maps θ ↦ E_k θ + g_k of the N intervals of a cycle (:func:`mechatron.drives.thermal.interval_maps`) compose to
the cycle's map θ ↦ M θ + G (M ← E_k M, G ← E_k G + g_k, k = 0 … N − 1); its fixed point θ₀ = (1 − M)⁻¹ G is the
state at the cycle's start, and θ_k+1 = E_k θ_k + g_k the state at the start of every later interval. NaN (the whole
row) where M has an eigenvalue of modulus ≥ 1 or the fixed point is not finite: no steady state (thermal runaway),
as :func:`mechatron.drives.thermal.tree_states`, the NumPy form of the same fixed point (a balanced tree of pairwise
compositions), which this equals to rounding and which runs where no C compiler is at hand (the kernel is compiled
once, :func:`mechatron.io.native.shared_library`).
"""

from __future__ import annotations

import ctypes

import numpy as np
from numpy.typing import NDArray

from ..io.native import settings, shared_library

SOURCE = r"""
#include <math.h>

/* The periodic states (w, c) at the start of each of the n intervals of each of the rows: the six arrays of the
   maps (E11, E12, E21, E22, g1, g2), each rows x n, row-major; w and c the same shape. */
void mechatron_periodic(long long rows, long long n, const double *e11, const double *e12, const double *e21,
                        const double *e22, const double *g1, const double *g2, double *w, double *c)
{
    for (long long r = 0; r < rows; ++r) {
        const long long o = r * n;
        double m11 = 1.0, m12 = 0.0, m21 = 0.0, m22 = 1.0, h1 = 0.0, h2 = 0.0;
        for (long long k = o; k < o + n; ++k) {  /* M <- E_k M, G <- E_k G + g_k */
            const double a11 = e11[k] * m11 + e12[k] * m21, a12 = e11[k] * m12 + e12[k] * m22;
            const double a21 = e21[k] * m11 + e22[k] * m21, a22 = e21[k] * m12 + e22[k] * m22;
            const double b1 = e11[k] * h1 + e12[k] * h2 + g1[k], b2 = e21[k] * h1 + e22[k] * h2 + g2[k];
            m11 = a11; m12 = a12; m21 = a21; m22 = a22; h1 = b1; h2 = b2;
        }
        const double i11 = 1.0 - m11, i22 = 1.0 - m22, det = i11 * i22 - m12 * m21;
        double x1 = (i22 * h1 + m12 * h2) / det, x2 = (i11 * h2 + m21 * h1) / det;
        const double tr = m11 + m22, dm = m11 * m22 - m12 * m21, disc = tr * tr / 4 - dm;
        const double radius = disc >= 0 ? fabs(tr) / 2 + sqrt(disc) : sqrt(fabs(dm));
        if (!(radius < 1.0) || !isfinite(x1) || !isfinite(x2)) {
            for (long long k = o; k < o + n; ++k) { w[k] = NAN; c[k] = NAN; }
            continue;
        }
        for (long long k = o; k < o + n; ++k) {
            w[k] = x1; c[k] = x2;
            const double y1 = e11[k] * x1 + e12[k] * x2 + g1[k], y2 = e21[k] * x1 + e22[k] * x2 + g2[k];
            x1 = y1; x2 = y2;
        }
    }
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
                function.restype = None
                function.argtypes = [ctypes.c_longlong] * 2 + [ctypes.c_void_p] * 8
            except OSError:
                function = None
        _LOADED[key] = function
    return _LOADED[key]


def available() -> bool:
    """Whether the compiled kernel runs here."""
    return _kernel() is not None


def native_states(maps: tuple[NDArray[np.float64], ...]
                  ) -> tuple[NDArray[np.float64], NDArray[np.float64]] | None:
    """The periodic states (θ_w, θ_h), each (..., N), of the six map arrays ``maps`` (they broadcast to (..., N)),
    by the compiled kernel; None where it is not available."""
    function = _kernel()
    if function is None:
        return None
    arrays = [np.ascontiguousarray(x, dtype=np.float64) for x in np.broadcast_arrays(*maps)]
    shape = arrays[0].shape
    n = shape[-1] if shape else 1
    rows = int(np.prod(shape[:-1], dtype=np.int64)) if len(shape) > 1 else 1
    w, c = np.empty(shape), np.empty(shape)
    if rows and n:
        function(rows, n, *(x.ctypes.data for x in arrays), w.ctypes.data, c.ctypes.data)
    return w, c
