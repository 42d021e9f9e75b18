"""The electrical side of a sizing: the braking energy of a lowered load against its energy balance, the common DC
bus against the closed-form powers, the motor current and the voltage limit, the emergency-stop limit, and the
optional electrical catalog columns."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
from protocol import check_result
from scipy.integrate import quad
from scipy.optimize import brentq

import mechatron
from mechatron.drives.checks import DriveLimits, evaluate
from mechatron.drives.converters import converters_for
from mechatron.drives.duty import JointDuty
from mechatron.drives.electrical import electrical, positive_energy
from mechatron.drives.motor import terminal_voltage, voltage_limit_speed, voltage_limited_torque
from mechatron.drives.sizing import size_mechanism
from mechatron.dynamics.motion import Trajectory
from mechatron.errors import InputError
from mechatron.model.dh import DHLink, DHTable, Inertial, dh_mechanism

# ------------------------------------------------------------------------------------------ the lift axis
# A 20 kg carriage on a vertical prismatic joint (z up), driven through a ball screw of lead 10 mm (u = 2π/0.01
# rad/m), efficiency η = 0.9 and inertia J_c = 2e-5 kg·m², by a motor of rotor inertia J_m = 5e-5 kg·m², k_t = 0.5
# N·m/A, R = 3 Ω on a 400 V supply. It is lowered (or raised) along v = ∓V sin(ωt), ω = π/T, V = 0.2 m/s, T = 1 s.
M, V, T = 20.0, 0.2, 1.0
LEAD, ETA, JC = 0.01, 0.9, 2e-5
JM, KT, R, U = 5e-5, 0.5, 3.0, 400.0
W, RATIO = math.pi / T, 2 * math.pi / LEAD

MOTOR = pd.DataFrame([{"key": "M", "rated_torque": 0.64, "peak_torque": 1.91, "rated_speed": 314.0,
                       "max_speed": 628.0, "rotor_inertia": JM, "torque_constant": KT, "resistance": R,
                       "voltage": U, "mass": 1.0}])
SCREW = pd.DataFrame([{"key": "S", "type": "ball screw", "diameter": 0.016, "lead": LEAD, "efficiency": ETA,
                       "inertia": JC, "max_speed": 500.0, "dynamic_load": 9300.0, "root_diameter": 0.0133,
                       "end_fixing": "fixed-pinned"}])


def lift():
    link = DHLink("prismatic", name="z", lower=-1.0, upper=1.0,
                  inertial=Inertial(M, np.zeros(3), np.diag([0.1, 0.1, 0.1])))
    return dh_mechanism(DHTable((link,)), "lift")


def gravity(mech) -> float:
    return -float(mech.model.gravity.linear[2])


def sized(direction: float, motors=MOTOR, samples: int = 10001):
    """The lift sized lowering (direction −1) or raising (+1) the carriage."""
    mech = lift()
    t = np.linspace(0.0, T, samples)
    z = direction * V / W * (1 - np.cos(W * t))
    v, a = direction * V * np.sin(W * t), direction * V * W * np.cos(W * t)
    result = size_mechanism(mech, Trajectory(t, z[:, None], v[:, None], a[:, None], ["z"]), motors, linear=SCREW)
    return mech, result


def hand_power(direction: float, g: float):
    """The motor torque, speed and electrical power of the lift as closed forms of t.

    Force on the carriage F = m (a + g) > 0; lowering, F v < 0: the screw is driven back and passes η F to the
    motor; raising, and holding at rest (v = 0, at t = 0), the motor passes F / η [Egorov, 4.59].
    T_m = (J_m + J_c) u a + F*/u, n = u v, P = T_m n + R (T_m / k_t)²."""
    J = JM + JC

    def torque(t):
        a, v = direction * V * W * math.cos(W * t), direction * V * math.sin(W * t)
        force = M * (a + g)
        carried = force * ETA if force * v < 0 else force / ETA
        return J * RATIO * a + carried / RATIO

    def speed(t):
        return RATIO * direction * V * math.sin(W * t)

    return torque, speed, lambda t: torque(t) * speed(t) + R * (torque(t) / KT) ** 2


def test_braking_energy_equals_the_energy_balance():
    """Lowering the carriage, the motor gives back power from t1 to t2 (where T_m n + R I² < 0). Over that interval
    T_m n = d/dt [½ (J_m + J_c) (u v)²] + η d/dt [½ m v² + m g z] (the screw passes η of the carriage's power), so the
    energy given back is the drop of the rotor's kinetic energy plus η × the drop of the carriage's kinetic and
    potential energy, minus the copper loss ∫ R I² dt, with I = T_m/k_t and T_m = c0 + c1 cos ωt."""
    mech, result = sized(-1.0)
    g = gravity(mech)
    torque, speed, power = hand_power(-1.0, g)
    t1, t2 = brentq(power, 1e-9, T / 2), brentq(power, T / 2, T - 1e-9)
    J = JM + JC
    c0 = ETA * M * g / RATIO
    c1 = -(J * RATIO + ETA * M / RATIO) * V * W
    assert torque(0.3) == pytest.approx(c0 + c1 * math.cos(W * 0.3), rel=1e-12)

    def rotor(t):  # ½ (J_m + J_c) n²
        return 0.5 * J * speed(t) ** 2

    def carriage(t):  # ½ m v² + m g z, z = −V/ω (1 − cos ωt)
        return 0.5 * M * (V * math.sin(W * t)) ** 2 - M * g * V / W * (1 - math.cos(W * t))

    def square(t):  # ∫_0^t (c0 + c1 cos ωs)² ds
        return c0**2 * t + 2 * c0 * c1 * math.sin(W * t) / W + c1**2 * (t / 2 + math.sin(2 * W * t) / (4 * W))

    copper = R / KT**2 * (square(t2) - square(t1))
    balance = (rotor(t1) - rotor(t2)) + ETA * (carriage(t1) - carriage(t2)) - copper
    assert 20.0 < balance < 23.0  # ≈ 0.9 × m g × 0.127 m: what a 20 kg load gives back lowered 12.7 cm
    balance_of = electrical(result)
    axis = balance_of.to_frame().iloc[0]
    assert axis["energy_regenerated"] == pytest.approx(balance, rel=1e-6)
    # a single axis: the bus sees the same; the continuous braking power is the energy per cycle over the cycle
    bus = balance_of.bus()
    assert bus["energy_regenerated"] == pytest.approx(axis["energy_regenerated"], rel=1e-12)
    assert bus["continuous_braking_power"] == pytest.approx(balance / T, rel=1e-6)
    # peak braking power: max of −P over the samples of the closed form
    t = result.joints[0].duty.t
    assert bus["peak_braking_power"] == pytest.approx(max(-power(s) for s in t), rel=1e-9)


def test_current_and_voltage_from_the_torque_constant():
    """I = T_m/k_t: the largest |T_m| is c0 + |c1| at t = T (cos ωT = −1); the voltage check is the largest
    k_t |n| + R |T_m| / k_t over the samples, from the closed forms."""
    mech, result = sized(-1.0)
    torque, speed, _ = hand_power(-1.0, gravity(mech))
    t = result.joints[0].duty.t
    row = electrical(result).to_frame().iloc[0]
    assert row["peak_current"] == pytest.approx(abs(torque(T)) / KT, rel=1e-9)
    rms = math.sqrt(np.trapezoid([(torque(s) / KT) ** 2 for s in t], t) / T)  # the time mean over the samples
    assert row["rms_current"] == pytest.approx(rms, rel=1e-9)
    assert rms == pytest.approx(math.sqrt(quad(lambda s: (torque(s) / KT) ** 2, 0, T)[0] / T), rel=1e-4)
    voltage = next(c for c in result.joints[0].checks if c.name == "voltage limit")
    assert voltage.limit == U
    assert voltage.value == pytest.approx(max(KT * abs(speed(s)) + R * abs(torque(s)) / KT for s in t), rel=1e-9)
    # the voltage-limit line: at the speed (U − R I)/k_t the voltage is U
    T_m = 0.4
    n_U = voltage_limit_speed(T_m, KT, R, U)
    assert n_U == pytest.approx((400 - 3 * 0.8) / 0.5)
    assert terminal_voltage(n_U, T_m, KT, R) == pytest.approx(U)
    assert voltage_limited_torque(n_U, KT, R, U) == pytest.approx(T_m)


def test_a_supply_too_low_fails_the_voltage_limit():
    """At 60 V the back-EMF k_t n alone (0.5 × 125.7 rad/s = 62.8 V) is too much: the voltage limit fails and is
    reported as the failing check of the closest drive."""
    low = MOTOR.assign(voltage=60.0)
    _, result = sized(-1.0, low, samples=2001)
    (joint,) = result.joints
    assert not joint.feasible
    assert [c.name for c in joint.failed] == ["voltage limit"]
    assert "voltage limit" in joint.closest["failed"].iloc[0]
    # the same through the supply voltage setting
    _, again = sized(-1.0, samples=2001)
    duty = again.joints[0].duty
    conv = converters_for(duty, linear=SCREW)
    evaluation = evaluate(duty, MOTOR, conv, limits=DriveLimits(voltage=60.0))
    assert evaluation.failed(0, 0) == [f"voltage limit ×{evaluation.load_factors_of(0, 0)[10]:.2f}"]


def test_common_bus_against_the_closed_form_powers():
    """One lift lowering and one raising on a common DC bus: the raising one takes what the lowering one gives
    back, so the bus gives the braking resistor ∫ max(−(P_down + P_up), 0) dt, the closed forms integrated by quad,
    less than the two axes alone; two identical axes give twice one. (The energy drawn differs from quad's by the
    first sample, held at rest and so driven forward, F/η: at most Δt × ΔP = 1e-4 s × 0.4 W.)"""
    mech, down = sized(-1.0)
    _, up = sized(+1.0)
    g = gravity(mech)
    p_down, p_up = hand_power(-1.0, g)[2], hand_power(+1.0, g)[2]
    up.joints[0].joint = "z2"
    both = electrical([down.joints[0], up.joints[0]])
    frame = both.to_frame().set_index("axis")
    for name, p in (("z", p_down), ("z2", p_up)):
        assert frame.loc[name, "energy_regenerated"] == pytest.approx(
            quad(lambda s, p=p: max(-p(s), 0.0), 0, T, limit=200)[0], rel=1e-6, abs=1e-9)
        assert frame.loc[name, "energy_drawn"] == pytest.approx(
            quad(lambda s, p=p: max(p(s), 0.0), 0, T, limit=200)[0], rel=1e-6, abs=1e-4 * 0.4)
    bus = quad(lambda s: max(-(p_down(s) + p_up(s)), 0.0), 0, T, limit=200)[0]
    assert frame.loc["DC bus", "energy_regenerated"] == pytest.approx(bus, rel=1e-6, abs=1e-9)
    assert frame.loc["DC bus", "energy_regenerated"] < frame.loc["z", "energy_regenerated"]
    twice = electrical([down.joints[0], down.joints[0]])
    assert twice.bus()["energy_regenerated"] == pytest.approx(2 * frame.loc["z", "energy_regenerated"], rel=1e-12)
    check_result(both)


def test_positive_energy_splits_at_the_zero():
    """P from −1 W to 3 W over 1 s: the positive part is the triangle ½ × 0.75 s × 3 W; P = 2 W constant: 2 J."""
    assert positive_energy([0.0, 1.0], [-1.0, 3.0]) == pytest.approx(1.125)
    assert positive_energy([0.0, 1.0], [3.0, -1.0]) == pytest.approx(1.125)
    assert positive_energy([0.0, 0.5, 1.0], [2.0, 2.0, 2.0]) == pytest.approx(2.0)
    assert positive_energy([0.0, 1.0], [-2.0, -1.0]) == 0.0


def test_a_motor_without_electrical_data_counts_the_shaft_power_only():
    mech, result = sized(-1.0, MOTOR.drop(columns=["torque_constant", "resistance", "voltage"]), samples=2001)
    torque, speed, _ = hand_power(-1.0, gravity(mech))
    row = electrical(result).to_frame().iloc[0]
    assert row["copper_loss"] == 0 and pd.isna(row["peak_current"])
    shaft = quad(lambda s: max(-torque(s) * speed(s), 0.0), 0, T)[0]
    assert row["energy_regenerated"] == pytest.approx(shaft, rel=1e-5)
    assert "voltage limit" not in {c.name for c in result.joints[0].checks}
    with pytest.raises(InputError, match="no motor-driven joint"):
        electrical(mechatron.size(mechatron.load("six_bar_bucket")))


# --------------------------------------------------------------------------------- the emergency-stop limit
# The hand case of test_drives_sizing: a motor of peak torque 0.3 N·m through a gearbox of ratio 50.
GEAR_MOTOR = pd.DataFrame([{"key": "M", "rated_torque": 0.1, "peak_torque": 0.3, "rated_speed": 300.0,
                            "max_speed": 500.0, "rotor_inertia": 1e-4, "torque_constant": 0.3}])
GEARBOX = pd.DataFrame([{"key": "G50", "type": "planetary", "ratio": 50.0, "rated_torque": 5.0, "peak_torque": 10.0,
                         "emergency_torque": 20.0, "max_input_speed": 600.0, "rated_input_speed": 400.0,
                         "efficiency": 0.9, "input_inertia": 2e-5}])


def _emergency(motors, limits=None) -> float:
    t = np.linspace(0, 1, 11)
    duty = JointDuty("q", "revolute", t, np.ones_like(t), np.zeros_like(t), np.ones_like(t), np.ones_like(t), 0.1)
    evaluation = evaluate(duty, motors, converters_for(duty, GEARBOX, direct=False), limits=limits)
    return next(c.value for c in evaluation.checks(0, 0) if c.name == "transmission emergency torque")


def test_emergency_stop_torque_or_current_limit():
    """Without a limit 0.3 × 50 = 15 N·m; a 0.2 N·m stop torque: 10 N·m; a 0.5 A stop current: k_t I u =
    0.3 × 0.5 × 50 = 7.5 N·m; never above the peak torque (2 N·m → 15); without k_t a current limit keeps the peak."""
    assert _emergency(GEAR_MOTOR) == pytest.approx(15.0)
    assert _emergency(GEAR_MOTOR, DriveLimits(stop_torque=0.2)) == pytest.approx(10.0)
    assert _emergency(GEAR_MOTOR, DriveLimits(stop_current=0.5)) == pytest.approx(7.5)
    assert _emergency(GEAR_MOTOR, DriveLimits(stop_torque=2.0)) == pytest.approx(15.0)
    assert _emergency(GEAR_MOTOR.drop(columns=["torque_constant"]), DriveLimits(stop_current=0.5)) == \
        pytest.approx(15.0)


def test_the_stop_limit_reaches_the_sizing():
    """The planar 2R arm with the example catalogs: limiting the stop torque to 1 mN·m takes the emergency check
    off every gearbox's way; the chosen gearboxes' emergency values become 0.001 × u."""
    mech = mechatron.load("planar_2r")
    limited = mechatron.size(mech, limits=DriveLimits(stop_torque=1e-3))
    for joint in limited.joints:
        stop = next(c for c in joint.checks if c.name == "transmission emergency torque")
        assert stop.value == pytest.approx(1e-3 * joint.ratio)
        assert joint.feasible


@pytest.mark.parametrize("kwargs, message", [
    ({"stop_torque": -1.0}, "stop_torque must be a finite number > 0"),
    ({"stop_current": math.inf}, "stop_current must be a finite number > 0"),
    ({"stop_torque": 1.0, "stop_current": 1.0}, "as a torque or as a current, not both"),
    ({"screw_life": 0.0}, "screw_life must be"),
    ({"voltage": 0.0}, "voltage must be"),
])
def test_bad_limits(kwargs, message):
    with pytest.raises(InputError, match=message):
        DriveLimits(**kwargs)


def test_voltage_check_is_exact_on_the_sample_envelope():
    """The voltage k_t |n| + R |T_m| / k_t grows with |n| and |T_m|, so the samples the envelope keeps decide it for
    every motor and converter: the evaluated check equals the largest voltage over all samples, computed pair by
    pair from the motor side (n = u ω, T_m = (J_m + J_c) u ω̇ + τ*/u), and the lazy bound never exceeds it."""
    from mechatron.drives.catalogs import default_catalog
    from mechatron.drives.checks import motor_side
    from mechatron.drives.duty import joint_duties
    from mechatron.dynamics.task import default_task

    mech = mechatron.load("planar_2r")
    duty = joint_duties(mech, default_task(mech).trajectory)[0]
    motors = default_catalog("motors").iloc[::7].reset_index(drop=True)
    motors = motors.assign(resistance=30 / motors["rated_current"], voltage=560.0)
    conv = converters_for(duty, default_catalog("gearboxes").iloc[::5])
    assert len(duty.envelope()) < len(duty.t)  # some samples are left out
    lazy, exact = evaluate(duty, motors, conv, exact=False), evaluate(duty, motors, conv)
    kt, R, Jm = (motors[c].to_numpy()[:, None] for c in ("torque_constant", "resistance", "rotor_inertia"))
    for c in range(len(conv)):
        n, accel, base = motor_side(duty, conv.ratio[c], conv.efficiency[c], conv.inertia[c])
        brute = (kt * np.abs(n) + R * np.abs(Jm * accel + base) / kt).max(axis=1)
        assert exact.values[:, c, 10] == pytest.approx(brute, rel=1e-12)
        assert np.all(lazy.values[:, c, 10] <= brute * (1 + 1e-12))
