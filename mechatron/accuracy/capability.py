r"""Process capability of the Monte Carlo of a tolerance study: performance indices, parts out and their intervals.

Against a limit L (m) on the positioning error, from the n samples of a pose (mean μ̂, standard deviation σ̂ with
n − 1 in the denominator), per axis of Δr with the two-sided specification ±L and of |Δr| with the one-sided upper
specification L [ISO 22514-2, the process performance indices]:

- Pp = 2L / (6σ̂) (axes only: |Δr| has no lower limit);
- Ppk = min(L − μ̂, μ̂ + L) / (3σ̂) = (L − |μ̂|)/(3σ̂) per axis, Ppk = (L − μ̂)/(3σ̂) of |Δr|;
- PPM = 10⁶ · x/n, x the samples out (|Δ| > L per axis, |Δr| > L), counted chunk by chunk.

Their 95 % intervals (``confidence``), with z = Φ⁻¹(1 − α/2), α = 1 − confidence:

- Pp: exact for normal samples, (n − 1)σ̂²/σ² ~ χ²(n − 1): Pp̂ · √(χ²_{α/2}(n − 1)/(n − 1)) … Pp̂ ·
  √(χ²_{1−α/2}(n − 1)/(n − 1));
- Ppk: Bissell's approximation [Bissell, 1990], Ppk̂ ± z √(1/(9n) + Ppk̂²/(2(n − 1))) for normal samples, here
  in the general form of the same delta method, with the skewness g₁ = m₃/σ̂³ and kurtosis g₂ = m₄/σ̂⁴ of the
  samples (streamed): Var(Ppk̂) ≈ 1/(9n) + Ppk̂² (g₂ − 1)/(4(n − 1)) + s Ppk̂ g₁/(3n), s = sign μ̂ per axis and
  1 for |Δr| (from Var μ̂ = σ²/n, Var σ̂ ≈ σ²(g₂ − 1)/(4n), Cov(μ̂, σ̂) ≈ g₁σ²/(2n)); for normal samples (g₁ = 0,
  g₂ = 3) it is Bissell's. The general form is ours: |Δr| is never normal (one axis: a folded normal), and
  Bissell's interval of its Ppk covered the true value 33 times in 40 (a linear case, 2,000 samples each), the
  general one 39 times in 40 (377 in 400);
- PPM: the exact binomial interval of Clopper and Pearson [Clopper, 1934]: B⁻¹(α/2; x, n − x + 1) …
  B⁻¹(1 − α/2; x + 1, n − x) (0 for x = 0, 1 for x = n), B the beta distribution, times 10⁶.

The indices are normal-theory numbers: for a normal axis error Ppk fixes the fraction out
(Φ(−3 Ppk) on the nearer side); |Δr| is not normal (a folded normal for one axis, a Rayleigh-like law for several),
so its Ppk is a summary of mean and spread only, and the parts out are its PPM, counted, not inferred.

The relative standard error of the estimates, which ``target_error`` bounds (:func:`next_count`):

- of σ̂, from the streamed fourth moment (the delta method on Var(σ̂²) = (μ₄ − σ⁴ (n − 3)/(n − 1))/n):
  √((m₄/σ̂⁴ − (n − 3)/(n − 1))/n) / 2, which is 1/√(2(n − 1)) for normal samples; the largest over the axes with a
  spread and |Δr|;
- of the PPM of |Δr| (a binomial proportion p = x/n): √((1 − p)/(n p)); infinite while no sample is out.

How the sample count follows a target is ours: the first chunk is half the count a normal σ̂ needs,
1 + 1/(2E²) (for ``ppm``: half of 1/E², the count for p = ½), at least :data:`FIRST`; then each next chunk brings
the count to n (e/E)², e the error reached (which falls as 1/√n), at least n/50 more, at most a chunk of the
Monte Carlo; while no sample is out the count doubles. It stops at the first chunk whose error is at most E, or at
the cap.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError

Floats = NDArray[np.float64]

__all__ = ["AXES", "TARGETS", "CONFIDENCE", "pp", "pp_interval", "ppk_interval", "ppm_interval", "sigma_error",
           "ppm_error", "capability_rows", "next_count"]

#: The quantities of a pose's capability: the three axes (two-sided ±L) and |Δr| (one-sided, ≤ L).
AXES = ("dx", "dy", "dz", "dr")
#: What ``target_error`` bounds: the relative standard error of σ̂ or of the PPM of |Δr|.
TARGETS = ("sigma", "ppm")
#: The confidence of the intervals.
CONFIDENCE = 0.95
#: The smallest first chunk under a target error, and the largest target error accepted.
FIRST, LARGEST_TARGET = 64, 0.5
#: A quantity whose σ̂ is below this fraction of the largest one has no spread (Δz of a planar arm): it is left out of
#: the error of σ̂.
NO_SPREAD = 1e-9


def pp(limit: float, std: float) -> float:
    """Pp = 2L/(6σ) (L the limit, σ the standard deviation, m); ``inf`` for σ = 0."""
    return 2 * limit / (6 * std) if std > 0 else math.inf


def pp_interval(value: float, n: int, confidence: float = CONFIDENCE) -> tuple[float, float]:
    """The exact interval of Pp for normal samples, Pp̂ √(χ²_{α/2}(n − 1)/(n − 1)) … Pp̂ √(χ²_{1−α/2}(n − 1)/(n − 1))."""
    from scipy.stats import chi2

    alpha = 1 - confidence
    low, high = chi2.ppf([alpha / 2, 1 - alpha / 2], n - 1) / (n - 1)
    return value * math.sqrt(low), value * math.sqrt(high)


def ppk_interval(value: float, n: int, confidence: float = CONFIDENCE, skewness: float = 0.0,
                 kurtosis: float = 3.0, side: float = 1.0) -> tuple[float, float]:
    """The interval of Ppk (two- or one-sided), Ppk̂ ± z √(1/(9n) + Ppk̂² (g₂ − 1)/(4(n − 1)) + s Ppk̂ g₁/(3n)) with
    the samples' skewness g₁ and kurtosis g₂ and s the sign of the mean (see the module); with the defaults
    (normal samples) Bissell's, Ppk̂ ± z √(1/(9n) + Ppk̂²/(2(n − 1))) [Bissell, 1990]."""
    from scipy.stats import norm

    if not math.isfinite(value):
        return value, value
    variance = 1 / (9 * n) + value**2 * (kurtosis - 1) / (4 * (n - 1)) + side * value * skewness / (3 * n)
    half = float(norm.ppf(1 - (1 - confidence) / 2)) * math.sqrt(max(variance, 0.0))
    return value - half, value + half


