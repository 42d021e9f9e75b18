r"""Monte Carlo statistics in constant memory: the samples arrive in chunks and only summaries are kept.

- **Moments** (:class:`Moments`): count n, mean x̄ and co-moment matrix M = Σ (x − x̄)(x − x̄)ᵀ of vectors,
  merged chunk by chunk with Chan's pairwise update (Chan, Golub & LeVeque 1979): for a chunk b of m samples with
  mean x̄_b and co-moment M_b (two-pass within the chunk), δ = x̄_b − x̄, n' = n + m,
  x̄' = x̄ + δ m/n', M' = M + M_b + δ δᵀ n m/n'. Variances are diag(M)/(n − ddof); the result equals the
  all-in-memory two-pass value up to rounding (relative 1e-13 for the sizes used here).
- **Central moments to the fourth** (:class:`CentralMoments`): per value n, x̄ and the sums of powers
  M_p = Σ (x − x̄)^p, p = 2, 3, 4, merged with the pairwise update of [Pebay, 2008] (its formulas for p ≤ 4; M₂ is
  Chan's above): for a chunk b (n_b, x̄_b, M_p,b, two-pass within the chunk) joined to a (n_a, …),
  δ = x̄_b − x̄_a, n = n_a + n_b, M₂ = M₂a + M₂b + δ² n_a n_b/n,
  M₃ = M₃a + M₃b + δ³ n_a n_b (n_a − n_b)/n² + 3δ (n_a M₂b − n_b M₂a)/n,
  M₄ = M₄a + M₄b + δ⁴ n_a n_b (n_a² − n_a n_b + n_b²)/n³ + 6δ² (n_a² M₂b + n_b² M₂a)/n² + 4δ (n_a M₃b − n_b M₃a)/n.
  The fourth moment gives the standard error of a standard deviation (:mod:`~mechatron.accuracy.capability`).
- **Variance shares** (:func:`variance_shares`): the least-squares fit Δr ≈ β e of the centred response on the
  centred errors by its normal equations C_ee β = C_eΔ, C the co-moments accumulated above (a (n_e, n_e) solve,
  scaled by the errors' spreads; no sample kept). Each source's share is Σ_axes (β_i s_i)² / Σ_axes var Δr with
  s_i the population spread of error i.
- **Quantiles** (:class:`Quantiles`): exact (``numpy.quantile``, linear interpolation) while the |Δr| samples of a
  pose fit :data:`EXACT_SAMPLES` values (8 MB). Past that, a fixed-bin histogram of :data:`BINS` bins over
  [0, top], top = :data:`HEADROOM` × the largest sample when the store overflows (the samples stored and the chunk
  that does not fit; all are binned), plus one overflow count. A quantile is the midpoint of the bin that holds
  its order statistics: its error is at most half a bin width, top / (2 · :data:`BINS`) (:attr:`Quantiles.bound`).
  An order statistic in the overflow (above top; for a normal |Δr| with 10⁶ samples, beyond ~24 σ) is given as the
  largest sample, an upper bound.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

Floats = NDArray[np.float64]

#: Samples of |Δr| per pose up to which the quantiles are exact (kept in memory: 8 bytes each).
EXACT_SAMPLES = 1_000_000
#: Bins of the histogram past :data:`EXACT_SAMPLES` (8 bytes each), and its range over the largest exact sample.
BINS, HEADROOM = 2**20, 4.0


#: Rows per block of the co-moment product Σ cᵀc: every block's product stays below OpenBLAS's threading threshold
#: (m·n·k < 262,144), so it runs on one thread; one 32,768-row product took 3 ms to 2.5 s on a busy two-core machine
#: (threads waiting for each other), the blocks 16–30 ms.
BLOCK = 128


def _gram(x: Floats) -> Floats:
    """xᵀ x (width, width) summed over blocks of :data:`BLOCK` rows (the last padded with zeros)."""
    m, width = x.shape
    if m % BLOCK:
        x = np.concatenate([x, np.zeros((BLOCK - m % BLOCK, width))])
    blocks = x.reshape(-1, BLOCK, width)
    return np.matmul(blocks.transpose(0, 2, 1), blocks).sum(axis=0)


class Moments:
    """Count, mean and co-moment matrix of vectors of ``width`` values, merged chunk by chunk (Chan's update)."""

    def __init__(self, width: int) -> None:
        self.n = 0
        self.mean = np.zeros(width)
        self.comoment = np.zeros((width, width))

    def add(self, x: Floats) -> None:
        """Merge the samples ``x`` (m, width)."""
        m = len(x)
        if not m:
            return
        mean = x.mean(axis=0)
        centred = x - mean
        n = self.n + m
        delta = mean - self.mean
        self.comoment += _gram(centred) + np.outer(delta, delta) * (self.n * m / n)
        self.mean = self.mean + delta * (m / n)
        self.n = n

    def variance(self, ddof: int = 1) -> Floats:
        """The variance of every value, Σ (x − x̄)² / (n − ddof)."""
        return np.diag(self.comoment) / max(self.n - ddof, 1)


class CentralMoments:
    """Count, mean and the central sums of powers M₂, M₃, M₄ of each of ``width`` values, merged chunk by chunk
    [Pebay, 2008] (see the module)."""

    def __init__(self, width: int) -> None:
        self.n = 0
        self.mean = np.zeros(width)
        self.m2, self.m3, self.m4 = np.zeros(width), np.zeros(width), np.zeros(width)

    def add(self, x: Floats) -> None:
        """Merge the samples ``x`` (m, width)."""
        nb = len(x)
        if not nb:
            return
        mean = x.mean(axis=0)
        c = x - mean
        c2 = c * c
        m2, m3, m4 = c2.sum(axis=0), (c2 * c).sum(axis=0), (c2 * c2).sum(axis=0)
        na = self.n
        n = na + nb
        d = mean - self.mean
        self.m4 = (self.m4 + m4 + d**4 * na * nb * (na * na - na * nb + nb * nb) / n**3
                   + 6 * d**2 * (na * na * m2 + nb * nb * self.m2) / n**2 + 4 * d * (na * m3 - nb * self.m3) / n)
        self.m3 = self.m3 + m3 + d**3 * na * nb * (na - nb) / n**2 + 3 * d * (na * m2 - nb * self.m2) / n
        self.m2 = self.m2 + m2 + d**2 * na * nb / n
        self.mean = self.mean + d * (nb / n)
        self.n = n

    def std(self, ddof: int = 1) -> Floats:
        """The standard deviation of every value, √(M₂/(n − ddof))."""
        return np.sqrt(self.m2 / max(self.n - ddof, 1))


def variance_shares(moments: Moments, n_errors: int, axes: int = 3) -> Floats:
    """Each error's share (%) of the total variance of Δr from the co-moments of [e (n_errors), Δr (axes), …]:
    β from the normal equations C_ee β = C_eΔ (scaled by the errors' spreads, least squares where singular),
    share_i = Σ_axes (β_i s_i)² / Σ_axes var Δr with s_i² = C_ii / n (population variances)."""
    C = moments.comoment
    ee, ed = C[:n_errors, :n_errors], C[:n_errors, n_errors:n_errors + axes]
    scale = np.sqrt(np.diag(ee))
    scale = np.where(scale > 0, scale, 1.0)
    y, *_ = np.linalg.lstsq(ee / np.outer(scale, scale), ed / scale[:, None], rcond=None)
    beta = y / scale[:, None]
    spread = np.sqrt(np.diag(ee) / moments.n)
    part = ((beta * spread[:, None]) ** 2).sum(axis=1)
    total = np.trace(C[n_errors:n_errors + axes, n_errors:n_errors + axes]) / moments.n
    return 100 * part / max(total, 1e-300)


class Quantiles:
    """Quantiles of non-negative samples (|Δr|, m) streamed in chunks: exact up to ``exact`` samples, else from a
    fixed-bin histogram (see the module)."""

    def __init__(self, total: int, exact: int | None = None, bins: int | None = None) -> None:
        exact = EXACT_SAMPLES if exact is None else exact
        self.bins = BINS if bins is None else bins
        self.values: Floats | None = np.empty(min(total, exact))
        self.n = 0
        self.largest = -np.inf
        self.counts: NDArray[np.int64] | None = None
        self.top = 0.0

    @property
    def bound(self) -> float:
        """The largest error of a quantile (m): 0 when exact, else half a bin width."""
        return 0.0 if self.counts is None else self.top / self.bins / 2

    def add(self, r: Floats) -> None:
        """Add the samples ``r`` (m,)."""
        if not len(r):
            return
        self.largest = max(self.largest, float(r.max()))
        if self.counts is None and self.n + len(r) <= len(self.values):
            self.values[self.n:self.n + len(r)] = r
        else:
            if self.counts is None:  # the exact store is full: bin it and every sample after it
                kept = self.values[: self.n]
                self.top = HEADROOM * max(float(kept.max(initial=0.0)), float(r.max()), 1e-300)
                self.counts = np.zeros(self.bins + 1, dtype=np.int64)
                self.values = None
                self._bin(kept)
            self._bin(r)
        self.n += len(r)

    def _bin(self, r: Floats) -> None:
        index = np.minimum(r * (self.bins / self.top), self.bins).astype(np.int64)  # the overflow is bin `bins`
        self.counts += np.bincount(index, minlength=self.bins + 1)

    def quantiles(self, levels: Floats) -> Floats:
        """The quantiles at ``levels`` (numpy's linear definition: between the order statistics ⌊h⌋ and ⌈h⌉,
        h = (n − 1) p), exact or within :attr:`bound`."""
        levels = np.asarray(levels, dtype=float)
        if self.counts is None:
            return np.quantile(self.values[: self.n], levels)
        cumulative = np.cumsum(self.counts)
        h = (self.n - 1) * levels
        out = []
        for low, high, t in zip(np.floor(h), np.ceil(h), h - np.floor(h)):
            a, b = (self._order_statistic(cumulative, int(rank)) for rank in (low, high))
            out.append(a + t * (b - a))
        return np.array(out)

    def _order_statistic(self, cumulative: NDArray[np.int64], rank: int) -> float:
        """The midpoint of the bin of the order statistic ``rank`` (from 0), the largest sample in the overflow."""
        b = int(np.searchsorted(cumulative, rank + 1))
        return self.largest if b >= self.bins else min((b + 0.5) * self.top / self.bins, self.largest)
