"""Write the example catalogs of this folder (servo motors, gearboxes, linear drives, hydraulic
cylinders).

They are representative example data, generated from scaling laws fitted to the general run of industrial
components (not one maker's data): rotor inertia J ≈ 5e-5 · T_rated^1.41 kg·m², peak torque 3–3.5 × rated, mass and
price growing with size. The motors' thermal data (:func:`thermal`) are illustrative too: a two-node model
calibrated on the motor's own ratings. Run ``python catalogs/make_examples.py`` to regenerate them. The textbook's
own tables (rotary tables of table 2.11, gearmotor ranges of section 2.2) are transcribed by hand in their files.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

HERE = Path(__file__).resolve().parent
#: k_t's temperature coefficient of the example motors (1/K): NdFeB magnets (mechatron.drives.thermal).
MAGNET_COEFFICIENT = -0.0011


def motors() -> list[dict]:
    rows = []
    sizes = [0.16, 0.25, 0.32, 0.5, 0.64, 0.9, 1.3, 1.6, 2.0, 2.6, 3.2, 4.5, 5.5, 6.4, 8.0, 9.0, 11.0, 13.0, 15.0,
             18.0, 22.0, 27.0, 36.0, 50.0, 70.0]
    for size in sizes:
        frame = next(f for limit, f in ((0.4, 40), (1.5, 60), (3.5, 80), (7.0, 100), (14.0, 130), (30.0, 155),
                                        (1e9, 190)) if size <= limit)
        for rated_speed in (1500, 2000, 3000, 4500, 6000):
            max_speed = min(8000, rated_speed * 1.6 if size < 10 else rated_speed * 1.35)
            if size > 20 and rated_speed > 3000 or size < 0.5 and rated_speed < 2000:
                continue
            rated = round(size * (1.08 - 0.035 * rated_speed / 1000), 3)
            peak = round(rated * (3.5 if size < 5 else 3.0), 3)
            inertia = 5e-5 * size**1.41 * (1.0 if rated_speed < 4000 else 0.9)
            power = rated * rated_speed * 2 * math.pi / 60
            current = power / 300
            heat = thermal(size, rated, rated_speed * 2 * math.pi / 60, power, current)
            rows.append({
                "key": f"SM{frame}-{size:g}-{rated_speed // 100:02d}", "maker": "example", "series": f"SM{frame}",
                "rated_torque": rated, "peak_torque": peak, "rated_speed_rpm": rated_speed,
                "max_speed_rpm": int(max_speed), "rotor_inertia_kgcm2": round(inertia * 1e4, 4),
                "torque_constant": round(rated / current, 3), "rated_current": round(current, 2),
                "rated_power_W": round(power), **heat, "mass": round(0.7 + 1.1 * size**0.8, 2),
                "price_eur": round(250 + 60 * size**0.85 + 0.02 * rated_speed),
            })
    return rows


def thermal(size: float, rated: float, rated_speed: float, power: float, current: float) -> dict:
    """The thermal columns of a motor (mechatron.drives.thermal): the winding's resistance at 25 °C, the speed loss
    torque and the two-node network, calibrated on the motor's ratings at 40 °C ambient and a 155 °C winding (class
    F). At standstill it gives the torque 1.08 · size continuously, at its rated speed its rated torque (the law of
    rated = size · (1.08 − 0.035 n_r/1000 rpm) above), so the losses at the rated point — a share
    0.16 · size^-0.12 of the rated power — are the copper loss I_r² R(155 °C) and, the rest, the speed loss
    T_f · n_r with the share 1 − (rated / 1.08 size)²; the thermal resistances sum to (155 − 40) K over them, 35 %
    winding → housing, 65 % housing → ambient; the time constants grow with size, τ_w = 15 s · size^0.3,
    τ_h = 600 s · size^0.3. The current I_r = T_r / k_t(T_m) of the torque constant at the magnets' temperature,
    the housing's T_m = 40 °C + 0.65 · 115 K (k_t(T) = k_t₂₅ (1 + β (T − 25 °C)), β = −0.11 %/K: NdFeB, the
    catalog's ``torque_constant_coefficient``), k_t₂₅ = T_r / ``current``."""
    losses = 0.16 * size**-0.12 * power
    speed_share = 1 - (rated / (1.08 * size)) ** 2
    copper = (1 - speed_share) * losses
    total = (155 - 40) / losses
    magnets = 1 + MAGNET_COEFFICIENT * (40 + 0.65 * (155 - 40) - 25)  # k_t(T_m) / k_t₂₅
    return {"resistance_ohm": float(f"{copper * magnets**2 / (current**2 * (1 + 0.0039 * (155 - 25))):.4g}"),
            "loss_torque_Nm": float(f"{speed_share * losses / rated_speed:.4g}"),
            "rth_winding_housing_K_W": float(f"{0.35 * total:.4g}"),
            "rth_housing_ambient_K_W": float(f"{0.65 * total:.4g}"),
            "tau_winding_s": round(15 * size**0.3, 1), "tau_housing_s": round(600 * size**0.3),
            "max_winding_temperature_degC": 155, "torque_constant_coefficient_percent_K": 100 * MAGNET_COEFFICIENT}


