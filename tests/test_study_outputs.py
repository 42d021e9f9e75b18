"""The study analyses ``linkage`` and ``dynamics`` (mechatron/studies/analyses) against closed forms, hand
calculations and finite differences of the potential energy."""

from __future__ import annotations

import math

import numpy as np
import pytest

import mechatron
from mechatron.errors import InputError, MechatronError
from mechatron.studies.analyses import analysis


def test_crank_slider_travel_is_twice_the_crank():
    # x_C = l1 cos q1 + sqrt(l2² − l1² sin² q1) [Egorov, fig. 4.18]: largest l1 + l2 at q1 = 0, smallest l2 − l1 at
    # q1 = π; the 13 samples of a turn from 60° in 30° steps pass through both. C stays on the x axis: y = 0.
    linkage = analysis("linkage")
    for l1, l2 in [(0.1, 0.4), (0.13, 0.31), (0.05, 0.5)]:
        mech = mechatron.load("crank_slider").with_parameters(l1=l1, l2=l2)
        out = linkage.outputs(mech, {"samples": 13}, seed=0)
        assert out["x_travel_m"] == pytest.approx(2 * l1, abs=1e-9)
        assert out["reach_m"] == pytest.approx(l1 + l2, abs=1e-9)
        assert out["height_m"] == pytest.approx(0.0, abs=1e-9) and out["depth_m"] == pytest.approx(0.0, abs=1e-9)
        assert out["y_travel_m"] == pytest.approx(0.0, abs=1e-9)
        assert "min_transmission_angle_deg" not in out  # no transmission-angle measure in the file


def test_crank_point_path_extents():
    # the crank pin B on a circle of radius l1 about A: reach = height = depth = l1, travels 2 l1 (samples through
    # 0°, 90°, 180°, 270°)
    mech = mechatron.load("crank_slider").with_parameters(l1=0.12)
    out = analysis("linkage").outputs(mech, {"samples": 13, "point": "B"}, seed=0)
    for key in ("reach_m", "height_m", "depth_m"):
        assert out[key] == pytest.approx(0.12, abs=1e-9)
    assert out["x_travel_m"] == pytest.approx(0.24, abs=1e-9) and out["y_travel_m"] == pytest.approx(0.24, abs=1e-9)


def test_front_shovel_forces_and_transmission_angles():
    # Holding forces by virtual work: F_i = ∂V/∂L_i with the other cylinders held (V: potential energy), central
    # differences of V over assembled positions; transmission angles from the points' positions.
    from mechatron.dynamics.tree import potential_energy
    from mechatron.kinematics.loops import assemble
    from mechatron.kinematics.sweeps import default_inputs, sweep

    mech = mechatron.load("front_shovel")
    out = analysis("linkage").outputs(mech, {"samples": 5}, seed=0)
    inputs = default_inputs(mech, 5)
    h = 1e-5
    largest = {name: 0.0 for name in mech.actuated}
    q = mech.reference_q
    for k in range(5):
        base = {name: float(inputs[name][k]) for name in mech.actuated}
        q = assemble(mech, base, guess=q)
        for name in mech.actuated:
            # second-order differences inside the stroke: central, or one-sided (−3V0 + 4V1 − V2)/(2h) at an end
            low, high = mech.cylinders[name].stroke
            side = 1 if base[name] - h < low else -1 if base[name] + h > high else 0
            steps = (-1, 1) if side == 0 else (0, side, 2 * side)
            energy = [potential_energy(mech, assemble(mech, {**base, name: base[name] + s * h}, guess=q))
                      for s in steps]
            force = (energy[1] - energy[0]) / (2 * h) if side == 0 else \
                side * (-3 * energy[0] + 4 * energy[1] - energy[2]) / (2 * h)
            largest[name] = max(largest[name], abs(force))
    for name in mech.actuated:
        assert out[f"{name}_max_force_N"] == pytest.approx(largest[name], rel=1e-5)
    table = sweep(mech, samples=5).table
    angles = []
    for a, b, c, d in [("A", "B", "C", "B"), ("D", "E", "F", "E"), ("G", "K", "Q", "K")]:
        u = table[[f"{b}_x", f"{b}_y"]].to_numpy() - table[[f"{a}_x", f"{a}_y"]].to_numpy()
        w = table[[f"{d}_x", f"{d}_y"]].to_numpy() - table[[f"{c}_x", f"{c}_y"]].to_numpy()
        cosine = np.abs((u * w).sum(1)) / np.linalg.norm(u, axis=1) / np.linalg.norm(w, axis=1)
        angles.append(np.degrees(np.arccos(np.minimum(cosine, 1.0))).min())
    assert out["min_transmission_angle_deg"] == pytest.approx(min(angles), abs=1e-9)
    assert out["reach_m"] == pytest.approx(table["V_x"].max(), abs=1e-12)


