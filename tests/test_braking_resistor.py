"""The braking resistor of the DC bus (mechatron.drives.resistors): a resistor sized from a regenerative energy per
cycle computed by hand, the resistance window, a regenerative supply instead, and bad resistor catalogs."""

from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest

from mechatron.drives.catalogs import read_catalog
from mechatron.drives.duty import JointDuty
from mechatron.drives.electrical import electrical
from mechatron.drives.joint import size_joint
from mechatron.drives.resistors import size_braking
from mechatron.errors import InputError

# A one-link arm: a point mass m at L, lowered at constant speed ω from θ = +60° to −60° (θ from the horizontal), by a
# direct drive whose chain has the efficiency η; the motor's torque constant k_t and winding resistance R.
M, G, L, OMEGA, ETA, KT, R_WINDING = 5.0, 9.81, 0.4, 3.0, 0.9, 4.0, 0.2
THETA0 = math.pi / 3
MOTOR = pd.DataFrame([{"key": "M", "rated_torque": 25.0, "peak_torque": 60.0, "rated_speed": 300.0,
                       "max_speed": 500.0, "rotor_inertia": 0.1, "torque_constant": KT, "resistance": R_WINDING,
                       "mass": 5.0}])
U_MAX, R_MIN = 48.0, 25.0


def lowering_duty() -> JointDuty:
    """τ = m g L cos θ (the gravity the joint holds), q̇ = −ω: the load drives the motor back all the way down."""
    t = np.linspace(0.0, 2 * THETA0 / OMEGA, 2001)
    theta = THETA0 - OMEGA * t
    tau = M * G * L * np.cos(theta)
    return JointDuty("q1", "revolute", t, np.full_like(t, -OMEGA), np.zeros_like(t), tau, tau, M * L**2,
                     2 * THETA0, efficiency=ETA)


def hand_figures() -> tuple[float, float, float]:
    """(E_reg (J), P_peak (W), T (s)) from the model's formula (mechatron.drives.electrical): back-driven, the motor's
    torque is T_m = η τ (mechatron.drives.transmission), its power P = T_m n + R (T_m/k_t)² with n = −ω, so

        E_reg = ∫ −P dt = η m g L (sin θ0 − sin θ1) − R (η m g L / k_t)² / ω ∫ cos²θ dθ
              = η m g Δh − R (η m g L / k_t)² (θ0 + sin 2θ0 / 2) / ω   (θ1 = −θ0, Δh = 2 L sin θ0)

    (the potential energy m g Δh less the converter's loss and the copper loss); the peak at θ = 0."""
    gravity = ETA * M * G * L
    copper = R_WINDING * (gravity / KT) ** 2
    energy = ETA * M * G * 2 * L * math.sin(THETA0) - copper * (THETA0 + math.sin(2 * THETA0) / 2) / OMEGA
    return energy, gravity * OMEGA - copper, 2 * THETA0 / OMEGA


def resistors() -> pd.DataFrame:
    """Five resistors, lightest first: too high a resistance, too low, too little continuous power, too little pulse
    energy, and the one that passes (hand figures: E_reg = 28.66 J, P_peak = 49.08 W, P_mean = 41.05 W)."""
    rows = [("too-high", 47.0, 100.0, 500.0), ("too-low", 22.0, 100.0, 500.0), ("weak", 33.0, 40.0, 500.0),
            ("short", 33.0, 60.0, 20.0), ("fits", 33.0, 60.0, 500.0)]
    return pd.DataFrame([{"key": k, "resistance": r, "continuous_power": pc, "pulse_energy": ep, "pulse_time": 1.0,
                          "mass": 0.3 + 0.1 * i} for i, (k, r, pc, ep) in enumerate(rows)])


@pytest.fixture(scope="module")
def balance():
    joint = size_joint(lowering_duty(), MOTOR)
    assert joint.feasible and joint.converter_kind == "direct" and joint.ratio == 1.0
    return electrical([joint])


