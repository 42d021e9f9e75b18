r"""The structural formulas of [Egorov, chapter 3], on counts (all dimensionless integers).

Conventions ([Egorov, table 3.1] and the text of its sections 3.2–3.4):

- a pair of class i imposes i constraints and leaves f = 6 − i relative mobilities (i = 1…5);
- n counts the moving links (the frame excluded); p_i the pairs of class i, passive and actuated alike;
- lower pairs are classes 5, 4, 3 (surface contact), higher pairs classes 2, 1 (line or point contact);
- in the planar formulas [Egorov, 3.3, 3.7, 3.8, 3.17, 3.20, 3.22] the index is not the spatial class: every lower
  pair counts with (5 − 3) = 2, every higher pair with (4 − 3) = 1, whatever its spatial class;
- in the per-loop count [Egorov, 3.14] m = 5 for lower and m = 4 for higher pairs, and the sum runs over the pairs of
  that loop only; in [Egorov, 3.16] the p_i count the pairs of the whole mechanism, and negative S_j (superfluous
  mobilities, h_j = −S_j) are added as they are.

``counts`` is a mapping class → number of pairs ({5: 4} is four class-5 pairs).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from fractions import Fraction

from ..errors import InputError

Counts = Mapping[int, int]


def _check(counts: Counts) -> None:
    for cls, number in counts.items():
        if cls not in (1, 2, 3, 4, 5):
            raise InputError(f"a kinematic pair class is 1…5 (the number of constraints), got {cls!r}")
        if number < 0:
            raise InputError(f"a number of pairs must be >= 0, got {number} of class {cls}")


def is_lower(cls: int) -> bool:
    """Lower pairs (surface contact) are classes 5, 4, 3; higher pairs (line, point) classes 2, 1."""
    return cls >= 3


def constraint_sum(counts: Counts) -> int:
    """Σ i·p_i."""
    _check(counts)
    return sum(cls * number for cls, number in counts.items())


def planar_constraint_sum(counts: Counts) -> int:
    """Σ (i − 3) p_i of the planar formulas: 2 per lower pair, 1 per higher pair [Egorov, 3.3]."""
    _check(counts)
    return sum((2 if is_lower(cls) else 1) * number for cls, number in counts.items())


def malyshev(n: int, counts: Counts) -> int:
    """W = 6n − Σ i·p_i [Egorov, 3.2], the spatial mobility."""
    return 6 * n - constraint_sum(counts)


def chebyshev(n: int, counts: Counts) -> int:
    """W_П = 3n − 2p₅ − p₄ [Egorov, 3.3 = 3.13], the planar mobility (p₅ lower, p₄ higher pairs)."""
    return 3 * n - planar_constraint_sum(counts)


def compound_hinge_pairs(links: int) -> int:
    """θ = N − 1 [Egorov, 3.1]: the pairs of a compound hinge where N links meet."""
    if links < 2:
        raise InputError(f"a hinge joins at least 2 links, got {links}")
    return links - 1


def gokhman(n: int, counts: Counts) -> int:
    """K = Σ p_i − n [Egorov, 3.10], the number of independent closed loops."""
    _check(counts)
    return sum(counts.values()) - n


def reshetov(n: int, counts: Counts, redundant: int) -> int:
    """W₀ = 6n − Σ i·p_i + S [Egorov, 3.11], the mobility of the basic scheme with S redundant constraints."""
    return malyshev(n, counts) + redundant


def reshetov_redundancy(n: int, counts: Counts, mobility: int) -> int:
    """S = W₀ − 6n + Σ i·p_i [Egorov, 3.12]: the redundant constraints of a mechanism of known mobility W₀."""
    return mobility - malyshev(n, counts)


def loop_redundancy(loop_counts: Counts) -> int:
    """S_j = 3 − Σ (m − i) p_i [Egorov, 3.14] over the pairs of loop j; m = 5 (lower) or 4 (higher). Negative values
    are superfluous mobilities h_j = −S_j."""
    _check(loop_counts)
    return 3 - sum(((5 if is_lower(cls) else 4) - cls) * number for cls, number in loop_counts.items())


def full_mobility(n: int, counts: Counts, loop_redundancies: Sequence[int], redundant_links: Sequence[int] = ()
                  ) -> int:
    """W = 6n − Σ i·p_i + Σ S_j − Σ Z_j [Egorov, 3.16], with the per-loop S_j of [Egorov, 3.14] and the redundant
    links Z_j."""
    return malyshev(n, counts) + sum(loop_redundancies) - sum(redundant_links)


def planar_mobility(n: int, counts: Counts, redundant_links: Sequence[int] = ()) -> int:
    """W_П = 3n − Σ (i − 3) p_i − Σ Z_j [Egorov, 3.17], planar, with redundant links."""
    return chebyshev(n, counts) - sum(redundant_links)


def degrees_of_mobility(n: int, loop_kinds: Sequence[int]) -> int:
    """H = n − Σ A_j [Egorov, 3.18]; A_j = 2 for a loop closed by a structural group, 1 for one closed by a single
    link."""
    for a in loop_kinds:
        if a not in (1, 2):
            raise InputError(f"A_j of [Egorov, 3.18] is 2 (closed by a group) or 1 (by one link), got {a!r}")
    return n - sum(loop_kinds)


# ------------------------------------------------------------------------------------------------ groups
def group_links(counts: Counts, planar: bool = False, redundancy: int = 0) -> Fraction:
    """Links of a structural group: n_Г = Σ i·p_i / 6 [Egorov, 3.5], or Σ (i − 3) p_i / 3 planar [Egorov, 3.8];
    with redundant constraints n_Г = (Σ i·p_i − Σ S_j) / 6 [Egorov, 3.24]. A group exists only when this is an
    integer."""
    if planar:
        return Fraction(planar_constraint_sum(counts), 3)
    return Fraction(constraint_sum(counts) - redundancy, 6)


def group_mobility(n: int, counts: Counts, planar: bool = False, redundancy: int = 0) -> int:
    """W_Г = 6n_Г − Σ i·p_i (+ Σ S_j) [Egorov, 3.4, 3.23], or 3n_Г − Σ (i − 3) p_i planar [Egorov, 3.7]: zero for a
    group."""
    return (chebyshev(n, counts) if planar else malyshev(n, counts) + redundancy)


# ------------------------------------------------------------------------------------------------ synthesis
def synthesis_links(mobility: int, counts: Counts, planar: bool = False, redundancy: int = 0,
                    redundant_links: int = 0) -> Fraction:
    """The number of links of a scheme with the given mobility and pairs:
    n = (W + Σ i·p_i − Σ S_j + Σ Z_j) / 6 [Egorov, 3.19] ([Egorov, 3.21] with S, Z) or
    n = (W_П + Σ (i − 3) p_i + Σ Z_j) / 3 [Egorov, 3.20] ([Egorov, 3.22]). A scheme exists only when this is a
    positive integer."""
    if planar:
        return Fraction(mobility + planar_constraint_sum(counts) + redundant_links, 3)
    return Fraction(mobility + constraint_sum(counts) - redundancy + redundant_links, 6)


def enumerate_schemes(mobility: int, classes: Sequence[int], *, planar: bool = False, redundancy: int = 0,
                      redundant_links: int = 0, max_pairs: int = 12, max_links: int = 12) -> list[dict]:
    """Structural synthesis by enumeration [Egorov, section 3.4]: every combination of pair counts of the allowed
    ``classes`` (at least one pair of each, at most ``max_pairs`` in all) for which [Egorov, 3.19–3.22] give a whole
    number of links n with 1 ≤ n ≤ max_links; each result has n, the counts, K [Egorov, 3.10] and Σ i·p_i."""
    classes = sorted(set(classes), reverse=True)
    _check({c: 0 for c in classes})
    out = []

    def extend(k: int, counts: dict[int, int], total: int) -> None:
        if k == len(classes):
            n = synthesis_links(mobility, counts, planar, redundancy, redundant_links)
            if n.denominator == 1 and 1 <= n <= max_links:
                out.append({"n": int(n), "pairs": dict(counts), "loops": gokhman(int(n), counts),
                            "constraints": constraint_sum(counts)})
            return
        for number in range(1, max_pairs - total - (len(classes) - k - 1) + 1):
            counts[classes[k]] = number
            extend(k + 1, counts, total + number)
        counts.pop(classes[k], None)

    extend(0, {}, 0)
    return sorted(out, key=lambda s: (sum(s["pairs"].values()), s["n"]))
