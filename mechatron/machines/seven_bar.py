r"""Two-cylinder planar seven-link mechanism (seed 004, Shi & Liang; notes seed-linkages.md).

Seven links, six revolute pins and two sliders, W = 3·6 − 2·8 = 2: the frame with the pins A, E, F (G is a point of
the fixed link AG), the boom ``ABC`` turning about A, the output link ``CD`` pinned to the boom at C (with the point
H fixed to it: CH = l3 at the angle α0 = ∠HCI from CD, and I on CD with HI = l4), and the two hydraulic cylinders
BF (length s1, input ``s1``) and DE (length s2, input ``s2``). Lengths of Table 1 (mm): l1 = AG 800, l2 = AC 585,
l3 = CH 375, l4 = HI 450, l5 = CD 200, l6 = BC 460, l7 = AB 160, l8 = AE 165, l9 = EG 675, l10 = AF 565,
l11 = FG 250; the garbled row of Table 1 reads s1min = 520, s2min = 565, V1 = 5, V2 = 6 mm/s and α0 = 98.5°.

The geometry (the figures are missing) is reconstructed from the paper's formulas: E and F on the same side of AG,
AB beyond AE seen from AF, AC beyond AB, A and D on opposite sides of CE, H beyond D. The model is in SI units
(metres; the paper's millimetres / 1000). The strokes are not given: 0.2 m for both cylinders (illustrative).

Table 2 (t = 0): the mechanism reproduces V_C = 18.462 mm/s, which is V1·l2/e with the lever arm
e = l7 sin∠ABF (eq. 3–4). Its other values (V_D = 18.774, β1 = 13.48°, ω_CD = 0.007124, V_H = 21.006, β2 = 16.511°)
do not follow from the stated data with V2 = 6 mm/s — the paper's own closed forms give the same as this model
(21.194, 73.555°, 0.038095, 32.315, 8.189°); see :func:`table2_comparison`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..kinematics.frames import angular_velocity, frame_placement, point_velocity
from ..kinematics.loops import joint_velocity
from ..model.mechanism import Mechanism, Parameter
from ..model.planar import GROUND, PlanarBuilder

MM = 1e-3


@dataclass(frozen=True)
class SevenBarData:
    """Table 1 (metres, m/s, degrees)."""

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


def _circles(p: np.ndarray, rp: float, q: np.ndarray, rq: float, side: int, what: str) -> np.ndarray:
    """Intersection of the circles (p, rp) and (q, rq) on the left (side = 1) or right (−1) of p → q."""
    d = q - p
    distance = float(np.linalg.norm(d))
    along = (rp**2 - rq**2 + distance**2) / (2 * distance)
    h2 = rp**2 - along**2
    if h2 < 0:
        raise InputError(f"seven_bar: {what} cannot be assembled (the circles do not meet)")
    u = d / distance
    return p + along * u + side * math.sqrt(h2) * np.array([-u[1], u[0]])


def pins(data: SevenBarData, s1: float, s2: float) -> dict[str, np.ndarray]:
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
    """Two-cylinder seven-link mechanism of seed 004 (inputs: cylinder lengths s1 = BF, s2 = DE)."""
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
    params = {name: Parameter(name, float(getattr(data, name)), "length", f"Table 1 {name}")
              for name in ("l1", "l2", "l3", "l4", "l5", "l6", "l7", "l8", "l9", "l10", "l11", "s1_min", "s2_min")}
    return b.build(actuated=["s1", "s2"], parameters=params, tool="H",
                   description="two-cylinder planar seven-link mechanism (inputs s1 = BF, s2 = DE)",
                   rebuild=lambda v: seven_bar(**{**overrides, **v}),
                   input_rates={"s1": data.v1, "s2": data.v2},
                   notes=["seed 004; Table 2 reproduces only V_C (see mechatron.machines.seven_bar."
                          "table2_comparison)"])


#: Table 2 of the paper (t = 0), in its units: mm/s, degrees, rad/s.
TABLE2 = {"V_C": 18.462, "V_D": 18.774, "beta1_deg": 13.480, "omega_CD": 0.007124, "V_H": 21.006,
          "beta2_deg": 16.511}


def table2_quantities(mech: Mechanism, v1: float, v2: float) -> dict[str, float]:
    """Table 2's quantities at t = 0 (s1 = s1min, s2 = s2min) for the cylinder speeds v1, v2 (m/s), in the paper's
    units (mm/s, deg, rad/s): β1 is the angle between v_D and the cylinder axis E→D, β2 between v_H and v_C."""
    q = mech.reference_q
    v = joint_velocity(mech, q, {"s1": v1, "s2": v2})
    vel = {p: point_velocity(mech, q, v, p)[:2] for p in ("C", "D", "H")}
    axis = frame_placement(mech, q, "D").translation[:2] - frame_placement(mech, q, "E").translation[:2]

    def angle(a: np.ndarray, b: np.ndarray) -> float:
        return math.degrees(math.acos(np.clip(a @ b / (np.linalg.norm(a) * np.linalg.norm(b)), -1.0, 1.0)))

    return {"V_C": float(np.linalg.norm(vel["C"])) / MM, "V_D": float(np.linalg.norm(vel["D"])) / MM,
            "beta1_deg": angle(vel["D"], axis), "omega_CD": float(angular_velocity(mech, q, v, "CD")[2]),
            "V_H": float(np.linalg.norm(vel["H"])) / MM, "beta2_deg": angle(vel["H"], vel["C"])}


def table2_comparison(mech: Mechanism | None = None) -> list[dict]:
    """Table 2 against this model at V2 = 6 mm/s (the paper's data) and at V2 = 0 (what its V_D, ω_CD and V_H
    correspond to, to within 0.4%), with the reason for each printed value that cannot be reproduced."""
    mech = mech or seven_bar()
    data = SevenBarData()
    stated = table2_quantities(mech, data.v1, data.v2)
    at_rest = table2_quantities(mech, data.v1, 0.0)
    reasons = {
        "V_C": "",
        "V_D": "the model and the paper's own eq. (13)-(14) give 21.194 with V2 = 6 mm/s; with the cylinder DE at "
               "rest (V2 = 0) it is 18.768",
        "beta1_deg": "eq. (14)-(15) force cos β1 = V2/V_D: 71.36° even with the printed V_D; 13.48° would need "
                     "V2 = 18.26 mm/s",
        "omega_CD": "0.038095 with V2 = 6 mm/s (also from eq. 17); 0.007099 with the cylinder DE at rest",
        "V_H": "32.315 with V2 = 6 mm/s (eq. 19 with the sign of its cosine term corrected); 21.000 with DE at rest",
        "beta2_deg": "impossible with the printed magnitudes: |v_H − v_C| = ω_CD·CH = 2.67 mm/s bounds the angle "
                     "between v_H and v_C by 8.32°",
    }
    rows = []
    for key, printed in TABLE2.items():
        digits = 6 if key == "omega_CD" else 3
        rows.append({"quantity": key, "printed": printed, "model": round(stated[key], digits + 3),
                     "model_v2_zero": round(at_rest[key], digits + 3),
                     "reproduced": round(stated[key], digits) == printed, "note": reasons[key]})
    return rows