def ppm_interval(out: int, n: int, confidence: float = CONFIDENCE) -> tuple[float, float]:
    """The Clopper–Pearson interval (parts per million) of the fraction out from ``out`` of ``n`` samples
    [Clopper, 1934]."""
    from scipy.stats import beta

    alpha = 1 - confidence
    low = float(beta.ppf(alpha / 2, out, n - out + 1)) if out > 0 else 0.0
    high = float(beta.ppf(1 - alpha / 2, out + 1, n - out)) if out < n else 1.0
    return 1e6 * low, 1e6 * high


def sigma_error(n: int, m2: Floats, m4: Floats) -> float:
    """The largest relative standard error of σ̂ over the quantities with a spread, √((g − (n − 3)/(n − 1))/n)/2 with
    g = m₄/m₂² (m₂, m₄ the central moments, divided by n); ``inf`` below 4 samples."""
    m2, m4 = np.asarray(m2, dtype=float), np.asarray(m4, dtype=float)
    spread = m2 > NO_SPREAD**2 * max(float(m2.max(initial=0.0)), 1e-300)
    if n < 4 or not spread.any():
        return math.inf
    g = m4[spread] / m2[spread] ** 2
    return float(np.max(np.sqrt(np.maximum(g - (n - 3) / (n - 1), 0.0) / n) / 2))


