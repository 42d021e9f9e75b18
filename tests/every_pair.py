"""The brute-force reference of the drive searches: every check of every motor × converter pair of a joint.

The dense evaluation (:func:`mechatron.drives.checks.evaluate`) simulates the winding of every pair with thermal data
(~0.3 ms a pair on a task of 1,115 samples: 30 s for the 100,000 pairs of a catalog three times the example one),
though a pair that fails another check fails whatever its winding does. :func:`worst_load_factors` checks every
pair by every other check (exact, the per-sample checks over every sample that can decide them) and simulates the
winding of exactly the pairs that pass all of them; so it says pass or fail for every pair as the dense evaluation
does, and gives the exact worst load factor of every pair that passes — every value the brute-force references
compare with a search (the ranking, the margins, the chosen pair, "some pair passes at this pace"), without the
thousands of windings no assertion reads.
"""

from __future__ import annotations

import numpy as np

from mechatron.drives.checks import ALL_CHECKS, PASS_TOLERANCE, PairChecks, _load_factor

#: The column of the winding's check, the one check that is a simulation.
WINDING = ALL_CHECKS.index("winding temperature rise")


def worst_load_factors(duty, motors, conv, inertia_ratio_max: float = 10.0, limits=None) -> np.ndarray:
    """The worst load factor (value/limit) of every pair, (N_m, N_c), of which ``<= 1 + PASS_TOLERANCE`` is the
    pass of the dense evaluation: exact for every pair that passes every check but the winding's (the winding
    simulated for those); for the others the largest of their other load factors, above 1 + PASS_TOLERANCE (they
    fail, and their exact worst is at least that)."""
    checks = PairChecks(duty, motors, conv, inertia_ratio_max, limits)
    m, c = (x.ravel() for x in np.indices(checks.shape))
    values, lim = checks.table(m, c, level=2, thermal=False)  # every check exact but the winding's
    values[:, WINDING] = 0.0
    others = _load_factor(values, lim).max(axis=1)
    simulate = (others <= 1 + PASS_TOLERANCE) & checks.heated[m]
    values[simulate, WINDING] = checks.winding(m[simulate], c[simulate])
    return _load_factor(values, lim).max(axis=1).reshape(checks.shape)


def passes(worst: np.ndarray) -> np.ndarray:
    """The pairs that pass every check (of :func:`worst_load_factors`'s worst load factors)."""
    return worst <= 1 + PASS_TOLERANCE
