r"""Two-cylinder planar seven-link mechanism of Shi Jinfa and Liang Xichang [ShiLiang].

Seven links, six revolute pins and two sliders, W = 3·6 − 2·8 = 2: the frame with the pins A, E, F (G is a point of
the fixed link AG), the boom ``ABC`` turning about A, the output link ``CD`` pinned to the boom at C (with the point
H fixed to it: CH = l3 at the angle α0 = ∠HCI from CD, and I on CD with HI = l4), and the two hydraulic cylinders
BF (length s1, input ``s1``) and DE (length s2, input ``s2``). Lengths of [ShiLiang, table 1] (mm): l1 = AG 800,
l2 = AC 585, l3 = CH 375, l4 = HI 450, l5 = CD 200, l6 = BC 460, l7 = AB 160, l8 = AE 165, l9 = EG 675,
l10 = AF 565, l11 = FG 250; the garbled row of that table reads s1min = 520, s2min = 565, V1 = 5, V2 = 6 mm/s and
α0 = 98.5°.

The geometry (the figures are missing) is reconstructed from the paper's formulas: E and F on the same side of AG,
AB beyond AE seen from AF, AC beyond AB, A and D on opposite sides of CE, H beyond D. The model is in SI units
(metres; the paper's millimetres / 1000). The strokes are not given: 0.2 m for both cylinders (illustrative).

[ShiLiang, table 2] (t = 0): the mechanism reproduces V_C = 18.462 mm/s, which is V1·l2/e with the lever arm
e = l7 sin∠ABF [ShiLiang, 3–4]. Its other values (V_D = 18.774, β1 = 13.48°, ω_CD = 0.007124, V_H = 21.006,
β2 = 16.511°) do not follow from the stated data with V2 = 6 mm/s — the paper's own closed forms give the same as
this model (21.194, 73.555°, 0.038095, 32.315, 8.189°); the comparison is in the test suite's
``validation/seven_bar.py``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from ..model.mechanism import Mechanism, Parameter
from ..model.planar import GROUND, PlanarBuilder

MM = 1e-3


@dataclass(frozen=True)
class SevenBarData:
    """[ShiLiang, table 1] (metres, m/s, degrees)."""

    l1: float = 800 * MM  # AG
    l2: float = 585 * MM  # AC
    l3: float = 375 * MM  # CH
    l4: float = 450 * MM  # HI
    l5: float = 200 * MM  # CD
    l6: float = 460 * MM  # BC
    l7: float = 160 * MM  # AB
    l8: float = 165 * MM  # AE
    l9: float = 675 * MM  # EG
    l10: float = 565 * MM  # AF
    l11: float = 250 * MM  # FG
    s1_min: float = 520 * MM
    s2_min: float = 565 * MM
    stroke1: float = 200 * MM
    stroke2: float = 200 * MM
    v1: float = 5 * MM
    v2: float = 6 * MM
    alpha0_deg: float = 98.5


def _circles(p: NDArray[np.float64], rp: float, q: NDArray[np.float64], rq: float, side: int, what: str
             ) -> NDArray[np.float64]:
    """Intersection of the circles (p, rp) and (q, rq) on the left (side = 1) or right (−1) of p → q."""
    d = q - p
    distance = float(np.linalg.norm(d))
    along = (rp**2 - rq**2 + distance**2) / (2 * distance)
    h2 = rp**2 - along**2
    if h2 < 0:
        raise InputError(f"seven_bar: {what} cannot be assembled (the circles do not meet)")
    u = d / distance
    return p + along * u + side * math.sqrt(h2) * np.array([-u[1], u[0]])


def pins(data: SevenBarData, s1: float, s2: float) -> dict[str, NDArray[np.float64]]:
    """Pin positions (m) for the cylinder lengths s1, s2: A at the origin, G on +x, E and F above AG."""
    A, G = np.zeros(2), np.array([data.l1, 0.0])
    E = _circles(A, data.l8, G, data.l9, 1, "E")
    F = _circles(A, data.l10, G, data.l11, 1, "F")
    B = _circles(A, data.l7, F, s1, 1, "B")
    C = _circles(A, data.l2, B, data.l6, 1, "C")
    D = _circles(C, data.l5, E, s2, 1, "D")
    ca, cd = A - C, D - C
    sense = math.copysign(1.0, ca[0] * cd[1] - ca[1] * cd[0])  # the turning sense from CA to CD
    angle = math.atan2(cd[1], cd[0]) + sense * math.radians(data.alpha0_deg)  # CH: CD turned on, away from CA
    H = C + data.l3 * np.array([math.cos(angle), math.sin(angle)])
    u = cd / np.linalg.norm(cd)
    w = C - H
    b, c = 2 * u @ w, w @ w - data.l4**2
    if b * b - 4 * c < 0:
        raise InputError("seven_bar: no point I on CD at HI = l4")
    I = C + (-b + math.sqrt(b * b - 4 * c)) / 2 * u
    return {"A": A, "B": B, "C": C, "D": D, "E": E, "F": F, "G": G, "H": H, "I": I}


def seven_bar(**overrides: float) -> Mechanism:
    """Two-cylinder seven-link mechanism [ShiLiang] (inputs: cylinder lengths s1 = BF, s2 = DE, m).

    ``overrides`` are fields of :class:`SevenBarData` (m, m/s, degrees as named)."""
    data = SevenBarData(**overrides)
    p = pins(data, data.s1_min, data.s2_min)
    b = PlanarBuilder("seven_bar")
    for name in ("A", "E", "F", "G"):
        b.point(name, GROUND, p[name])
    boom = b.revolute("ABC", "A", toward=p["C"], coordinate="phi_ABC", mass=60.0, com=(p["A"] + p["B"] + p["C"]) / 3,
                      inertia=60.0 * data.l2**2 / 12)
    b.point("B", boom, p["B"])
    b.point("C", boom, p["C"])
    link = b.revolute("CD", "C", toward=p["D"], coordinate="phi_CD", mass=15.0, com=(p["C"] + p["D"] + p["H"]) / 3,
                      inertia=15.0 * data.l3**2 / 12)
    for name in ("D", "H", "I"):
        b.point(name, link, p[name])
    b.cylinder("s1", "F", "B", stroke=(data.s1_min, data.s1_min + data.stroke1))
    b.cylinder("s2", "E", "D", stroke=(data.s2_min, data.s2_min + data.stroke2))
    b.line("frame", "G", "F", "A", "E", "G", kind="ground")
    b.line("ABC", "A", "B", "C", "A")
    b.line("CD", "C", "D", "I", "H", "C")
    b.transmission_angle("mu_B", "F", "B", "A", "B")
    b.transmission_angle("mu_D", "E", "D", "C", "D")
    params = {name: Parameter(name, float(getattr(data, name)), "length", f"[ShiLiang, table 1] {name}")
              for name in ("l1", "l2", "l3", "l4", "l5", "l6", "l7", "l8", "l9", "l10", "l11", "s1_min", "s2_min")}
    return b.build(actuated=["s1", "s2"], parameters=params, tool="H",
                   description="two-cylinder planar seven-link mechanism (inputs s1 = BF, s2 = DE)",
                   rebuild=lambda v: seven_bar(**{**overrides, **v}),
                   input_rates={"s1": data.v1, "s2": data.v2},
                   notes=["geometry reconstructed from [ShiLiang]; of its table 2 only V_C is reproducible"])
