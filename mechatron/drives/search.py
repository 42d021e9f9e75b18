r"""The search for the best motor × converter pairs of one joint, without an (N_m, N_c) array.

The pairs are screened by cheap exact bounds (:meth:`~mechatron.drives.checks.PairChecks.screen`: the checks that
need no pass over the samples, the RMS torque and mean speed from moments of the duty) and the per-sample checks are
made exact only for the pairs that can still win, in the order of the objective (:func:`first_in_order`) or of the
worst load factor (:func:`smallest_worst`, branch and bound). The fastest pace of the ``time`` objective is a
bisection over the pace (:func:`fastest_scale`, :func:`motor_passes`).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import pandas as pd

from .brakes import with_brakes
from .checks import PASS_TOLERANCE, DriveLimits, MotorArrays, PairChecks
from .converters import Converters
from .duty import JointDuty


def fastest_scale(passes: Callable[[float], bool], k_min: float = 0.02, k_max: float = 50.0,
                  tolerance: float = 1e-3) -> float:
    """The smallest time scale k ∈ [k_min, k_max] for which ``passes(k)`` (some drive passes every check with the
    task replayed k times slower), by bisection on log k to a relative ``tolerance``; the value returned is a
    tested, passing k, or inf if nothing passes even at k_max (the static load — gravity, external forces — does
    not scale, so a drive that cannot hold it fails at every k)."""
    if passes(1.0):
        if passes(k_min):
            return k_min
        low, high = k_min, 1.0
    else:
        if not passes(k_max):
            return math.inf
        low, high = 1.0, k_max
    while high / low > 1 + tolerance:
        middle = math.sqrt(low * high)
        if passes(middle):
            high = middle
        else:
            low = middle
    return high


#: Pairs evaluated at a time (a block of motors × every converter, or a slice of the ranking's order): the
#: sizing's memory does not grow with the catalogs beyond this and the per-motor and per-converter arrays.
CHUNK = 1 << 15
#: Pairs in the first slice of the ranking's order (:func:`first_in_order`; each next slice twice as many).
FIRST_SLICE = 1 << 11


def _motor_blocks(checks: PairChecks) -> list[slice]:
    """Slices of the motors, each with about :data:`CHUNK` pairs (motors × every converter)."""
    motors, converters = checks.shape
    step = max(1, CHUNK // max(1, converters))
    return [slice(start, min(start + step, motors)) for start in range(0, motors, step)]


def feasible_pairs(checks: PairChecks, m: np.ndarray, c: np.ndarray, screened: bool = False) -> np.ndarray:
    """Which pairs (m[i], c[i]) pass every check: the checks without samples first (:meth:`PairChecks.screen`;
    ``screened``: the pairs passed it already), then lower bounds of the per-sample ones, then those exact (the
    winding temperature at its bound), then the winding temperature simulated, each on the pairs the one before
    let through."""
    ok = np.ones(len(m), dtype=bool) if screened else checks.screen(m, c)
    index = np.flatnonzero(ok)
    ok[index] = checks.bounds_pass(m[index], c[index])
    index = np.flatnonzero(ok)
    exactly = getattr(checks, "passes_exactly", None)  # the winding simulated last, where the rest passes
    ok[index] = exactly(m[index], c[index]) if exactly else checks.worst(m[index], c[index]) <= 1 + PASS_TOLERANCE
    return ok


def _pairs_between(first: np.ndarray, second: np.ndarray, low: float, high: float
                   ) -> tuple[np.ndarray, np.ndarray]:
    """The pairs (m, c) with low < first[m] + second[c] ≤ high, in catalog order (m, then c)."""
    order = np.argsort(second, kind="stable")
    ordered = second[order]
    room = 1e-9 * (abs(high) + np.abs(first) + 1.0)  # the sums' rounding: the pairs are filtered exactly below
    lo = np.searchsorted(ordered, low - first - room, side="left") if math.isfinite(low) else \
        np.zeros(len(first), dtype=int)
    hi = np.searchsorted(ordered, high - first + room, side="right")
    counts = np.maximum(hi - lo, 0)
    m = np.repeat(np.arange(len(first)), counts)
    start = np.repeat(lo - (np.cumsum(counts) - counts), counts)
    c = order[start + np.arange(len(m))]
    total = first[m] + second[c]
    keep = (total > low) & (total <= high)
    m, c = m[keep], c[keep]
    flat = np.argsort(m * len(second) + c, kind="stable")
    return m[flat], c[flat]


def _threshold(first: np.ndarray, second: np.ndarray, low: float, count: int) -> float:
    """A sum s with about ``count`` pairs (m, c) with low < first[m] + second[c] ≤ s (bisection on s), or the
    largest sum when fewer remain."""
    ordered = np.sort(second)
    top = float(first.max() + ordered[-1])

    def pairs_below(s: float) -> int:
        return int(np.searchsorted(ordered, s - first, side="right").sum())

    below = 0 if not math.isfinite(low) else pairs_below(low)
    if pairs_below(top) - below <= count:
        return top
    a, b = (float(first.min() + ordered[0]) if not math.isfinite(low) else low), top
    for _ in range(60):
        middle = 0.5 * (a + b)
        found = pairs_below(middle) - below
        if found < count:
            a = middle
        else:
            b = middle
            if found <= 2 * count:
                break
    return b


def _in_order(m: np.ndarray, c: np.ndarray, primary: tuple[np.ndarray, np.ndarray],
              tie: tuple[np.ndarray, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """The pairs (m, c), given in catalog order, sorted by primary, then tie (stable: catalog order last)."""
    order = np.lexsort((tie[0][m] + tie[1][c], primary[0][m] + primary[1][c]))
    return m[order], c[order]


#: Pairs of an order's first slices kept for the next joints and sizings with the same catalogs (:class:`_Order`).
KEPT_PAIRS = 1 << 16
#: Pairs of a slice screened at first (:func:`first_in_order`; then twice as many, …): the lightest pairs that
#: pass the screening mostly pass every check, so the first feasible pair is usually among the first screened.
SCREENED_FIRST = 256
#: Orders kept (:func:`_order_of`): one per objective and kind of converter of the catalogs sized with last.
KEPT_ORDERS = 8


class _Order:
    """All motor × converter pairs in the order of the score primary[0][m] + primary[1][c], then of
    tie[0][m] + tie[1][c], then of the catalogs (m, then c), slice by slice: slice k holds the pairs whose score
    lies in the k-th interval (about :data:`FIRST_SLICE` pairs, then twice as many, … up to :data:`CHUNK`), sorted.
    The order depends on the catalogs alone, not on the duty: the first slices (up to :data:`KEPT_PAIRS` pairs) are
    kept for every joint and every design sized with these catalogs (:func:`_order_of`); later ones are made again
    when asked for, so the memory stays with a slice."""

    def __init__(self, primary: tuple[np.ndarray, np.ndarray], tie: tuple[np.ndarray, np.ndarray]):
        self.primary, self.tie = primary, tie
        self.top = float(primary[0].max() + primary[1].max())
        self._starts: list[tuple[float, int]] = [(-math.inf, FIRST_SLICE)]  # (low, size) of each slice
        self._kept: list[tuple[np.ndarray, np.ndarray]] = []
        self._pairs = 0

    def slice(self, k: int) -> tuple[np.ndarray, np.ndarray] | None:
        """The k-th slice (m, c), ``None`` past the last; slice k − 1 must have been asked for before."""
        if k < len(self._kept):
            return self._kept[k]
        low, size = self._starts[k]
        if not low < self.top:
            return None
        high = _threshold(*self.primary, low, size)
        pairs = _in_order(*_pairs_between(*self.primary, low, high), self.primary, self.tie)
        if k == len(self._starts) - 1:
            self._starts.append((high, min(2 * size, CHUNK)))
        if k == len(self._kept) and self._pairs + len(pairs[0]) <= KEPT_PAIRS:
            self._kept.append(pairs)
            self._pairs += len(pairs[0])
        return pairs


_ORDERS: dict[tuple, _Order] = {}


def _order_of(primary: tuple[np.ndarray, np.ndarray], tie: tuple[np.ndarray, np.ndarray]) -> _Order:
    """The :class:`_Order` of these scores, made once for the last :data:`KEPT_ORDERS` different ones (the scores
    are per motor and per converter: their bytes are the key)."""
    key = tuple((x.dtype.str, x.shape, x.tobytes()) for x in (*primary, *tie))
    order = _ORDERS.pop(key, None) or _Order(primary, tie)
    _ORDERS[key] = order
    while len(_ORDERS) > KEPT_ORDERS:
        _ORDERS.pop(next(iter(_ORDERS)))
    return order


def first_in_order(checks: PairChecks, primary: tuple[np.ndarray, np.ndarray], tie: tuple[np.ndarray, np.ndarray],
                    count: int, before: int = 2) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The first ``count`` feasible pairs in the order of the score primary[0][m] + primary[1][c], then of
    tie[0][m] + tie[1][c], then of the catalogs (m, then c), and the ``before`` pairs just before the first of them,
    nearest first (all fail a check): (m, c) of the feasible ones and (m, c) of those before.

    The pairs are taken in the slices of their order (:class:`_Order`), so that the memory stays with the slice
    and the work with the pairs before the ``count``-th feasible one. In a slice the pairs that pass the screening
    (:meth:`PairChecks.screen`, a block at a time: :data:`SCREENED_FIRST` pairs, then twice as many, …) are checked
    in order, ``count`` (at most 8) at a time and then more (:func:`_growing`); the pairs before the first feasible
    one are those before it in its slice (and the slice before)."""
    order = _order_of(primary, tie)
    found_m, found_c = [np.zeros(0, dtype=int)], [np.zeros(0, dtype=int)]
    previous = (np.zeros(0, dtype=int), np.zeros(0, dtype=int))
    prior: tuple[np.ndarray, np.ndarray] | None = None
    k, found = 0, 0
    while found < count and (pairs := order.slice(k)) is not None:
        m, c = pairs
        for block in _growing(len(m), SCREENED_FIRST):
            alive = block.start + np.flatnonzero(checks.screen(m[block], c[block]))
            for part in _growing(len(alive), min(count, 8)):
                index = alive[part]
                ok = index[feasible_pairs(checks, m[index], c[index], screened=True)]
                if prior is None and len(ok):
                    prior = _just_before(pairs, previous, int(ok[0]), before)
                found_m.append(m[ok])
                found_c.append(c[ok])
                found += len(ok)
                if found >= count:
                    break
            if found >= count:
                break
        previous, k = pairs, k + 1
    m, c = np.concatenate(found_m)[:count], np.concatenate(found_c)[:count]
    return m, c, *(prior if prior is not None else (m[:0], c[:0]))


