r"""The seven-link paper's Table 2 [ShiLiang, table 2] and its own closed forms [ShiLiang, 3–20] against the
closed-loop model of robots/seven_bar.toml (the reconstruction of :mod:`mechatron.machines.seven_bar`).

Only V_C of Table 2 is reproducible. The paper's closed forms, read through the text extraction's digit swaps
(1↔7, 6↔9, 3↔8: ∠ABF with l10, CE with l2 and l8, (13) with V_C, (17) with l5 = CD, (19) with the sign of its cosine
term for H beyond D), agree with the model, and both disagree with the printed V_D, β1, ω_CD, V_H and β2. The three
of them that are speeds correspond to the same mechanism with the cylinder DE at rest; β1 and β2 contradict the
paper's own equations (:func:`table2_comparison` gives the reasons).
"""

from __future__ import annotations

import math

import numpy as np

from mechatron.kinematics.frames import angular_velocity, frame_placement, point_velocity
from mechatron.kinematics.loops import joint_velocity
from mechatron.machines.seven_bar import MM, SevenBarData, seven_bar
from mechatron.model.mechanism import Mechanism

#: [ShiLiang, table 2] (t = 0), in its units: mm/s, degrees, rad/s.
TABLE2 = {"V_C": 18.462, "V_D": 18.774, "beta1_deg": 13.480, "omega_CD": 0.007124, "V_H": 21.006,
          "beta2_deg": 16.511}


def law_of_cosines(a: float, b: float, opposite: float) -> float:
    """The angle (rad) between the sides a and b of a triangle with the third side ``opposite``."""
    return math.acos((a * a + b * b - opposite * opposite) / (2 * a * b))


def paper_closed_forms(v1: float = 5.0, v2: float = 6.0) -> dict[str, float]:
    """Table 2's quantities from the paper's closed forms [ShiLiang, 3–20] at t = 0, in its units (lengths mm,
    cylinder speeds ``v1``, ``v2`` and the results in mm/s, degrees, rad/s), as read (see the module docstring)."""
    l1, l2, l3, l5, l7, l8, l9, l10, l11, s1, s2 = 800, 585, 375, 200, 160, 165, 675, 565, 250, 520, 565
    alpha1 = law_of_cosines(l7, l2, 460)  # ∠BAC from the triangle ABC
    abf = law_of_cosines(l7, s1, l10)  # (3)
    e = l7 * math.sin(abf)
    vc = l2 * v1 / e  # (4)
    alpha2 = law_of_cosines(l7, l10, s1) - (law_of_cosines(l8, l1, l9) - law_of_cosines(l10, l1, l11))
    lce = math.sqrt(l2**2 + l8**2 - 2 * l2 * l8 * math.cos(alpha1 + alpha2))
    a3, a4, a5 = law_of_cosines(l2, lce, l8), law_of_cosines(l5, lce, s2), law_of_cosines(l5, s2, lce)
    a = a3 + a4
    theta2 = math.atan(v2 * math.sin(a5) / (v2 * math.cos(a5) + vc * math.sin(a)))  # (13)
    vd = v2 / math.sin(theta2)  # (14)
    vdc = vd * math.sin(a + a5 - theta2) / math.sin(a)  # (16)
    w = vdc / l5  # (17)
    vhc = w * l3
    vh = math.sqrt(vc**2 + vhc**2 - 2 * vc * vhc * math.cos(a + math.radians(98.5)))  # (19), sign corrected
    beta2 = math.degrees(math.acos((vh**2 + vc**2 - vhc**2) / (2 * vh * vc)))  # (20)
    return {"V_C": vc, "V_D": vd, "beta1_deg": 90 - math.degrees(theta2), "omega_CD": w, "V_H": vh,
            "beta2_deg": beta2}


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
    """[ShiLiang, table 2] against the model at V2 = 6 mm/s (the paper's data) and at V2 = 0 (what its V_D, ω_CD and
    V_H correspond to, to within 0.4 %), with the reason for each printed value that cannot be reproduced. Rows:
    quantity, printed, model, model_v2_zero, reproduced, note (the paper's units)."""
    mech = mech or seven_bar()
    data = SevenBarData()
    stated = table2_quantities(mech, data.v1, data.v2)
    at_rest = table2_quantities(mech, data.v1, 0.0)
    reasons = {
        "V_C": "",
        "V_D": "the model and the paper's own (13)-(14) give 21.194 with V2 = 6 mm/s; with the cylinder DE at "
               "rest (V2 = 0) it is 18.768",
        "beta1_deg": "(14)-(15) force cos β1 = V2/V_D: 71.36° even with the printed V_D; 13.48° would need "
                     "V2 = 18.26 mm/s",
        "omega_CD": "0.038095 with V2 = 6 mm/s (also from (17)); 0.007099 with the cylinder DE at rest",
        "V_H": "32.315 with V2 = 6 mm/s ((19) with the sign of its cosine term corrected); 21.000 with DE at rest",
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
