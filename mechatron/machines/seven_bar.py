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

The reconstruction (:func:`pins`, :func:`seven_bar_spec`) writes the mechanism file ``robots/seven_bar.toml``
(:func:`write_seven_bar`), which ``mechatron.load("seven_bar")`` and every command read; the lengths l1 … l11 are its
named lengths (``--set l7=0.17``). Other table data (``s1_min``, strokes, α0) go through the reconstruction:
``write_seven_bar("my.toml", s1_min=0.53)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from ..model.linkage import BodySpec, JointSpec, LengthSpec, LinkageSpec, MeasureSpec, PointSpec, build_linkage
from ..model.linkage_file import write_linkage_file
from ..model.mechanism import Mechanism
from ..model.planar import GROUND

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


#: The comment at the top of robots/seven_bar.toml.
HEADER = """The two-cylinder planar seven-link mechanism of Shi Jinfa and Liang Xichang [ShiLiang], reconstructed from
the paper's formulas (its figures are missing): written by mechatron.machines.seven_bar.write_seven_bar() from
SevenBarData (the lengths of [ShiLiang, table 1]); do not edit it by hand, change the reconstruction and write it
again. The masses are illustrative and the strokes 0.2 m (the paper gives neither). Inputs: the cylinder lengths
s1 = BF and s2 = DE (m), drawn at s1min = 520 mm and s2min = 565 mm."""


def seven_bar_spec(**overrides: float) -> LinkageSpec:
    """The mechanism file of the seven-link mechanism [ShiLiang] as a :class:`~mechatron.model.linkage.LinkageSpec`:
    the pins of :func:`pins` at s1 = s1min, s2 = s2min (m), the lengths l1 … l11 of [ShiLiang, table 1] as named
    lengths, the boom ABC (60 kg, I = m l2²/12) and the link CD (15 kg, I = m l3²/12) with their centres at the
    centroids of ABC and CDH, cylinders s1 = BF and s2 = DE (inputs, strokes s_min … s_min + stroke).

    ``overrides`` are fields of :class:`SevenBarData` (m, m/s, degrees as named)."""
    data = SevenBarData(**overrides)
    p = pins(data, data.s1_min, data.s2_min)
    names = ("A", "G", "E", "F", "B", "C", "D", "H", "I")
    points = tuple(PointSpec(n, (float(p[n][0]), float(p[n][1]))) for n in names)

    def centroid(*corners: str) -> tuple[float, float]:
        return tuple(float(v) for v in sum(p[c] for c in corners) / len(corners))

    bodies = (BodySpec(GROUND, ("A", "G", "E", "F"), draw=("G", "F", "A", "E", "G")),
              BodySpec("ABC", ("A", "B", "C"), mass=60.0, com=centroid("A", "B", "C"), inertia=60.0 * data.l2**2 / 12,
                       draw=("A", "B", "C", "A")),
              BodySpec("CD", ("C", "D", "H", "I"), mass=15.0, com=centroid("C", "D", "H"),
                       inertia=15.0 * data.l3**2 / 12, draw=("C", "D", "I", "H", "C")))
    joints = (JointSpec("revolute", body="ABC", at="A", coordinate="phi_ABC", toward="C"),
              JointSpec("revolute", body="CD", at="C", coordinate="phi_CD", toward="D"),
              JointSpec("cylinder", name="s1", base="F", eye="B", stroke=(data.s1_min, data.s1_min + data.stroke1)),
              JointSpec("cylinder", name="s2", base="E", eye="D", stroke=(data.s2_min, data.s2_min + data.stroke2)))
    measures = (MeasureSpec("transmission_angle", "mu_B", ("F", "B", "A", "B")),
                MeasureSpec("transmission_angle", "mu_D", ("E", "D", "C", "D")))
    lengths = tuple(LengthSpec(name, (a, b), float(getattr(data, name))) for name, a, b in (
        ("l1", "A", "G"), ("l2", "A", "C"), ("l3", "C", "H"), ("l4", "H", "I"), ("l5", "C", "D"), ("l6", "B", "C"),
        ("l7", "A", "B"), ("l8", "A", "E"), ("l9", "E", "G"), ("l10", "A", "F"), ("l11", "F", "G")))
    return LinkageSpec(
        name="seven_bar", points=points, bodies=bodies, joints=joints, actuated=("s1", "s2"), measures=measures,
        lengths=lengths, description="two-cylinder planar seven-link mechanism (inputs s1 = BF, s2 = DE)",
        source="[ShiLiang, table 1]; geometry reconstructed, masses and strokes illustrative", tool="H",
        input_rates={"s1": data.v1, "s2": data.v2},
        notes=("geometry reconstructed from [ShiLiang]; of its table 2 only V_C is reproducible",))


def seven_bar(**overrides: float) -> Mechanism:
    """Two-cylinder seven-link mechanism [ShiLiang] (inputs: cylinder lengths s1 = BF, s2 = DE, m).

    The mechanism of :func:`seven_bar_spec`, as ``mechatron.load("seven_bar")`` reads it from robots/seven_bar.toml.

    ``overrides`` are fields of :class:`SevenBarData` (m, m/s, degrees as named)."""
    return build_linkage(seven_bar_spec(**overrides))


def write_seven_bar(path: str | Path, **overrides: float) -> Path:
    """Write the mechanism file of :func:`seven_bar_spec` to ``path`` (robots/seven_bar.toml is this with the
    defaults)."""
    return write_linkage_file(seven_bar_spec(**overrides), path, HEADER)
