"""Decomposition of a planar mechanism into its driving links and structural (Assur) groups [Egorov, section 3.3,
tables 3.2 and 3.3].

The driven pairs are frozen first: links joined by an actuated pair move as one (a crank driven from the frame
joins the frame; a cylinder's barrel and rod become one link of given length). Starting from the frame, the
smallest connected set of not-yet-placed links, attached to the placed ones, whose pairs to the placed ones and among
themselves give zero planar mobility, 3n_Г − 2p_lower − p_higher = 0 [Egorov, 3.7], is a structural group; it is
placed and the search goes on. Only connected sets of at most :data:`MAX_GROUP` links grown from the placed ones are
tried, so the search grows with the number of links times the (bounded) number of such sets around each, not with
the number of all subsets: an open chain of hundreds of pairs is analysed at once.
Groups of two links and three lower pairs are dyads, named by their pairs outer–inner–outer (table 3.2: RRR, RRP,
RPR, PRP, RPP); a group of one link closes its loop by a single link (A_j = 1 in [Egorov, 3.18]), any larger group
by a structural group (A_j = 2).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

from ..errors import InputError
from .description import Pair, StructuralDescription

DYAD_TYPES = ("RRR", "RRP", "RPR", "PRP", "RPP")
MAX_GROUP = 6  # frozen links per group tried
#: The most candidate sets the group search builds in all (seconds of work): an open chain or a textbook linkage
#: needs hundreds, a dense graph of dozens of links joined to one another millions (the search is polynomial, of
#: degree MAX_GROUP).
MAX_CANDIDATES = 50_000


@dataclass(frozen=True)
class Group:
    """A structural group: its links (original names), its pairs (to placed links and among its links), the
    number of loops it closes, and its dyad type when it is one."""

    links: tuple[str, ...]
    pairs: tuple[str, ...]
    loops: int
    dyad: str | None = None
    driven: tuple[str, ...] = ()  # actuated pairs inside the group's links (a cylinder: a link of driven length)

    @property
    def closing_value(self) -> int:
        """A_j of [Egorov, 3.18] for each loop this group closes: 1 for a single link, 2 for a group."""
        return 1 if len(self.links) == 1 else 2


@dataclass(frozen=True)
class Decomposition:
    driving_links: tuple[str, ...]
    groups: tuple[Group, ...]
    unplaced: tuple[str, ...]

    @property
    def complete(self) -> bool:
        """Every moving link is a driving link or in a group."""
        return not self.unplaced


def _weight(pair: Pair) -> int:
    return 2 if pair.lower else 1


def decompose(desc: StructuralDescription) -> Decomposition | None:
    """The groups of a planar description whose pairs all name their links (None otherwise)."""
    if not desc.planar or any(p.links is None for p in desc.pairs):
        return None
    parent = {link: link for link in [desc.frame, *desc.links]}

    def find(x: str) -> str:
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    for p in desc.pairs:
        if p.actuated:
            a, b = find(p.links[0]), find(p.links[1])
            if a != b:
                if b == find(desc.frame):  # the frame stays the root of its set
                    a, b = b, a
                parent[b] = a
    frame = find(desc.frame)
    members: dict[str, list[str]] = {}
    for link in desc.links:
        members.setdefault(find(link), []).append(link)
    driving = tuple(members.pop(frame, []))
    placed = {frame}
    free = [p for p in desc.pairs if find(p.links[0]) != find(p.links[1])]
    unknown = list(members)
    ends = [(find(p.links[0]), find(p.links[1])) for p in free]
    neighbours: dict[str, set[str]] = {root: set() for root in [frame, *members]}
    incident: dict[str, list[int]] = {root: [] for root in [frame, *members]}
    for k, (a, b) in enumerate(ends):
        neighbours[a].add(b)
        neighbours[b].add(a)
        incident[a].append(k)
        incident[b].append(k)
    order = {root: k for k, root in enumerate(members)}
    groups = []
    tried = [0]  # candidate sets built so far (bounded by MAX_CANDIDATES)
    while unknown:
        found = None
        for size, candidates in zip(range(1, min(MAX_GROUP, len(unknown)) + 1),
                                    _connected_sets(unknown, placed, neighbours, order, tried, desc.name)):
            for candidate in candidates:
                inside = set(candidate)
                touching = sorted({k for c in candidate for k in incident[c]})
                pairs = [free[k] for k in touching if ends[k][0] in inside | placed and ends[k][1] in inside | placed]
                if pairs and 3 * size - sum(_weight(p) for p in pairs) == 0 and _attached(pairs, placed, find):
                    found = (candidate, pairs)
                    break
            if found:
                break
        if not found:
            break
        candidate, pairs = found
        links = tuple(x for c in candidate for x in members[c])
        dyad = _dyad_type(candidate, pairs, placed, find) if len(candidate) == 2 and len(pairs) == 3 else None
        driven = tuple(p.name for p in desc.pairs if p.actuated and find(p.links[0]) in candidate)
        groups.append(Group(links, tuple(p.name for p in pairs), len(pairs) - len(candidate), dyad, driven))
        placed |= set(candidate)
        unknown = [u for u in unknown if u not in candidate]
    return Decomposition(driving, tuple(groups), tuple(x for u in unknown for x in members[u]))


def _connected_sets(unknown: list[str], placed: set[str], neighbours: dict[str, set[str]], order: dict[str, int],
                    tried: list[int], name: str) -> Iterator[list[tuple[str, ...]]]:
    """The connected sets of unplaced links that touch a placed one, by size (1, 2, …): each size as a list of
    tuples in the links' order, sorted as ``itertools.combinations`` would give them. ``tried[0]`` counts the sets
    built; past :data:`MAX_CANDIDATES` the search stops with an :class:`~mechatron.errors.InputError`."""
    pool = set(unknown)
    level = {frozenset([u]) for u in unknown if neighbours[u] & placed}
    while level:
        tried[0] += len(level)
        yield sorted((tuple(sorted(s, key=order.__getitem__)) for s in level),
                     key=lambda c: [order[x] for x in c])
        grown: set[frozenset[str]] = set()
        for s in level:
            for x in s:
                grown.update(s | {n} for n in neighbours[x] & pool if n not in s)
            if tried[0] + len(grown) > MAX_CANDIDATES:
                raise InputError(f"structure {name}: the search for structural groups would try more than "
                                 f"{MAX_CANDIDATES:,} sets of links ({len(pool)} links left, joined to many others): "
                                 "give each loop's closed_by, or describe fewer links")
        level = grown


def _attached(pairs: list[Pair], placed: set[str], find) -> bool:
    return any(find(p.links[0]) in placed or find(p.links[1]) in placed for p in pairs)


def _code(pair: Pair) -> str:
    return "P" if pair.kind == "P" else "R"


def _dyad_type(candidate, pairs: list[Pair], placed: set[str], find) -> str | None:
    """outer–inner–outer pair codes of a dyad, read from either end to match table 3.2."""
    if not all(p.lower and p.kind in ("R", "P") for p in pairs):
        return None
    inner = [p for p in pairs if {find(x) for x in p.links} == set(candidate)]
    if len(inner) != 1:
        return None
    outer = {}
    for c in candidate:
        touching = [p for p in pairs if p is not inner[0] and c in {find(x) for x in p.links}]
        if len(touching) != 1:
            return None
        outer[c] = touching[0]
    first, second = (_code(outer[candidate[0]]), _code(outer[candidate[1]]))
    for name in (first + _code(inner[0]) + second, second + _code(inner[0]) + first):
        if name in DYAD_TYPES:
            return name
    return None
