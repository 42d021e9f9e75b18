"""Ball screws and racks: the equivalent load and L10 life, the critical speed and buckling of the screw shaft with
its end fixing, and the rack's tooth force, against hand calculations; the checks reach the sizing."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

import mechatron
from mechatron.drives.catalogs import default_catalog
from mechatron.drives.checks import DriveLimits, evaluate
from mechatron.drives.converters import converters_for
from mechatron.drives.duty import JointDuty
from mechatron.drives.screws import equivalent_load, screw_life
from mechatron.drives.shafts import END_FIXINGS, critical_speed, end_fixing, euler_load
from mechatron.drives.sizing import size_mechanism
from mechatron.dynamics.task import default_task
from mechatron.errors import InputError

E, RHO = 2.1e11, 7850.0  # steel: Pa, kg/m³

# A BS2010-like screw: C = 9.3 kN, lead 5 mm, root diameter 16.6 mm, fixed at the motor, supported at the far end.
SCREW = pd.DataFrame([{"key": "S", "type": "ball screw", "diameter": 0.020, "lead": 0.005, "efficiency": 0.9,
                       "inertia": 2e-5, "max_speed": 600.0, "dynamic_load": 9300.0, "root_diameter": 0.0166,
                       "end_fixing": "supported-fixed", "max_length": 1.5}])
# A motor strong enough for everything below (N·m, rad/s, kg·m²).
MOTOR = pd.DataFrame([{"key": "M", "rated_torque": 100.0, "peak_torque": 300.0, "rated_speed": 300.0,
                       "max_speed": 600.0, "rotor_inertia": 1e-2}])


def out_and_back(force_out: float, force_back: float, stroke: float = 0.8, samples: int = 20001) -> JointDuty:
    """v = V sin(2πt/T), V = 0.25 m/s, T = 2 s: out for 1 s against force_out, back for 1 s against force_back."""
    t = np.linspace(0.0, 2.0, samples)
    v = 0.25 * np.sin(math.pi * t)
    force = np.where(v >= 0, force_out, -force_back)
    return JointDuty("z", "prismatic", t, v, 0.25 * math.pi * np.cos(math.pi * t), force, force, 5.0, stroke)


def checks_of(duty, linear=SCREW, motors=MOTOR, limits=None):
    evaluation = evaluate(duty, motors, converters_for(duty, linear=linear), limits=limits)
    return {c.name: c for c in evaluation.checks(0, 0)}, evaluation


def test_equivalent_load_and_l10_life_by_hand():
    """Out at 1200 N, back at 400 N, the same revolutions each way:
    F_m = ((1200³ + 400³)/2)^(1/3) = 964.06 N [ISO 3408-5]; L10 = (9300/964.06)³ · 10⁶ = 8.9772e8 revolutions.
    Per 2 s cycle the screw turns ∫|v| dt / p = (2 V T/π)/p = (2 · 0.25 · 2/π)/0.005 = 63.662 times, 31.831 rev/s,
    so L10 lasts 8.9772e8 / 31.831 / 3600 = 7834.1 h. For 20 000 h it needs L_req = 20 000 · 3600 · 31.831 =
    2.2918e9 revolutions, reached at F_m = C (10⁶/L_req)^(1/3) = 705.38 N < 964.06 N: the check fails."""
    duty = out_and_back(1200.0, 400.0)
    assert equivalent_load(duty) == pytest.approx(964.0569, rel=1e-6)
    life = screw_life(duty, 0.005, 9300.0)
    assert life["equivalent_load"] == pytest.approx(((1200**3 + 400**3) / 2) ** (1 / 3), rel=1e-6)
    assert life["l10_revolutions"] == pytest.approx((9300 / 964.0569) ** 3 * 1e6, rel=1e-6)
    assert life["l10_revolutions"] == pytest.approx(8.97720e8, rel=1e-5)
    assert life["revolutions_per_cycle"] == pytest.approx(2 * 0.25 * 2 / math.pi / 0.005, rel=1e-6)
    assert life["l10_hours"] == pytest.approx(7834.08, rel=1e-5)
    checks, _ = checks_of(duty)
    load = checks["screw equivalent load"]
    assert load.value == pytest.approx(964.0569, rel=1e-6)
    assert load.limit == pytest.approx(9300 * (1e6 / (20000 * 3600 * 31.830989)) ** (1 / 3), rel=1e-6)
    assert load.limit == pytest.approx(705.378, rel=1e-5) and not load.passed
    # asking for 7000 h only: L10 = 7834 h is enough, the margin in load is 1 − (7000/7834.08)^(1/3)
    checks, _ = checks_of(duty, limits=DriveLimits(screw_life=7000 * 3600.0))
    assert checks["screw equivalent load"].passed
    assert checks["screw equivalent load"].margin == pytest.approx(1 - (7000 / 7834.08) ** (1 / 3), rel=1e-5)


def test_critical_speed_and_buckling_by_hand():
    """Root diameter 16.6 mm, free length L = stroke + 0.2 m = 1.0 m, fixed–supported (K = 0.7, λ = 3.926602).
    I = π d⁴/64 = 3.7274e-9 m⁴, A = π d²/4: ω_cr = (λ/L)² √(E I/(ρ A)) = 330.95 rad/s (3160 rpm), 80 % allowed:
    264.76 rad/s. Euler: F_E = π² E I/(K L)² = 15 766 N, half allowed: 7883.1 N."""
    duty = out_and_back(1200.0, 400.0)
    checks, _ = checks_of(duty)
    d, L = 0.0166, 1.0
    inertia, area = math.pi * d**4 / 64, math.pi * d**2 / 4
    assert inertia == pytest.approx(3.72737e-9, rel=1e-5)
    omega = (3.926602 / L) ** 2 * math.sqrt(E * inertia / (RHO * area))
    assert omega == pytest.approx(330.946, rel=1e-5)
    speed = checks["screw critical speed"]
    assert speed.limit == pytest.approx(0.8 * omega, rel=1e-9)
    assert speed.value == pytest.approx(0.25 * 2 * math.pi / 0.005, rel=1e-9)  # u V = 314.16 rad/s
    assert not speed.passed  # 314 rad/s is beyond 80 % of the critical speed
    buckling = checks["screw buckling"]
    assert buckling.limit == pytest.approx(math.pi**2 * E * inertia / (0.7 * L) ** 2 / 2, rel=1e-9)
    assert buckling.limit == pytest.approx(7883.07, rel=1e-5)
    assert buckling.value == pytest.approx(1200.0) and buckling.passed
    length = checks["screw length"]
    assert (length.value, length.limit) == pytest.approx((1.0, 1.5))
    # pinned at both ends the same shaft whirls at (π/3.926602)² of it and buckles at 0.7² of it
    pinned, _ = checks_of(duty, SCREW.assign(end_fixing="pinned-pinned"))
    assert pinned["screw critical speed"].limit == pytest.approx(speed.limit * (math.pi / 3.926602) ** 2)
    assert pinned["screw buckling"].limit == pytest.approx(buckling.limit * 0.7**2)
    # the closed forms of the shafts module: the same numbers by λ² d √(E/ρ)/(4 L²)
    assert critical_speed(d, L, 3.926602) == pytest.approx(omega, rel=1e-12)
    assert euler_load(d, L, 0.7) == pytest.approx(2 * buckling.limit, rel=1e-12)


def test_checks_apply_only_with_their_data():
    duty = out_and_back(1200.0, 400.0)
    bare = SCREW.drop(columns=["dynamic_load", "root_diameter", "end_fixing", "max_length"])
    names = set(checks_of(duty, bare)[0])
    assert not names & {"screw equivalent load", "screw critical speed", "screw buckling", "screw length",
                        "rack tooth force"}
    assert {"peak torque", "max speed", "transmission max input speed"} <= names


def test_rack_tooth_force():
    """A rack and pinion of module 2 (pitch diameter 40 mm, lead π · 40 mm) permits 4 kN at the teeth: 3 kN passes
    (margin 25 %), 5 kN fails by 5/4 and is the failing check reported."""
    rack = pd.DataFrame([{"key": "R", "type": "rack and pinion", "diameter": 0.04, "lead": math.pi * 0.04,
                          "efficiency": 0.96, "inertia": 4e-5, "max_speed": 300.0, "permitted_force": 4000.0}])
    checks, _ = checks_of(out_and_back(3000.0, 1000.0), rack)
    tooth = checks["rack tooth force"]
    assert (tooth.value, tooth.limit) == pytest.approx((3000.0, 4000.0)) and tooth.margin == pytest.approx(0.25)
    assert "screw critical speed" not in checks and "screw equivalent load" not in checks
    _, evaluation = checks_of(out_and_back(5000.0, 1000.0), rack)
    assert evaluation.failed(0, 0) == ["rack tooth force ×1.25"]


def test_the_sizing_checks_the_shipped_screws():
    """The cylindrical robot's prismatic joints with the shipped ball screws: every screw check of the chosen screw
    from its catalog row by hand (free length stroke + 0.2 m, fixed–supported)."""
    mech = mechatron.load("cylindrical_rpp")
    result = size_mechanism(mech, default_task(mech).trajectory)
    catalog = default_catalog("linear").set_index("key")
    for joint in (j for j in result.joints if j.kind == "prismatic"):
        row = catalog.loc[joint.converter]
        checks = {c.name: c for c in joint.checks}
        L, d = joint.duty.stroke + 0.2, row["root_diameter"]
        K, lam = END_FIXINGS[row["end_fixing"]]
        assert (K, lam) == (0.7, 3.926602)
        inertia, area = math.pi * d**4 / 64, math.pi * d**2 / 4
        assert checks["screw critical speed"].limit == pytest.approx(
            0.8 * (lam / L) ** 2 * math.sqrt(E * inertia / (RHO * area)), rel=1e-9)
        assert checks["screw buckling"].limit == pytest.approx(math.pi**2 * E * inertia / (K * L) ** 2 / 2, rel=1e-9)
        assert checks["screw buckling"].value == pytest.approx(np.abs(joint.duty.torque).max())
        force, speed, t = np.abs(joint.duty.torque), np.abs(joint.duty.speed), joint.duty.t
        mean = (np.trapezoid(speed * force**3, t) / np.trapezoid(speed, t)) ** (1 / 3)
        assert checks["screw equivalent load"].value == pytest.approx(mean, rel=1e-9)
        rate = np.trapezoid(speed, t) / (t[-1] - t[0]) / row["lead"]  # rev/s
        assert checks["screw equivalent load"].limit == pytest.approx(
            row["dynamic_load"] * (1e6 / (20000 * 3600 * rate)) ** (1 / 3), rel=1e-9)
        assert (checks["screw length"].value, checks["screw length"].limit) == pytest.approx((L, row["max_length"]))
        assert joint.feasible and all(c.passed for c in joint.checks)


@pytest.mark.parametrize("name, canonical", [("fixed-free", "fixed-free"), ("free-fixed", "fixed-free"),
                                             ("Supported–Fixed", "fixed-pinned"), ("pinned pinned", "pinned-pinned"),
                                             ("clamped-clamped", "fixed-fixed")])
def test_end_fixing_names(name, canonical):
    assert end_fixing(name) == canonical


@pytest.mark.parametrize("name", ["bolted", "free-free", "fixed", "fixed-pinned-free"])
def test_unknown_end_fixing(name):
    with pytest.raises(InputError, match="unknown end fixing"):
        end_fixing(name)