def test_resistor_from_a_hand_computed_regenerative_energy(balance):
    energy, peak, period = hand_figures()
    assert energy == pytest.approx(28.66, abs=0.01)  # m g Δh = 33.98 J less the converter's and copper losses
    supply = size_braking(balance.t, balance.bus_power, resistors(), bus_voltage=U_MAX, resistor_min=R_MIN)
    assert supply.pulse_energy == pytest.approx(energy, rel=1e-6)  # one braking interval: the whole move
    assert supply.pulse_time == pytest.approx(period, rel=1e-9)
    assert supply.mean_power == pytest.approx(energy / period, rel=1e-6)
    assert supply.peak_power == pytest.approx(peak, rel=1e-9)
    assert balance.bus()["energy_regenerated"] == pytest.approx(energy, rel=1e-6)
    assert supply.feasible and supply.resistor["key"] == "fits"
    checks = {name: (value, limit) for name, value, limit, _ in supply.checks}
    # the window R_min ≤ R ≤ U_max²/P_peak = 48²/49.08 = 46.9 Ω, by hand
    assert checks["resistance (max U²/P_peak)"] == pytest.approx((33.0, U_MAX**2 / peak), rel=1e-9)
    assert checks["resistance (min of the drive)"] == (R_MIN, 33.0)
    assert checks["continuous power"] == pytest.approx((energy / period, 60.0), rel=1e-6)
    assert checks["pulse energy"] == pytest.approx((energy, 500.0), rel=1e-6)


@pytest.mark.parametrize(("key", "failed"), [("too-high", "resistance (max U²/P_peak)"),
                                             ("too-low", "resistance (min of the drive)"),
                                             ("weak", "continuous power"), ("short", "pulse energy")])
def test_each_rejected_resistor_fails_its_own_check(balance, key, failed):
    alone = resistors().query("key == @key")
    supply = size_braking(balance.t, balance.bus_power, alone, bus_voltage=U_MAX, resistor_min=R_MIN)
    assert not supply.feasible and supply.resistor["key"] == key
    assert [name for name, value, limit, _ in supply.checks if value > limit] == [failed]


def test_a_regenerative_supply_chooses_no_resistor(balance):
    energy, peak, period = hand_figures()
    supply = size_braking(balance.t, balance.bus_power, resistors(), regenerative=True, bus_voltage=U_MAX)
    assert supply.feasible and supply.resistor is None and supply.checks == []
    assert supply.peak_power == pytest.approx(peak, rel=1e-9)
    assert supply.as_dict()["kind"] == "regenerative supply" and supply.as_dict()["resistor"] is None
    assert "no braking resistor" in supply.line()


def test_regenerative_supply_through_the_cli():
    cli = subprocess.run([sys.executable, "-m", "mechatron", "size", "puma560", "--regenerative-supply", "--json"],
                         capture_output=True, text=True)
    assert cli.returncode == 0, cli.stderr
    braking = json.loads(cli.stdout)["totals"]["braking_supply"]
    assert braking["kind"] == "regenerative supply" and braking["resistor"] is None and braking["checks"] == []


@pytest.mark.parametrize(("value", "message"), [("nan", "not a finite number"), ("-10", "> 0"), ("", "missing")])
def test_bad_resistor_catalogs(tmp_path, value, message):
    """A resistance that is NaN, negative or missing: one line naming file, row and field, exit 2."""
    path = tmp_path / "resistors.csv"
    path.write_text("key,resistance_ohm,continuous_power_W,pulse_energy_J,pulse_time_s\n"
                    "BR-1,33,60,500,1\n" f"BR-2,{value},60,500,1\n")
    with pytest.raises(InputError) as error:
        read_catalog(path, "resistors")
    text = str(error.value)
    assert str(path) in text and "row 3" in text and "resistance" in text
    cli = subprocess.run([sys.executable, "-m", "mechatron", "size", "puma560", "--resistors", str(path)],
                         capture_output=True, text=True)
    lines = cli.stderr.strip().splitlines()
    assert cli.returncode == 2 and len(lines) == 1, cli.stderr
    assert str(path) in lines[0] and "row 3" in lines[0] and "resistance" in lines[0]


def test_the_whole_axis_in_the_reports(tmp_path):
    """The README's whole-axis command: the servo drive next to each motor and the braking resistor in the totals, in
    the text and the HTML report."""
    report = tmp_path / "axis.html"
    cli = subprocess.run([sys.executable, "-m", "mechatron", "size", "puma560", "--drives", "catalogs/servo_drives.csv",
                          "--resistors", "catalogs/braking_resistors.csv", "--report", str(report)],
                         capture_output=True, text=True)
    assert cli.returncode == 0, cli.stderr
    heads = [line for line in cli.stdout.splitlines() if line.startswith("q")]
    assert len(heads) == 6 and all(" with servo drive SD-" in line for line in heads)
    resistor = next(line for line in cli.stdout.splitlines() if line.startswith("  braking resistor: "))
    key = resistor.split(": ")[1]
    html = report.read_text()
    assert "servo drive" in html and f"braking resistor: {key}" in html
