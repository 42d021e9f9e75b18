r"""Slender round shafts, screws and rods: Euler buckling and the critical (whirling) speed by the end fixing.

A round section of diameter d has I = π d⁴/64 and A = π d²/4. Between two supports a free length L apart, with an
end fixing of effective-length factor K and first-mode eigenvalue λ (Euler's four cases):

- Euler buckling load   F_E = π² E I / (K L)²  (N);
- critical speed        ω_cr = (λ / L)² √(E I / (ρ A)) = λ² d √(E/ρ) / (4 L²)  (rad/s), the first bending mode of
  the shaft turning about its axis (its whirling speed).

=================  ======  ==========  ==================================================================
end fixing         K       λ           supports
=================  ======  ==========  ==================================================================
``fixed-free``     2       1.875104    one end clamped (two bearings or a flange), the other free
``pinned-pinned``  1       π           both ends held but free to turn (one bearing, a clevis or an eye)
``fixed-pinned``   0.7     3.926602    one end clamped, the other held
``fixed-fixed``    0.5     4.730041    both ends clamped
=================  ======  ==========  ==================================================================

``supported`` is read as ``pinned`` and the order of the two ends does not matter (``pinned-fixed`` is
``fixed-pinned``). K = 0.7 is the value the makers tabulate for the fixed–pinned case (the exact Euler value is
0.699); the screw and cylinder makers' sizing sections use these four cases ([Vendor sizing]).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError

STEEL_MODULUS = 2.1e11  # Pa
STEEL_DENSITY = 7850.0  # kg/m³

#: end fixing → (effective-length factor K, first bending-mode eigenvalue λ).
END_FIXINGS: dict[str, tuple[float, float]] = {
    "fixed-free": (2.0, 1.875104),
    "pinned-pinned": (1.0, math.pi),
    "fixed-pinned": (0.7, 3.926602),
    "fixed-fixed": (0.5, 4.730041),
}
#: The end fixing assumed where none is given: both ends pinned (K = 1), Euler's base case.
DEFAULT_FIXING = "pinned-pinned"
_WORDS = {"fixed": "fixed", "clamped": "fixed", "pinned": "pinned", "supported": "pinned", "hinged": "pinned",
          "free": "free"}
_ORDER = ("fixed", "pinned", "free")


def end_fixing(name: str) -> str:
    """The canonical name of an end fixing (a key of :data:`END_FIXINGS`): ``"supported-fixed"`` →
    ``"fixed-pinned"``. Raises :class:`~mechatron.errors.InputError` for an unknown one."""
    words = [w.strip() for w in str(name).strip().lower().replace("–", "-").replace(" ", "-").split("-") if w.strip()]
    if len(words) == 2 and all(w in _WORDS for w in words):
        canonical = "-".join(sorted((_WORDS[w] for w in words), key=_ORDER.index))
        if canonical in END_FIXINGS:
            return canonical
    raise InputError(f"unknown end fixing {name!r}; expected one of: {', '.join(END_FIXINGS)} "
                     "('supported' reads as 'pinned')")


def fixing_factors(names: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """(K, λ) of each end fixing name (an empty name or NaN: :data:`DEFAULT_FIXING`)."""
    out = [END_FIXINGS[end_fixing(n) if isinstance(n, str) and n.strip() else DEFAULT_FIXING]
           for n in np.atleast_1d(np.asarray(names, dtype=object))]
    factors = np.array(out, dtype=float).reshape(-1, 2)
    return factors[:, 0], factors[:, 1]


def second_moment(diameter: ArrayLike) -> NDArray[np.float64]:
    """I = π d⁴/64 (m⁴) of a solid round section of diameter d (m)."""
    return math.pi * np.asarray(diameter, dtype=float) ** 4 / 64


def euler_load(diameter: ArrayLike, length: ArrayLike, factor: ArrayLike = 1.0,
               modulus: float = STEEL_MODULUS) -> NDArray[np.float64]:
    """Euler's buckling load F_E = π² E I / (K L)² (N) of a solid round column of diameter d (m), free length L (m),
    effective-length factor K and Young's modulus E (Pa); arrays broadcast."""
    return math.pi**2 * modulus * second_moment(diameter) / (np.asarray(factor) * np.asarray(length)) ** 2


def critical_speed(diameter: ArrayLike, length: ArrayLike, eigenvalue: ArrayLike = math.pi,
                   modulus: float = STEEL_MODULUS, density: float = STEEL_DENSITY) -> NDArray[np.float64]:
    """The first critical (whirling) speed ω_cr = λ² d √(E/ρ) / (4 L²) (rad/s) of a solid round shaft of diameter
    d (m) between supports L (m) apart, with the end fixing's eigenvalue λ, modulus E (Pa) and density ρ (kg/m³);
    arrays broadcast."""
    d, L = np.asarray(diameter, dtype=float), np.asarray(length, dtype=float)
    return np.asarray(eigenvalue) ** 2 * d * math.sqrt(modulus / density) / (4 * L**2)
