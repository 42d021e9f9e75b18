r"""Interference of a planar linkage's bodies and cylinders along a sweep: which pairs come closer than a clearance,
and at which pose first.

**The outlines.** Every body is its drawing (the polyline ``draw`` of the mechanism file, else its points in order,
the charts' sketch) and every cylinder the segment from its base pin to its eye (barrel and rod). Each segment is a
capsule of width w (m): the points within w/2 of it. The file gives no width, so by our default w = 0 (the drawn
centre lines: a pair interferes where the lines cross); :func:`interference` takes one width for all and one per
body or cylinder (``widths``), e.g. a cylinder's outer diameter from its catalog.

**The signed distance of two segments** AB and CD in the plane (m): if they do not cross, the least distance of
an end point to the other segment (in the plane the closest points of two disjoint segments include an end point),

.. math::

    s = \min\{d(A, CD),\ d(B, CD),\ d(C, AB),\ d(D, AB)\},

and if they cross, minus the least distance by which one must move to part them (the distance from the origin to
the boundary of the parallelogram AB ⊖ CD, whose edges lie on the lines through A − C, B − C along CD and through
A − C, A − D along AB):

.. math::

    s = -\min\{\ell(A, CD),\ \ell(B, CD),\ \ell(C, AB),\ \ell(D, AB)\},

ℓ(P, XY) = |(Y − X) × (P − X)| / |XY| the distance of P to the line XY. Two capsules of widths w₁, w₂ are then
s − (w₁ + w₂)/2 apart (negative: overlapping by that much), exactly. A pair of elements is as far apart as its
closest pair of segments; it **interferes** at a pose where that gap is below ``clearance`` (m, default 0).

**Pairs left out (our rule).** Bodies joined to each other touch by design, so a pair is not checked when the two
share a joint or a closure: a body and its parent in the joint tree (a pin or a prismatic guide), the two bodies of
a pin, slider or gear closure, a body held on a world curve and the ground, and a cylinder and the bodies its base
and eye are pinned to. Every other pair is checked, the ground's outline among them. Bodies side by side in
different planes (a cylinder between a scissor's outer arms) cross in the drawing: leave such pairs out with
``ignore``.

All samples and segment pairs are computed at once in NumPy, the poses from the sweep's joint coordinates by the
batched forward kinematics of :mod:`mechatron.model.batched`. Units: m, rad (angles shown in degrees).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from ..model.mechanism import Mechanism
from ..report.result import Result, frame_records, readable

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from .sweeps import SweepResult

#: The most pairs :meth:`InterferenceResult.plot` draws: those that come closest.
PLOTTED_PAIRS = 8


def _cross(u: NDArray[np.float64], v: NDArray[np.float64]) -> NDArray[np.float64]:
    """The z component of u × v over the last axis (length 2)."""
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]


def point_segment_distance(p: ArrayLike, a: ArrayLike, b: ArrayLike) -> NDArray[np.float64]:
    """Distance (m) from points p to segments ab, all (..., 2) broadcasting: |p − (a + t(b − a))| with
    t = clip((p − a)·(b − a) / |b − a|², 0, 1) (t = 0 for a segment of zero length)."""
    p, a, b = (np.asarray(x, dtype=float) for x in (p, a, b))
    ab, ap = b - a, p - a
    length2 = np.einsum("...i,...i->...", ab, ab)
    with np.errstate(invalid="ignore", divide="ignore"):
        t = np.where(length2 > 0.0, np.einsum("...i,...i->...", ap, ab) / length2, 0.0)
    t = np.clip(t, 0.0, 1.0)
    return np.linalg.norm(ap - t[..., None] * ab, axis=-1)


def segment_distance(a: ArrayLike, b: ArrayLike, c: ArrayLike, d: ArrayLike) -> NDArray[np.float64]:
    """Signed distance (m) of the segments ab and cd, all (..., 2) broadcasting (see the module docstring): the
    least distance between them if they do not cross, minus the least move that parts them if they do."""
    a, b, c, d = (np.asarray(x, dtype=float) for x in (a, b, c, d))
    apart = np.minimum(np.minimum(point_segment_distance(a, c, d), point_segment_distance(b, c, d)),
                       np.minimum(point_segment_distance(c, a, b), point_segment_distance(d, a, b)))
    o1, o2 = _cross(b - a, c - a), _cross(b - a, d - a)  # sides of c and d of the line ab
    o3, o4 = _cross(d - c, a - c), _cross(d - c, b - c)  # sides of a and b of the line cd
    crossing = (o1 * o2 < 0.0) & (o3 * o4 < 0.0)
    lab, lcd = np.linalg.norm(b - a, axis=-1), np.linalg.norm(d - c, axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        depth = np.minimum(np.minimum(np.abs(o1), np.abs(o2)) / lab, np.minimum(np.abs(o3), np.abs(o4)) / lcd)
    return np.where(crossing, -depth, apart)


@dataclass(frozen=True)
class Element:
    """A body or a cylinder as interference sees it: its name, ``kind`` ("link", "ground", "slider", "cylinder"),
    the frames its polyline runs through, the tree joints that carry it and its width (m)."""

    name: str
    kind: str
    frames: tuple[str, ...]
    joints: frozenset[int]
    width: float

    @property
    def label(self) -> str:
        """The name in reports: ``cylinder lift`` for a cylinder, the body's name otherwise."""
        return f"cylinder {self.name}" if self.kind == "cylinder" else self.name