#: The planetary gearheads' shock factors by cycles per hour (maker-style, illustrative; docs/catalogs.md, "Gearbox
#: duty"), and the count of the harmonic gears' momentary peak torque.
SHOCK_FACTORS = "1000:1;2000:1.1;3000:1.2;4000:1.3;6000:1.4;10000:1.6"
MOMENTARY_PEAKS = 10000
#: The end of the gearboxes' first line: their peak-torque rules (catalogs/README.md describes them).
GEARBOX_NOTE = "; peak-torque rules maker-style, illustrative (catalogs/README.md)\n"


def gearboxes() -> list[dict]:
    rows = []
    planetary = {  # frame: (rated torque 1-stage N·m, max input rpm, rated input rpm, input inertia kg·cm², mass kg)
        60: (40, 6000, 4000, 0.15, 1.2), 90: (120, 6000, 3500, 0.6, 3.0), 120: (260, 4500, 3000, 2.5, 7.0),
        155: (600, 4000, 2500, 8.0, 16.0), 205: (1200, 3500, 2000, 25.0, 32.0)}
    for frame, (torque, n_max, n_rated, inertia, mass) in planetary.items():
        for ratio in (3, 4, 5, 7, 10, 16, 20, 25, 35, 50, 70, 100):
            stages = 1 if ratio <= 10 else 2
            rated = torque * (1.0 if ratio >= 4 else 0.8) * (1.1 if stages == 2 else 1.0)
            rows.append({
                "key": f"PG{frame}-{ratio}", "maker": "example", "type": "planetary", "stages": stages,
                "ratio": ratio, "rated_torque": round(rated), "peak_torque": round(1.8 * rated),
                "emergency_torque": round(2.5 * rated), "peak_rule": "shock_factors",
                "shock_factors_per_h": SHOCK_FACTORS, "emergency_stops": "", "max_input_speed_rpm": n_max,
                "rated_input_speed_rpm": n_rated, "efficiency": 0.97 if stages == 1 else 0.94,
                "input_inertia_kgcm2": round(inertia * (1.0 if stages == 1 else 0.45) * (1.2 - ratio / 100), 4),
                "backlash_arcmin": 5 if stages == 1 else 7, "mass": round(mass * (1.0 if stages == 1 else 1.3), 1),
                "price_eur": round(300 + 4 * frame + (150 if stages == 2 else 0)),
            })
    harmonic = {14: (7.8, 8000, 2000, 0.033, 0.5), 17: (20, 7000, 2000, 0.079, 0.7), 20: (34, 6000, 2000, 0.193, 1.0),
                25: (55, 5600, 2000, 0.413, 1.5), 32: (140, 4800, 2000, 1.69, 3.0), 40: (260, 4000, 1700, 4.5, 5.0)}
    for size, (torque, n_max, n_rated, inertia, mass) in harmonic.items():
        for ratio in (50, 80, 100, 120, 160):
            rated = torque * (0.8 if ratio == 50 else 1.0)
            rows.append({
                "key": f"HD{size}-{ratio}", "maker": "example", "type": "harmonic", "stages": 1, "ratio": ratio,
                "rated_torque": round(rated, 1), "peak_torque": round(2.8 * rated, 1),
                "emergency_torque": round(5.0 * rated, 1), "peak_rule": "repeated_peak", "shock_factors_per_h": "",
                "emergency_stops": MOMENTARY_PEAKS, "max_input_speed_rpm": n_max,
                "rated_input_speed_rpm": n_rated, "efficiency": 0.78 if ratio < 100 else 0.72,
                "input_inertia_kgcm2": inertia, "backlash_arcmin": 0.5, "mass": mass,
                "price_eur": round(400 + 25 * size),
            })
    for size, torque in ((10, 100), (20, 230), (40, 500)):
        for ratio in (59, 89, 119):
            rows.append({
                "key": f"CY{size}-{ratio}", "maker": "example", "type": "cycloidal", "stages": 2, "ratio": ratio,
                "rated_torque": torque, "peak_torque": 2 * torque, "emergency_torque": 5 * torque, "peak_rule": "",
                "shock_factors_per_h": "", "emergency_stops": "",
                "max_input_speed_rpm": 4500, "rated_input_speed_rpm": 2000, "efficiency": 0.85,
                "input_inertia_kgcm2": round(0.02 * size, 3), "backlash_arcmin": 1, "mass": round(0.15 * size, 1),
                "price_eur": 600 + 30 * size,
            })
    return rows


