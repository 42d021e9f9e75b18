"""The drive data of a robot file load the joint in the sizing (issue 25, item 4): the friction of a ``drive`` table,
seen at the joint through its gear ratio, τ_f = u (B u q̇ + T_c±), is added to the joint torque with the sign of the
speed; its efficiency multiplies the candidate converter's; its rotor inertia gives way to the candidate's.

The case: a disc of 0.5 kg·m² on a vertical axis (no gravity torque) moves 2 rad in 1.2 s (trapezoid, 2 rad/s,
10 rad/s²), driven directly (u = 1, η = 1) by motors of rotor inertia J_m = 1e-3 kg·m². The file's drive: u = −10,
B = 2e-3 N·m·s/rad, T_c = [0.3, −0.5] N·m. The motor turns the other way (u q̇ < 0 for q̇ > 0), so T_c− acts:
τ_f = −10 (2e-3 · (−10) q̇ − 0.5) = 0.2 q̇ + 5 N·m for q̇ > 0, 0.2 q̇ − 3 N·m for q̇ < 0. The motor torque
T = K q̈ + τ_f with K = J_m + 0.5, and its mean square over the cycle in closed form (a = K α + C, b = B_q α):

    accelerating (0.2 s):  ∫ (a + b t)² dt = a² t_a + a b t_a² + b² t_a³/3,
    cruising (0.8 s):      (B_q v + C)² t_c,
    braking (0.2 s):       a' = −K α + B_q v + C, b' = −B_q α, the same integral;

without friction (K α)² (2 t_a) / T.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import mechatron
from mechatron.drives.checks import evaluate
from mechatron.drives.converters import converters_for
from mechatron.drives.duty import joint_duties
from mechatron.dynamics.motion import move
from mechatron.dynamics.tree import inverse_dynamics

T_A, T_C, ALPHA, V = 0.2, 0.8, 10.0, 2.0  # s, s, rad/s², rad/s
DURATION = 2 * T_A + T_C
J_DISC, J_M = 0.5, 1e-3
B_Q, C_POS, C_NEG = 2e-3 * 10**2, 5.0, -3.0  # the file's friction at the joint
ROBOT = """name = "{name}"
[[links]]
joint = "revolute"
lower_deg = -180.0
upper_deg = 180.0
inertia = {{ xx = 0.25, yy = 0.25, zz = 0.5 }}
drive = {{ {drive} }}
"""
FRICTION = "rotor_inertia = 1e-3, gear_ratio = -10.0, viscous_friction = 2e-3, coulomb_friction = [0.3, -0.5]"
MOTORS = pd.DataFrame([{"key": key, "rated_torque": rated, "peak_torque": 40.0, "rated_speed": 300.0,
                        "max_speed": 500.0, "rotor_inertia": J_M, "mass": mass, "price": 100.0 * mass}
                       for key, rated, mass in (("A", 3.2, 1.0), ("B", 8.0, 2.0), ("C", 20.0, 4.0))])


def robot(tmp_path: Path, name: str, drive: str) -> mechatron.model.Mechanism:
    path = tmp_path / f"{name}.toml"
    path.write_text(ROBOT.format(name=name, drive=drive), encoding="utf-8")
    return mechatron.load(path)


def trapezoid(mech, start=0.0, end=2.0):
    return move(mech, [start], [end], profile="trapezoidal", vmax=V, amax=ALPHA, dt=1e-4)


def mean_square(k: float, b: float = 0.0, c: float = 0.0) -> float:
    """⟨T²⟩ of T = k q̈ + b q̇ + c (q̇ > 0) over the trapezoid, in closed form (the module docstring)."""
    def phase(a0: float, slope: float) -> float:
        return a0**2 * T_A + a0 * slope * T_A**2 + slope**2 * T_A**3 / 3

    return (phase(k * ALPHA + c, b * ALPHA) + (b * V + c) ** 2 * T_C + phase(-k * ALPHA + b * V + c, -b * ALPHA)) \
        / DURATION


def rms_values(duty) -> np.ndarray:
    """The RMS torque check's value for every motor driving the joint directly."""
    evaluation = evaluate(duty, MOTORS, converters_for(duty, None))
    return evaluation.values[:, 0, 2]


def test_the_friction_is_added_at_the_joint_with_the_sign_of_the_speed(tmp_path):
    """Forward and back: duty torque − the dynamics without the file's armature = 0.2 q̇ + 5 (q̇ > 0), 0.2 q̇ − 3
    (q̇ < 0), 0 at rest; the file's rotor inertia is not in it (the candidate brings its own)."""
    mech = robot(tmp_path, "rough", FRICTION)
    assert mech.model.armature[0] == pytest.approx(1e-3 * 100)  # J_rotor u², in the file's own dynamics
    for start, end in ((0.0, 2.0), (2.0, 0.0)):
        tr = trapezoid(mech, start, end)
        (duty,) = joint_duties(mech, tr)
        bare = J_DISC * tr.a[:, 0]  # the disc alone: no gravity about a vertical axis, no armature
        assert np.allclose(inverse_dynamics(mech, tr.q, tr.v, tr.a)[:, 0] - 0.1 * tr.a[:, 0], bare, atol=1e-9)
        qd = tr.v[:, 0]
        friction = B_Q * qd + np.where(qd > 0, C_POS, np.where(qd < 0, C_NEG, 0.0))
        assert np.allclose(duty.torque, bare + friction, rtol=0, atol=1e-9)
        assert duty.friction == pytest.approx((B_Q, C_POS, C_NEG), rel=1e-15)
        assert np.array_equal(duty.static_torque, np.zeros_like(qd))  # at rest: no friction, no gravity
        assert (qd > 0).any() if end > start else (qd < 0).any()