def elements(mech: Mechanism, width: float = 0.0, widths: Mapping[str, float] | None = None) -> list[Element]:
    """The bodies and cylinders of the planar linkage ``mech`` (its sketch), each of width ``widths[name]`` or
    ``width`` (m, ≥ 0).

    Raises:
        InputError: for a mechanism without a sketch, a negative width, or a width for no body or cylinder.
    """
    if not mech.sketch:
        raise InputError(f"{mech.name}: no drawing of its bodies (a mechanism file's linkage has one); "
                         "interference checks the outlines of a planar linkage")
    widths = dict(widths or {})
    names = {line.name for line in mech.sketch}
    for name, value in {"width": width, **widths}.items():
        if not (math.isfinite(value) and value >= 0.0):
            raise InputError(f"interference: width of {name}: {value!r} m; expected a number >= 0")
    unknown = sorted(set(widths) - names)
    if unknown:
        raise InputError(f"interference: width for {', '.join(unknown)}: no such body or cylinder "
                         f"(known: {', '.join(sorted(names))})")
    model = mech.model
    out = []
    for line in mech.sketch:
        if line.kind == "cylinder":
            joints = {mech.joint_id(f"{line.name}_angle"), mech.joint_id(line.name)}
        else:
            joints = {model.frames[mech.frame_id(line.name)].parentJoint}
        out.append(Element(line.name, line.kind, tuple(line.points), frozenset(joints),
                           float(widths.get(line.name, width))))
    return out


def joined(mech: Mechanism, first: Element, second: Element) -> bool:
    """Whether two elements touch by design (our rule, module docstring): a joint of one is the other's parent in
    the tree, or a closure uses frames on both (a closure of one frame, a point on a world curve, joins the
    ground)."""
    parents = mech.model.parents
    if any(parents[j] in second.joints for j in first.joints) or \
            any(parents[j] in first.joints for j in second.joints):
        return True
    for closure in mech.closures:
        carried = {mech.model.frames[mech.frame_id(f)].parentJoint for f in closure.frames}
        if len(closure.frames) == 1:
            carried.add(0)
        if carried & first.joints and carried & second.joints:
            return True
    return False


def frame_positions(mech: Mechanism, Q: ArrayLike, names: Iterable[str]) -> dict[str, NDArray[np.float64]]:
    """World positions (N, 3) (m) of the frames ``names`` at the N configurations ``Q`` (N, nq): batched
    (:mod:`mechatron.model.batched`), or by Pinocchio one configuration at a time for joints it does not know."""
    from ..model.batched import batched_frames

    names = list(dict.fromkeys(names))
    Q = np.atleast_2d(np.asarray(Q, dtype=float))
    ids = [mech.frame_id(n) for n in names]
    try:
        position = batched_frames(mech.model, ids).placements(Q, jacobians=False).position
    except NotImplementedError:
        data = mech.model.createData()
        position = np.empty((len(Q), len(ids), 3))
        for k, q in enumerate(Q):
            pin.framesForwardKinematics(mech.model, data, q)
            position[k] = [data.oMf[i].translation for i in ids]
    return {n: position[:, k] for k, n in enumerate(names)}