def _growing(n: int, first: int = 8) -> list[slice]:
    """Consecutive slices of range(n), the first ``first`` long and each next twice as long (up to
    :data:`FIRST_SLICE`): the pairs in order are checked a few at a time while the first feasible ones are likely
    near, more at a time further on."""
    out, start, size = [], 0, first
    while start < n:
        out.append(slice(start, min(start + size, n)))
        start, size = start + size, min(2 * size, FIRST_SLICE)
    return out


def _just_before(pairs: tuple[np.ndarray, np.ndarray], previous: tuple[np.ndarray, np.ndarray], position: int,
                 count: int) -> tuple[np.ndarray, np.ndarray]:
    """The ``count`` pairs just before the one at ``position`` of ``pairs`` (a slice, in order), nearest first,
    with those at the end of ``previous`` (the slice before) when its slice has too few."""
    m, c = pairs[0][:position], pairs[1][:position]
    if len(m) < count:
        m, c = np.concatenate([previous[0], m]), np.concatenate([previous[1], c])
    return m[::-1][:count], c[::-1][:count]


def _ranked(factors: np.ndarray) -> np.ndarray:
    """Load factors to rank by: NaN (an unlimited check's ∞/∞) as +inf, so that every comparison is defined."""
    return np.where(np.isnan(factors), math.inf, factors)