def linear_drives() -> list[dict]:
    """Ball screws: rolled steel shafts, the ball size of the common nuts, root diameter d - 0.85 d_ball, fixed at the
    motor end and supported at the other, the longest shafts rolled. Racks and pinions: the permitted tangential
    force of a hardened rack, about 100 N per mm² of module × face width."""
    rows = []
    for diameter, leads, load, longest in ((16, (5, 10, 16), 9.3, 1500), (20, (5, 10, 20), 14.0, 2500),
                                           (25, (5, 10, 25), 17.5, 3000), (32, (5, 10, 20, 32), 26.0, 4000),
                                           (40, (10, 20, 40), 38.0, 5000)):
        d = diameter / 1000
        inertia = 7850 * math.pi * d**4 / 32  # kg·m² per metre of steel shaft
        for lead in leads:
            ball = 3.175 if lead == 5 or diameter == 16 else 3.969 if diameter <= 25 and lead != 10 or \
                diameter == 20 else 4.762 if diameter == 25 else 6.35
            rows.append({
                "key": f"BS{diameter}{lead:02d}", "maker": "example", "type": "ball screw", "diameter_mm": diameter,
                "lead_mm": lead, "efficiency": 0.9, "inertia_kgcm2": "", "inertia_per_length_kgcm2_m":
                round(inertia * 1e4, 4), "max_speed_rpm": min(5000, int(70000 / diameter)), "dynamic_load_kN": load,
                "root_diameter_mm": round(diameter - 0.85 * ball, 1), "end_fixing": "fixed-pinned",
                "max_length_mm": longest, "permitted_force_kN": "",
                "mass": "", "mass_per_length_kg_m": round(7850 * math.pi * d**2 / 4, 2), "price_eur": 80 + 6 * diameter,
            })
    for module, teeth, width in ((2, 20, 20), (2, 30, 20), (3, 20, 30), (3, 30, 30), (4, 20, 40)):
        d = module * teeth / 1000  # pitch diameter (m); travel per pinion turn π d
        pinion = 7850 * math.pi / 32 * d**4 * width / 1000  # steel disc
        rows.append({
            "key": f"RP{module}-{teeth}", "maker": "example", "type": "rack and pinion", "diameter_mm": d * 1000,
            "lead_mm": round(math.pi * d * 1000, 3), "efficiency": 0.96, "inertia_kgcm2": round(pinion * 1e4, 4),
            "inertia_per_length_kgcm2_m": "", "max_speed_rpm": 3000, "dynamic_load_kN": "",
            "root_diameter_mm": "", "end_fixing": "", "max_length_mm": "",
            "permitted_force_kN": round(0.1 * module * width, 1),
            "mass": round(7850 * math.pi / 4 * d**2 * width / 1000, 2),
            "mass_per_length_kg_m": round(7850 * (module * 10 / 1000) ** 2 * 1.5, 2), "price_eur": 150 + 40 * module,
        })
    return rows


def cylinders() -> list[dict]:
    """Double-acting cylinders of the bores and rods of ISO 3320, rated 25 and 32 MPa, with an eye at each end."""
    rows = []
    for bore, rod in ((40, 22), (50, 28), (63, 36), (80, 45), (100, 56), (125, 70), (140, 90), (160, 100),
                      (180, 110), (200, 125), (220, 140), (250, 160), (280, 180), (320, 200)):
        D, d = bore / 1000, rod / 1000
        for pressure in (25, 32):
            wall = D * (0.10 if pressure == 25 else 0.125)  # tube wall from the hoop stress
            per_metre = 7850 * math.pi / 4 * ((D + 2 * wall) ** 2 - D**2 + d**2)
            rows.append({
                "key": f"HC{bore}/{rod}-{pressure}", "maker": "example", "bore_mm": bore, "rod_mm": rod,
                "max_stroke_mm": 1500 if bore < 100 else 3000 if bore < 200 else 4000, "max_pressure_MPa": pressure,
                "end_fixing": "pinned-pinned",
                "mass": round(7850 * 2.4 * D**3 + 0.5, 1), "mass_per_stroke": round(per_metre, 1),
                "price_eur": round(200 + 0.08 * bore**2 * (1.15 if pressure == 32 else 1.0)),
            })
    return rows


def write(name: str, rows: list[dict], header: str) -> None:
    with (HERE / name).open("w", newline="") as fh:
        fh.write(header)
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)


if __name__ == "__main__":
    note = "# example data from catalogs/make_examples.py (scaling laws, not one maker's data)\n"
    write("servo_motors.csv", motors(), note)
    write("gearboxes.csv", gearboxes(), note.rstrip("\n") + GEARBOX_NOTE)
    write("linear_drives.csv", linear_drives(), note)
    write("hydraulic_cylinders.csv", cylinders(), note)