@dataclass
class InterferenceResult(Result):
    """Results of :func:`interference`: the gap of every checked pair of bodies and cylinders at every pose of a
    sweep.

    Attributes:
        mechanism: The mechanism checked.
        sweep: The sweep whose poses were checked.
        elements: The bodies and cylinders with their widths (m).
        pairs: The checked pairs, as indices into ``elements``.
        gap: (N, P) the signed distance of each pair's outlines (capsules) at each pose, m (negative: overlapping).
        clearance: The least gap required, m.
        excluded: The pairs not checked (joined, our rule, or in ``ignore``), as pairs of names.
    """

    mechanism: Mechanism
    sweep: SweepResult
    elements: list[Element]
    pairs: list[tuple[int, int]]
    gap: NDArray[np.float64]
    clearance: float = 0.0
    excluded: list[tuple[str, str]] = field(default_factory=list)

    # --------------------------------------------------------------------------------------------- the data
    @property
    def inputs(self) -> list[str]:
        """The actuated coordinates: the columns of the sweep table that name a pose."""
        return list(self.mechanism.actuated)

    def _names(self, k: int) -> tuple[str, str]:
        i, j = self.pairs[k]
        return self.elements[i].label, self.elements[j].label

    def _pose(self, row: int) -> dict[str, float]:
        table = self.sweep.table
        return {name: float(table[name].iloc[row]) for name in self.inputs}

    def _shown(self, name: str, value: float) -> str:
        """``name = value unit`` with an angle in degrees."""
        unit = self.sweep.column_unit(name)
        return f"{name} = {readable(math.degrees(value) if unit == 'deg' else value)} {unit}"

    def interfering(self) -> list[int]:
        """The indices of the pairs that interfere at some pose, in the order of ``pairs``."""
        return [k for k in range(len(self.pairs)) if len(self.gap) and (self.gap[:, k] < self.clearance).any()]

    def rows(self) -> list[dict[str, Any]]:
        """One record per checked pair: ``first``, ``second`` (names), ``interferes``, ``min_gap`` (m) and the
        ``min_sample`` where it is least, ``first_sample`` (the first pose where the gap is below the clearance, or
        None), ``first_gap`` (m) there, and the inputs at that pose (m or rad, None where it never interferes)."""
        out = []
        for k in range(len(self.pairs)):
            first, second = self._names(k)
            gaps = self.gap[:, k]
            below = np.flatnonzero(gaps < self.clearance)
            low = int(np.argmin(gaps)) if len(gaps) else None
            row: dict[str, Any] = {"first": first, "second": second, "interferes": bool(len(below)),
                                   "min_gap": float(gaps[low]) if low is not None else None,
                                   "min_sample": int(self.sweep.table["sample"].iloc[low]) if low is not None else None}
            hit = int(below[0]) if len(below) else None
            row["first_sample"] = int(self.sweep.table["sample"].iloc[hit]) if hit is not None else None
            row["first_gap"] = float(gaps[hit]) if hit is not None else None
            row.update(self._pose(hit) if hit is not None else dict.fromkeys(self.inputs))
            out.append(row)
        return out

    def warnings(self) -> list[str]:
        """One line per interfering pair at its first pose: ``interference: boom and cylinder bucket at lift =
        0.42 m (distance -0.013 m)``."""
        lines = []
        for row in self.rows():
            if row["interferes"]:
                pose = ", ".join(self._shown(name, row[name]) for name in self.inputs)
                lines.append(f"interference: {row['first']} and {row['second']} at {pose} "
                             f"(distance {readable(row['first_gap'])} m)")
        return lines

    def to_frame(self) -> pd.DataFrame:
        """:meth:`rows` as a table: one row per checked pair (gaps in m, inputs in m or rad; NaN where a pair never
        interferes)."""
        import pandas as pd

        columns = ["first", "second", "interferes", "first_sample", *self.inputs, "first_gap", "min_gap",
                   "min_sample"]
        return pd.DataFrame(self.rows(), columns=columns)

    def as_dict(self) -> dict[str, Any]:
        """The mechanism, the clearance (m), the widths (m), the rule for the pairs left out, those pairs, the
        checked pairs (:meth:`rows`) and the warnings."""
        return {"mechanism": self.mechanism.name, "samples": len(self.gap), "clearance": self.clearance,
                "widths": {e.label: e.width for e in self.elements},
                "excluded_rule": "pairs joined by a joint or a closure touch by design and are not checked (ours)",
                "excluded": [list(p) for p in self.excluded], "pairs": frame_records(self.to_frame()),
                "warnings": self.warnings()}

    def __str__(self) -> str:
        width = sorted({e.width for e in self.elements})
        widths = f"{readable(width[0])} m" if len(width) == 1 else "per body (see --json)"
        lines = [f"{self.mechanism.name}: interference of {len(self.elements)} bodies and cylinders over "
                 f"{len(self.gap)} poses (outline width {widths}, clearance {readable(self.clearance)} m); "
                 f"{len(self.pairs)} pairs checked, {len(self.excluded)} joined pairs left out"]
        lines += [f"  {line}" for line in self.warnings()] or ["  no pair comes closer than the clearance"]
        closest = sorted(self.rows(), key=lambda r: math.inf if r["min_gap"] is None else r["min_gap"])[:3]
        for row in closest:
            if row["min_gap"] is not None:
                lines.append(f"  closest: {row['first']} and {row['second']}, {readable(row['min_gap'])} m at "
                             f"sample {row['min_sample']}")
        return "\n".join(lines)

    # -------------------------------------------------------------------------------------------- the chart
    def plot(self, ax: Axes | None = None) -> Figure:
        """The gap of each pair (m; the :data:`PLOTTED_PAIRS` closest) against the first input that moves, with the
        clearance drawn and the pairs that interfere in solid lines."""
        from ..report.figures import figure_axes, style_axes

        figure, ax = figure_axes(ax)
        table = self.sweep.table
        moving = [n for n in self.inputs if len(table) and np.ptp(table[n].to_numpy()) > 0.0]
        x = (moving or self.inputs)[0]
        unit = self.sweep.column_unit(x)
        values = table[x].to_numpy(dtype=float)
        values = np.degrees(values) if unit == "deg" else values
        hits = set(self.interfering())
        order = sorted(range(len(self.pairs)), key=lambda k: float(self.gap[:, k].min()) if len(self.gap) else 0.0)
        for k in order[:PLOTTED_PAIRS]:
            first, second = self._names(k)
            ax.plot(values, self.gap[:, k], ls="-" if k in hits else "--", label=f"{first} – {second}")
        ax.axhline(self.clearance, color="black", lw=1.0, label=f"clearance {readable(self.clearance)} m")
        if self.clearance != 0.0:
            ax.axhline(0.0, color="gray", lw=0.8, ls=":")
        style_axes(ax, f"{x} ({unit})", "gap between outlines (m)",
                   title=f"{self.mechanism.name}: interference along the sweep", legend=True)
        return figure


