"""The textbook's single-loop mechanisms [Egorov, sections 4.1–4.3; figs. 4.2, 4.4–4.6, 4.10, 4.18, 5.7, 8.3].

All are drawn in the xy plane with the crank pivot A at the origin and the crank angle q1 (rad) measured
counter-clockwise from the x axis; lengths in m. The masses are illustrative (rod 2 kg as a uniform bar, slider
1 kg, crank balanced with its centre at A): the book gives none.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError
from ..model.mechanism import Mechanism, Parameter
from ..model.planar import GROUND, PlanarBuilder


def _check_positive(name: str, **values: float) -> None:
    for key, value in values.items():
        if not value > 0:
            raise InputError(f"{name}: parameter {key} must be > 0 m, got {value:g}")


def crank_slider(l1: float = 0.1, l2: float = 0.4, q1: float = math.pi / 3) -> Mechanism:
    """Central crank-slider: crank AB = l1 about A, rod BC = l2, slider C on the x axis through A
    [Egorov, figs. 4.2, 4.18].

    Position (the example of [Egorov, fig. 4.18]): x_C = l1 cos q1 + sqrt(l2² − l1² sin² q1). Actuated coordinate
    ``q1`` (crank angle);
    ``xC`` is the slider coordinate. Points A, B, C (slider pin), S2 (middle of the rod); links ``crank``, ``rod``,
    ``slider``. Drawn with the slider on the +x side of A at crank angle ``q1`` (branch ``right``, the reference);
    branch ``left`` has the slider on the other side.
    """
    _check_positive("crank_slider", l1=l1, l2=l2)
    if l2 <= l1:
        raise InputError(f"crank_slider: the rod l2 = {l2:g} m must be longer than the crank l1 = {l1:g} m "
                         "for the crank to turn fully")
    B = np.array([l1 * math.cos(q1), l1 * math.sin(q1)])
    xC = B[0] + math.sqrt(l2**2 - B[1] ** 2)
    C = np.array([xC, 0.0])
    b = PlanarBuilder("crank_slider")
    b.point("A", GROUND, (0.0, 0.0))
    b.point("guide", GROUND, (0.0, 0.0), report=False)
    crank = b.revolute("crank", "A", toward=B, coordinate="q1", mass=1.0, com=(0.0, 0.0), inertia=1e-3)
    b.point("B", crank, B)
    rod = b.revolute("rod", "B", toward=C, coordinate="phi2", mass=2.0, com=(B + C) / 2, inertia=2.0 * l2**2 / 12)
    b.point("C", rod, C)
    b.point("S2", rod, (B + C) / 2)
    slider = b.prismatic("slider", "guide", (1.0, 0.0), reference=xC, coordinate="xC", mass=1.0, com=C)
    b.point("C_slider", slider, C, report=False)
    b.pin("C", "C_slider")
    b.line("crank", "A", "B")
    b.line("rod", "B", "C")
    b.line("slider", "C_slider", "C_slider", kind="slider")
    params = {"l1": Parameter("l1", l1, "length", "crank AB"), "l2": Parameter("l2", l2, "length", "rod BC")}
    # the other assembly branch: the slider on the far side, at x = l1 cos q1 − √(l2² − l1² sin² q1)
    left = np.array([q1, math.atan2(-B[1], -math.sqrt(l2**2 - B[1] ** 2)) - q1, B[0] - math.sqrt(l2**2 - B[1] ** 2)])
    return b.build(actuated=["q1"], description=f"central crank-slider, crank l1 = {l1:g} m, rod l2 = {l2:g} m",
                   parameters=params, tool="C", rebuild=lambda v: crank_slider(v["l1"], v["l2"], q1),
                   branches={"right": b.reference_configuration(), "left": left})


def scotch_yoke(l1: float = 0.1, q1: float = math.pi / 3) -> Mechanism:
    """Sine (scotch-yoke) mechanism: crank AB = l1 about A, a block on the crank pin B slides in the vertical slot
    of the yoke, which slides along the x axis [Egorov, fig. 4.4]: x_C = l1 cos q1 (the example of
    [Egorov, section 4.1]).

    Actuated ``q1``; the yoke coordinate ``xC`` is the position of its slot line. Points A, B, C (yoke reference on
    the x axis); links ``crank``, ``block``, ``yoke``.
    """
    _check_positive("scotch_yoke", l1=l1)
    B = np.array([l1 * math.cos(q1), l1 * math.sin(q1)])
    b = PlanarBuilder("scotch_yoke")
    b.point("A", GROUND, (0.0, 0.0))
    crank = b.revolute("crank", "A", toward=B, coordinate="q1", mass=1.0, com=(0.0, 0.0), inertia=1e-3)
    b.point("B", crank, B)
    block = b.revolute("block", "B", coordinate="block_angle", mass=0.2, com=B, inertia=1e-4)
    b.point("B_block", block, B, direction=(0.0, 1.0), report=False)
    yoke = b.prismatic("yoke", "A", (1.0, 0.0), reference=B[0], coordinate="xC", mass=2.0, com=(B[0], 0.0))
    b.point("C", yoke, (B[0], 0.0))
    b.point("slot", yoke, (B[0], 0.0), direction=(0.0, 1.0), report=False)
    b.slider("B_block", "slot", lock_angle=True)
    b.line("crank", "A", "B")
    b.line("yoke", "slot", "C", kind="slider")
    params = {"l1": Parameter("l1", l1, "length", "crank AB")}
    return b.build(actuated=["q1"], description=f"scotch-yoke (sine) mechanism, crank l1 = {l1:g} m",
                   parameters=params, tool="C", rebuild=lambda v: scotch_yoke(v["l1"], q1))


def slotted_link(l1: float = 0.1, d: float = 0.3, q1: float = math.pi / 3) -> Mechanism:
    """Slotted-link (coulisse) mechanism: crank AB = l1 about A, a block on the crank pin B slides along the slotted
    link, which turns about C = (d, 0) [Egorov, figs. 4.5, 4.6]; d > l1 gives an oscillating, d < l1 a rotating link.

    The book's angle β at C between CA and CB obeys tan β = l1 sin q1 / (d − l1 cos q1); the link's
    counter-clockwise angle is ``phi3`` = π − β. Actuated ``q1``. Points A, B, C; links ``crank``, ``block``,
    ``coulisse``.
    """
    _check_positive("slotted_link", l1=l1, d=d)
    if abs(d - l1) < 1e-9:
        raise InputError("slotted_link: d = l1 puts the crank pin on the pivot C")
    B = np.array([l1 * math.cos(q1), l1 * math.sin(q1)])
    C = np.array([d, 0.0])
    b = PlanarBuilder("slotted_link")
    b.point("A", GROUND, (0.0, 0.0))
    b.point("C", GROUND, C)
    crank = b.revolute("crank", "A", toward=B, coordinate="q1", mass=1.0, com=(0.0, 0.0), inertia=1e-3)
    b.point("B", crank, B)
    block = b.revolute("block", "B", toward=C, coordinate="block_angle", mass=0.2, com=B, inertia=1e-4)
    b.point("B_block", block, B, direction=C - B, report=False)
    reach = max(l1 + d, 1e-3)
    coulisse = b.revolute("coulisse", "C", toward=B, coordinate="phi3", mass=2.0,
                          com=C + 0.5 * reach * (B - C) / np.linalg.norm(B - C), inertia=2.0 * reach**2 / 12)
    b.point("slot", coulisse, C, direction=B - C, report=False)
    b.point("slot_end", coulisse, C + reach * (B - C) / np.linalg.norm(B - C), report=False)
    b.slider("B_block", "slot", lock_angle=True)
    b.line("crank", "A", "B")
    b.line("coulisse", "C", "slot_end")
    params = {"l1": Parameter("l1", l1, "length", "crank AB"),
              "d": Parameter("d", d, "length", "distance AC between the pivots")}
    kind = "oscillating" if d > l1 else "rotating"
    return b.build(actuated=["q1"], description=f"slotted-link mechanism ({kind}), l1 = {l1:g} m, AC = {d:g} m",
                   parameters=params, tool="B", rebuild=lambda v: slotted_link(v["l1"], v["d"], q1))