def ppm_error(out: int, n: int) -> float:
    """The relative standard error √((1 − p)/(n p)) of a fraction out p = out/n; ``inf`` with none out."""
    if out <= 0 or n <= 0:
        return math.inf
    p = out / n
    return math.sqrt((1 - p) / (n * p))


def capability_rows(limit: float, n: int, mean: Floats, std: Floats, out: NDArray[np.int64],
                    skewness: Floats | None = None, kurtosis: Floats | None = None,
                    confidence: float = CONFIDENCE) -> list[dict]:
    """One row per quantity of :data:`AXES` of a pose: ``quantity``, ``spec`` (``±L`` or ``≤ L``), ``mean``,
    ``std`` (m), ``pp`` (NaN for |Δr|), ``ppk``, their ``_low`` and ``_high`` bounds, ``ppm`` with ``ppm_low`` and
    ``ppm_high`` — from the samples' mean and standard deviation (m, one per quantity), their skewness and kurtosis
    (default normal: 0 and 3), the counts ``out`` of samples beyond the limit (m) and the sample count n."""
    rows = []
    skewness = np.zeros(len(AXES)) if skewness is None else skewness
    kurtosis = np.full(len(AXES), 3.0) if kurtosis is None else kurtosis
    for quantity, mu, sigma, x, g1, g2 in zip(AXES, mean, std, out, skewness, kurtosis):
        two_sided = quantity != "dr"
        index = pp(limit, sigma) if two_sided else math.nan
        k = (limit - abs(mu) if two_sided else limit - mu) / (3 * sigma) if sigma > 0 else \
            (math.inf if (abs(mu) if two_sided else mu) < limit else -math.inf)
        pp_low, pp_high = pp_interval(index, n, confidence) if two_sided else (math.nan, math.nan)
        side = (1.0 if mu >= 0 else -1.0) if two_sided else 1.0
        ppk_low, ppk_high = ppk_interval(k, n, confidence, float(g1), float(g2), side)
        ppm_low, ppm_high = ppm_interval(int(x), n, confidence)
        rows.append({"quantity": quantity, "spec": "±L" if two_sided else "≤ L", "mean": float(mu),
                     "std": float(sigma), "pp": index, "pp_low": pp_low, "pp_high": pp_high, "ppk": k,
                     "ppk_low": ppk_low, "ppk_high": ppk_high, "ppm": 1e6 * int(x) / n, "ppm_low": ppm_low,
                     "ppm_high": ppm_high})
    return rows


def check_target(target_error: float | None, target: str, limit: float | None) -> float | None:
    """``target_error`` checked (None, or in (0, :data:`LARGEST_TARGET`]) with ``target`` of :data:`TARGETS`;
    ``ppm`` needs a limit."""
    from ..io.budget import option
    from ..io.values import number

    name = option("target_error")
    target_error = number(name, target_error, positive=True, maximum=LARGEST_TARGET, allow_none=True)
    if target not in TARGETS:
        raise InputError(f"{option('target')} must be one of {', '.join(TARGETS)}, got {target!r}")
    if target_error is not None and target == "ppm" and limit is None:
        raise InputError(f"{name} of the ppm needs a limit of |Δr| (--limit-mm, or limit in m)")
    return target_error


def first_count(target_error: float, target: str) -> int:
    """The first chunk under a target error E: half of 1 + 1/(2E²) (σ̂; ``ppm``: half of 1/E²), at least
    :data:`FIRST`."""
    need = 1 + 1 / (2 * target_error**2) if target == "sigma" else 1 / target_error**2
    return max(FIRST, math.ceil(need / 2))


def next_count(n: int, error: float, target_error: float, target: str, chunk: int, cap: int) -> int:
    """The samples to draw next (see the module): toward n (e/E)², at least n/50 and :data:`FIRST`, at most
    ``chunk`` and what is left of ``cap``; the count doubles while the error is infinite (nothing out yet)."""
    left = cap - n
    if n == 0:
        want = first_count(target_error, target)
    elif math.isfinite(error):
        want = max(math.ceil(n * (error / target_error) ** 2) - n, math.ceil(n / 50), FIRST)
    else:
        want = max(n, FIRST)
    return max(1, min(want, chunk, left))
