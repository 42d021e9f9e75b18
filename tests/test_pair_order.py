"""The order in which the sizing tries motor × converter pairs (mass, then price, then catalog order) is made once
per catalogs and kept: it must be the full sort of every pair, slice by slice, whatever is kept, and the search
must find the same first feasible pairs and the same pairs just before them as a brute force over all pairs."""

import numpy as np
import pytest

from mechatron.drives import search
from mechatron.drives.search import _Order, _order_of, first_in_order


def _scores(rng, motors=40, converters=30):
    # rounded so that many pairs tie on mass and on price
    primary = (np.round(rng.uniform(0, 5, motors), 1), np.round(rng.uniform(0, 5, converters), 1))
    tie = (np.round(rng.uniform(0, 3, motors), 0), np.round(rng.uniform(0, 3, converters), 0))
    return primary, tie


def _brute_order(primary, tie):
    m, c = (x.ravel() for x in np.meshgrid(np.arange(len(primary[0])), np.arange(len(primary[1])), indexing="ij"))
    order = np.lexsort((m * len(primary[1]) + c, tie[0][m] + tie[1][c], primary[0][m] + primary[1][c]))
    return m[order], c[order]


def _all_slices(order):
    out, k = [], 0
    while (pairs := order.slice(k)) is not None:
        out.append(pairs)
        k += 1
    return out


@pytest.mark.parametrize("kept", [0, 300, 1 << 16])
def test_the_slices_are_the_full_sort_whatever_is_kept(monkeypatch, kept):
    monkeypatch.setattr(search, "FIRST_SLICE", 64)
    monkeypatch.setattr(search, "KEPT_PAIRS", kept)
    primary, tie = _scores(np.random.default_rng(3))
    order = _Order(primary, tie)
    first, again = _all_slices(order), _all_slices(order)
    assert len(first) > 3  # several slices
    expected = _brute_order(primary, tie)
    for slices in (first, again):
        np.testing.assert_array_equal(np.concatenate([m for m, _ in slices]), expected[0])
        np.testing.assert_array_equal(np.concatenate([c for _, c in slices]), expected[1])
    assert order._pairs <= kept


class _Feasible:
    """Checks where a fixed set of pairs is feasible (stands for PairChecks in the search)."""

    def __init__(self, ok):
        self.ok = ok

    def screen(self, m, c):
        return np.ones(len(m), dtype=bool)

    def bounds_pass(self, m, c):
        return np.ones(len(m), dtype=bool)

    def worst(self, m, c):
        return np.where(self.ok[m, c], 0.5, 2.0)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_first_feasible_pairs_and_those_before_match_a_brute_force(monkeypatch, seed):
    monkeypatch.setattr(search, "FIRST_SLICE", 64)
    rng = np.random.default_rng(seed)
    primary, tie = _scores(rng)
    ok = rng.uniform(size=(40, 30)) < 0.01
    m_all, c_all = _brute_order(primary, tie)
    feasible = np.flatnonzero(ok[m_all, c_all])
    for count in (1, 3):
        for _ in range(2):  # the second time from the kept order
            m, c, m_before, c_before = first_in_order(_Feasible(ok), primary, tie, count)
            np.testing.assert_array_equal(m, m_all[feasible[:count]])
            np.testing.assert_array_equal(c, c_all[feasible[:count]])
            first = feasible[0]
            np.testing.assert_array_equal(m_before, m_all[max(0, first - 2):first][::-1])
            np.testing.assert_array_equal(c_before, c_all[max(0, first - 2):first][::-1])


def test_orders_are_kept_for_the_last_few_catalogs():
    rng = np.random.default_rng(5)
    scores = [_scores(rng) for _ in range(search.KEPT_ORDERS + 2)]
    orders = [_order_of(*s) for s in scores]
    assert _order_of(*scores[-1]) is orders[-1]
    assert _order_of(*scores[0]) is not orders[0]  # dropped: only the last KEPT_ORDERS are kept
    same = tuple(tuple(x.copy() for x in pair) for pair in scores[-1])  # equal scores, other arrays
    assert _order_of(*same) is orders[-1]