def smallest_worst(checks: PairChecks, count: int, feasible_only: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """The ``count`` pairs with the smallest exact worst load factor (ties: the smaller lower bound of
    :meth:`PairChecks.worst` at level 1, then catalog order), by branch and bound a block of motors at a time: a
    pair whose lower bound exceeds the ``count``-th best exact value found so far cannot enter. With
    ``feasible_only`` only the pairs that pass every check count (the ``margin`` ranking). A load factor that is
    not a number ranks as infinite (:func:`_ranked`): every pair of an infeasible joint is comparable, and the
    closest pairs are never empty."""
    best = np.zeros((0, 4))  # m, c, exact, bound
    limit = math.inf
    converters = np.arange(checks.shape[1])
    for block in _motor_blocks(checks):
        mm, cc = np.meshgrid(np.arange(block.start, block.stop), converters, indexing="ij")
        m, c = mm.ravel(), cc.ravel()
        if feasible_only:
            keep = checks.screen(m, c)
            m, c = m[keep], c[keep]
        bound = _ranked(checks.worst(m, c, 0))
        m, c = m[bound <= limit], c[bound <= limit]
        bound = _ranked(checks.worst(m, c, 1))
        keep = bound <= limit
        m, c, bound = m[keep], c[keep], bound[keep]
        order = np.argsort(bound, kind="stable")
        heated = bool(checks.heated[m].any())  # the winding simulated only where its bound leaves a chance
        parts = _growing(len(order), 16) if heated else [slice(s, s + 256) for s in range(0, len(order), 256)]
        for piece in parts:
            part = order[piece]
            if bound[part[0]] > limit:
                break
            exact = _ranked(checks.worst(m[part], c[part], 2, thermal=not heated))
            if heated:
                sharp = np.flatnonzero((exact <= limit) & ((exact <= 1 + PASS_TOLERANCE) | (not feasible_only)))
                exact[sharp] = _ranked(checks.worst(m[part[sharp]], c[part[sharp]], 2))
            if feasible_only:
                part, exact = part[exact <= 1 + PASS_TOLERANCE], exact[exact <= 1 + PASS_TOLERANCE]
            rows = np.column_stack([m[part], c[part], exact, bound[part]])
            best = np.concatenate([best, rows])
            if len(best) >= count:
                limit = float(np.sort(best[:, 2])[count - 1])
                best = best[best[:, 2] <= limit]
    order = np.lexsort((best[:, 0] * checks.shape[1] + best[:, 1], best[:, 3], best[:, 2]))[:count]
    return best[order, 0].astype(int), best[order, 1].astype(int)


def motor_passes(duty: JointDuty, motors: pd.DataFrame | MotorArrays, conv: Converters, inertia_ratio_max: float,
                  limits: DriveLimits | None = None) -> Callable[[float], bool]:
    """passes(k): whether some pair passes every check with the task replayed k times slower, a block of motors at
    a time (the pair that passed last is tried first; with motors checked by their winding, the pairs of a block by
    their lower bounds, smallest first, a few at a time, until one passes). On a joint that holds a load at rest each
    motor carries its brake (:func:`~mechatron.drives.brakes.with_brakes`: J_m + J_b in every check, the brake's
    checks), as in the sizing at the pace found."""
    last: list[tuple[int, int]] = []
    motors = with_brakes(MotorArrays.of(motors), duty)

    def passes(k: float) -> bool:
        checks = PairChecks(duty.scaled(k), motors, conv, inertia_ratio_max, limits)
        if last and feasible_pairs(checks, np.array([last[0][0]]), np.array([last[0][1]]))[0]:
            return True
        usable = np.flatnonzero(checks.converter_passes)
        for block in _motor_blocks(checks):
            index = np.arange(block.start, block.stop)
            mm, cc = np.nonzero(checks.screen(index[:, None], usable[None, :]))
            m, c = index[mm], usable[cc]
            if checks.heated[m].any():  # the most likely first, a few at a time: each winding is a simulation
                bound = checks.worst(m, c, 1)
                order = np.argsort(bound, kind="stable")[: np.count_nonzero(bound <= 1 + PASS_TOLERANCE)]
                parts = [order[part] for part in _growing(len(order))]
            else:
                parts = [np.arange(len(m))]
            for part in parts:
                ok = np.flatnonzero(feasible_pairs(checks, m[part], c[part], screened=True))
                if len(ok):
                    last[:] = [(int(m[part][ok[0]]), int(c[part][ok[0]]))]
                    return True
        return False

    return passes