def test_large_friction_sizes_differently_by_its_own_rms(tmp_path):
    """The acceptance test: the same disc with and without the file's friction. The RMS check of every motor is the
    closed-form √⟨T²⟩ (1e-3: the task sampled every 0.1 ms) — without friction √⟨(K q̈)²⟩ = 2.893 N·m, with it
    6.07 N·m; their squares differ by the friction's own part, ⟨τ_f²⟩ + 2⟨K q̈ τ_f⟩ — and the sizing chooses the
    lightest motor whose S1 torque holds it: A (3.2 N·m) without friction, B (8 N·m) with it."""
    smooth, rough = robot(tmp_path, "smooth", "rotor_inertia = 1e-3, gear_ratio = -10.0"), \
        robot(tmp_path, "rough", FRICTION)
    k = J_M + J_DISC
    without, with_friction = math.sqrt(mean_square(k)), math.sqrt(mean_square(k, B_Q, C_POS))
    assert without == pytest.approx(2.893, abs=5e-4) and with_friction == pytest.approx(6.07, abs=5e-3)
    values = {}
    for name, mech, expected in (("smooth", smooth, without), ("rough", rough, with_friction)):
        (duty,) = joint_duties(mech, trapezoid(mech))
        values[name] = rms_values(duty)
        assert values[name] == pytest.approx(np.full(3, expected), rel=1e-3), name
    own = mean_square(k, B_Q, C_POS) - mean_square(k)
    assert values["rough"] ** 2 - values["smooth"] ** 2 == pytest.approx(np.full(3, own), rel=2e-3)
    sized = {name: mechatron.size(mech, trapezoid(mech), motors=MOTORS, gearboxes=pd.DataFrame(),
                                  inertia_ratio_max=1e3)
             for name, mech in (("smooth", smooth), ("rough", rough))}
    assert [j.choice() for j in sized["smooth"].joints] == ["A + direct"]
    assert [j.choice() for j in sized["rough"].joints] == ["B + direct"]
    for name, expected in (("smooth", without), ("rough", with_friction)):
        (joint,) = sized[name].joints
        rms = next(c for c in joint.checks if c.name == "RMS torque")
        assert rms.value == pytest.approx(expected, rel=1e-3)
        assert rms.value == values[name][1 if name == "rough" else 0]  # the sizing's own check, bit for bit
    # and the peak: K α + B_q V + C at the end of the acceleration, against K α without friction
    peak = next(c for c in sized["rough"].joints[0].checks if c.name == "peak torque")
    assert peak.value == pytest.approx(k * ALPHA + B_Q * V + C_POS, rel=1e-3)


def test_the_file_efficiency_is_a_factor_of_the_chain(tmp_path):
    """A lossy file drive (η_f = 0.8, no friction) through a direct drive: T = J_m q̈ + J_disc q̈ / 0.8 while the
    load takes power (accelerating), J_m q̈ + 0.8 J_disc q̈ while it gives it back (braking): RMS
    √((6.26² + 4.01²) · 0.2/1.2); with a chain efficiency of 0.95, direct drive counts 0.95 · 0.8 and a gearbox
    of η 0.9 counts 0.9 · 0.95 · 0.8."""
    mech = robot(tmp_path, "lossy", "gear_ratio = 5.0, efficiency = 0.8")
    (duty,) = joint_duties(mech, trapezoid(mech))
    assert duty.efficiency == 0.8 and duty.friction == (0.0, 0.0, 0.0)
    accelerating, braking = J_M * ALPHA + J_DISC * ALPHA / 0.8, J_M * ALPHA + 0.8 * J_DISC * ALPHA
    assert (accelerating, braking) == pytest.approx((6.26, 4.01))
    expected = math.sqrt((accelerating**2 + braking**2) * T_A / DURATION)
    assert rms_values(duty) == pytest.approx(np.full(3, expected), rel=1e-3)
    gearbox = pd.DataFrame([{"key": "G", "type": "planetary", "ratio": 10.0, "rated_torque": 50.0,
                             "peak_torque": 100.0, "emergency_torque": 900.0, "max_input_speed": 600.0,
                             "rated_input_speed": 400.0, "efficiency": 0.9, "input_inertia": 0.0}])
    conv = converters_for(duty, gearbox, chain_efficiency=0.95)
    assert conv.efficiency.tolist() == pytest.approx([0.95 * 0.8, 0.9 * 0.95 * 0.8], rel=1e-15)