def interference(mech: Mechanism, sweep: SweepResult | None = None, *, samples: int = 200, width: float = 0.0,
                 widths: Mapping[str, float] | None = None, clearance: float = 0.0,
                 ignore: Iterable[tuple[str, str]] = ()) -> InterferenceResult:
    """Check every pair of bodies and cylinders of the planar linkage ``mech`` for interference at each pose of
    ``sweep`` (default :func:`~mechatron.kinematics.sweeps.sweep` of ``samples`` poses): the signed distance of
    their outlines (segments of width ``widths[name]`` or ``width``, m) against ``clearance`` (m); pairs joined by a
    joint or a closure, and the pairs ``ignore`` names (body or cylinder names, either order), are not checked
    (module docstring).

    Raises:
        InputError: for a mechanism without a drawing or out of its plane, a negative width or clearance, or a name
            in ``widths`` or ``ignore`` that is no body or cylinder.
    """
    from .sweeps import sweep as run_sweep

    if not (math.isfinite(clearance) and clearance >= 0.0):
        raise InputError(f"interference: clearance {clearance!r} m; expected a number >= 0")
    parts = elements(mech, width, widths)
    names = {e.name for e in parts}
    skipped = set()
    for pair in ignore:
        unknown = [n for n in pair if n not in names]
        if unknown or len(pair) != 2:
            raise InputError(f"interference: ignore {tuple(pair)!r}: expected two of {', '.join(sorted(names))}")
        skipped.add(frozenset(pair))
    sweep = sweep if sweep is not None else run_sweep(mech, samples=samples)
    pairs, excluded = [], []
    for i in range(len(parts)):
        for j in range(i + 1, len(parts)):
            if frozenset((parts[i].name, parts[j].name)) in skipped or joined(mech, parts[i], parts[j]):
                excluded.append((parts[i].label, parts[j].label))
            else:
                pairs.append((i, j))
    positions = frame_positions(mech, sweep.q, (f for e in parts for f in e.frames)) if len(sweep.q) else {}
    if positions and max(float(np.ptp(p[:, 2])) for p in positions.values()) > 1e-9:
        raise InputError(f"{mech.name}: its points leave the x–y plane; interference checks planar linkages")
    gap = _gaps(parts, pairs, positions, len(sweep.q))
    return InterferenceResult(mech, sweep, parts, pairs, gap, float(clearance), excluded)


def _segments(element: Element, positions: Mapping[str, NDArray[np.float64]]
              ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The ends (N, S, 2) of the S segments of an element's polyline (a single point: one segment of length 0)."""
    xy = np.stack([positions[f][:, :2] for f in element.frames], axis=1)
    if xy.shape[1] == 1:
        return xy, xy
    return xy[:, :-1], xy[:, 1:]


def _gaps(parts: list[Element], pairs: list[tuple[int, int]], positions: Mapping[str, NDArray[np.float64]],
          n: int) -> NDArray[np.float64]:
    """(N, P) the gap of each pair: the least signed distance over its segment pairs less the half widths (m)."""
    gap = np.empty((n, len(pairs)))
    if n == 0:
        return gap
    ends = [_segments(e, positions) for e in parts]
    for k, (i, j) in enumerate(pairs):
        (a, b), (c, d) = ends[i], ends[j]
        s = segment_distance(a[:, :, None], b[:, :, None], c[:, None, :], d[:, None, :])  # (N, Si, Sj)
        gap[:, k] = s.reshape(n, -1).min(axis=1) - 0.5 * (parts[i].width + parts[j].width)
    return gap