def test_pressure_from_bore():
    # p = F / (count π D² / 4) pushing; the bucket cylinder pushes or pulls: the larger of the two pressures
    mech = mechatron.load("front_shovel")
    options = {"samples": 5, "cylinders": {"L3": {"bore": 0.18, "rod": 0.125}}}
    out = analysis("linkage").outputs(mech, options, seed=0)
    assert "L1_max_pressure_Pa" not in out
    assert out["L3_max_pressure_Pa"] <= out["L3_max_force_N"] / (math.pi * (0.18**2 - 0.125**2) / 4) + 1e-6
    assert out["L3_max_pressure_Pa"] > 0


def test_linkage_refuses():
    linkage = analysis("linkage")
    with pytest.raises(InputError, match="no closed loops"):
        linkage.check(mechatron.load("puma560"), {})
    with pytest.raises(InputError, match="unknown option 'sample'"):
        linkage.check(mechatron.load("crank_slider"), {"sample": 3})
    with pytest.raises(InputError, match="three-cylinder"):
        linkage.check(mechatron.load("crank_slider"), {"working_range": True})
    mech = mechatron.load("crank_slider").with_parameters(l1=0.3, l2=0.28)  # rod shorter than the crank: no q1 = 90°
    with pytest.raises(MechatronError, match="cannot be assembled"):
        linkage.outputs(mech, {"samples": 13}, seed=0)


def test_dynamics_planar_2r_by_hand():
    # planar_2r (robots/planar_2r.toml): gravity along the joint axes (no torque). Joint 2 held at 0, joint 1
    # moves 1 rad on a trapezoid (v = 1 rad/s, a = 5 rad/s²): accelerating 0.2 s, cruising 0.8 s, braking 0.2 s.
    # With q2 = 0 and q̇2 = 0: τ1 = M11 q̈1, τ2 = M21 q̈1 (the centrifugal term m2 l1 lc2 sin q2 q̇1² is 0), with
    #   I1 = 0.0425667 + 2.0·0.25² = 0.1675667 (about joint 1),  I2c = 0.02046875 (link 2 about its centre)
    #   M11 = I1 + I2c + 1.5·(0.5 + 0.2)² = 0.1675667 + 0.02046875 + 0.735 = 0.92303545 kg·m²
    #   M21 = I2c + 1.5·(0.2² + 0.5·0.2) = 0.02046875 + 0.21 = 0.23046875 kg·m²
    # Peak |τ| = M·5; RMS = M·5·sqrt(0.4 / 1.2) (|q̈| = 5 during 0.4 s of 1.2 s).
    mech = mechatron.load("planar_2r")
    options = {"start": [0.0, 0.0], "end": [1.0, 0.0], "vmax": 1.0, "amax": 5.0, "dt": 0.0005}
    out = analysis("dynamics").outputs(mech, options, seed=0)
    names = [k[:-len("_peak_Nm")] for k in out if k.endswith("_peak_Nm")]
    assert len(names) == 2
    for name, m in zip(names, (0.92303545, 0.23046875)):
        assert out[f"{name}_peak_Nm"] == pytest.approx(5 * m, rel=1e-5)
        assert out[f"{name}_rms_Nm"] == pytest.approx(5 * m * math.sqrt(0.4 / 1.2), rel=2e-3)


def test_dynamics_degrees_and_errors():
    mech = mechatron.load("planar_2r")
    dynamics = analysis("dynamics")
    a = dynamics.outputs(mech, {"start_deg": [0, 0], "end_deg": [90, 0], "dt": 0.002}, seed=0)
    b = dynamics.outputs(mech, {"start": [0, 0], "end": [math.pi / 2, 0], "dt": 0.002}, seed=0)
    assert a == pytest.approx(b, rel=1e-12)
    with pytest.raises(InputError, match="start"):
        dynamics.check(mech, {"start": [0.0], "end": [1.0, 0.0]})
    with pytest.raises(InputError, match="both start and end"):
        dynamics.check(mech, {"start": [0.0, 0.0]})
