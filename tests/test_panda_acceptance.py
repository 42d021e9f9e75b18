r"""The Panda case of issue 32 as tests: example-robot-data's Franka Panda with its own small motor catalog (with the
thermal columns) and gearbox catalog (a handful of rows in the format of examples/data/), a 3 kg payload at its
tool and a 50 °C ambient.

* Its link masses include the actuators (the library says so): the fixed-point sizing chooses the drives and peak
  torques of ``--single-pass`` (every check's value to 1e-9), and the report says which applied.
* Declared exclusive, the fixed point adds the chosen drives at their mounts. At a static pose the torques then
  follow by hand, with the positions and axes of Pinocchio's kinematics of the URDF alone (Pinocchio's RNEA gives
  the arm's own gravity torques g(q)): a point mass m at p held at rest needs at joint j (origin o_j, axis z_j,
  gravity along −ẑ) the torque τ_j = m g ((p − o_j) × ẑ) · z_j. So the payload adds that with m = 3 kg at the tool,
  and the drives add Σ_{k>j} m_k g ((o_k − o_j) × ẑ) · z_j, joint k's drive (m_k, the catalog masses) sitting on the
  link before it at the joint (it moves with every joint before k).
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import mechatron
from mechatron.cli import main
from mechatron.drives.checks import DriveLimits
from mechatron.drives.thermal import ZERO_CELSIUS
from mechatron.library import EXAMPLE_ROBOTS, installed_example_robots
from mechatron.model.payload import with_payload
from mechatron.model.urdf import load_urdf

pin = pytest.importorskip("pinocchio")
URDF = installed_example_robots().get("panda")
pytestmark = pytest.mark.skipif(URDF is None, reason="example-robot-data is not installed")

G, PAYLOAD, AMBIENT = 9.81, 3.0, 50.0
JOINTS = [f"panda_joint{k}" for k in range(1, 8)]

# Own catalogs: rows of the illustrative AS servo motors (thermal columns included) and of the harmonic and
# planetary gearboxes, in the columns of examples/data/motors.csv and gearboxes.csv.
MOTORS = """# own servo motors with thermal data (illustrative)
key,maker,series,rated_torque_Nm,peak_torque_Nm,rated_speed_rpm,max_speed_rpm,rotor_inertia_kgcm2,\
torque_constant_Nm_A,rated_current_A,rated_power_W,resistance_ohm,voltage_V,loss_torque_Nm,rth_winding_housing_K_W,\
rth_housing_ambient_K_W,tau_winding_s,tau_housing_s,max_winding_temperature_degC,\
torque_constant_coefficient_percent_K,mass_kg,price_eur
AS40-005,own,AS40,0.16,0.48,3000,6000,0.025,0.145,1.1,50,20,400,0.0254,0.757,1.41,9,346,155,-0.11,0.32,290
AS40-010,own,AS40,0.32,0.95,3000,6000,0.051,0.29,1.1,100,12,400,0.0153,1.26,2.35,11,426,155,-0.11,0.47,310
AS60-040,own,AS60,1.27,3.82,3000,6000,0.26,0.49,2.6,400,2,400,0.014,1.37,2.55,16,645,155,-0.11,1.2,420
AS80-075,own,AS80,2.39,7.16,3000,6000,0.87,0.58,4.1,750,1.2,400,0.0212,0.902,1.68,19,779,155,-0.11,2.3,540
AS100-150,own,AS100,4.77,14.3,3000,5000,2.9,0.55,8.7,1500,0.55,400,0.0431,0.446,0.829,24,959,155,-0.11,5.0,820
AS130-200,own,AS130,6.37,19.1,3000,5000,3.9,0.56,11.4,2000,0.4,400,0.0539,0.357,0.662,26,1046,155,-0.11,6.5,980
"""
GEARBOXES = """# own gearboxes (illustrative)
key,maker,type,stages,ratio,rated_torque_Nm,peak_torque_Nm,emergency_torque_Nm,peak_rule,shock_factors_per_h,\
emergency_stops,max_input_speed_rpm,rated_input_speed_rpm,efficiency_percent,input_inertia_kgcm2,backlash_arcmin,\
mass_kg,price_eur
HG14-50,own,harmonic,1,50,5.4,18,35,repeated_peak,,10000,8500,3500,70,0.033,1,0.31,650
HG20-100,own,harmonic,1,100,40,82,147,repeated_peak,,10000,6500,3500,72,0.193,1,0.75,830
HG32-100,own,harmonic,1,100,137,333,647,repeated_peak,,10000,4800,3500,75,1.69,1,2.1,1250
PG80-10,own,planetary,1,10,40,64,100,shock_factors,1000:1;2000:1.1;3000:1.2;4000:1.3;6000:1.4;10000:1.6,1000,7000,\
3500,96,0.35,10,1.9,420
PG120-100,own,planetary,2,100,180,330,800,shock_factors,1000:1;2000:1.1;3000:1.2;4000:1.3;6000:1.4;10000:1.6,1000,\
6000,3000,94,0.75,10,6.4,760
"""


@pytest.fixture
def catalogs(tmp_path):
    motors, gearboxes = tmp_path / "my_motors.csv", tmp_path / "my_gearboxes.csv"
    motors.write_text(MOTORS.replace("\\\n", ""))
    gearboxes.write_text(GEARBOXES.replace("\\\n", ""))
    return str(motors), str(gearboxes)


def size_json(capsys, *args: str) -> dict:
    code = main(["size", "panda", "--payload", str(PAYLOAD), "--ambient", str(AMBIENT), *args, "--json"])
    data = json.loads(capsys.readouterr().out)
    assert code == 0 and data["feasible"]
    return data


def test_the_panda_with_its_actuators_in_its_link_masses_sizes_as_a_single_pass(catalogs, capsys):
    motors, gearboxes = catalogs
    options = ["--motors", motors, "--gearboxes", gearboxes]
    fixed, single = size_json(capsys, *options), size_json(capsys, *options, "--single-pass")
    assert fixed["method"] == "fixed point" and fixed["drive_masses"] == "included"
    assert single["drive_masses"] == "weightless" and len(fixed["iterations"]) == 1
    for ours, theirs in zip(fixed["joints"], single["joints"], strict=True):
        assert (ours["joint"], ours["motor"], ours["gearbox"], ours["ratio"]) == \
            (theirs["joint"], theirs["motor"], theirs["gearbox"], theirs["ratio"])
        assert ours["mounted_on"]["loads_the_mechanism"] is False
        assert [c["name"] for c in ours["checks"]] == [c["name"] for c in theirs["checks"]]
        for a, b in zip(ours["checks"], theirs["checks"]):  # the peak torques among them
            assert a["value"] == pytest.approx(b["value"], rel=1e-9, abs=1e-12), (ours["joint"], a["name"])
        names = {c["name"] for c in ours["checks"]}
        assert {"transmission peak torque", "winding temperature rise"} <= names  # the catalog's thermal data
        assert "RMS torque" not in names
        rise = next(c for c in ours["checks"] if c["name"] == "winding temperature rise")
        assert rise["limit"] == pytest.approx(155.0 - AMBIENT, rel=1e-12)  # the 50 °C ambient derates the winding
    assert fixed["totals"].keys() == single["totals"].keys()
    for name, value in fixed["totals"].items():  # drive mass, energy per cycle, peak power, …
        assert value == (pytest.approx(single["totals"][name], rel=1e-9) if isinstance(value, float)
                         else single["totals"][name]), name
    assert main(["size", "panda", "--payload", str(PAYLOAD), "--ambient", str(AMBIENT), *options]) == 0
    text = capsys.readouterr().out
    assert "drive masses: included in the link masses of panda (link_masses_include_drives) — not added" in text
    assert "two-node model of winding and housing at 50 °C ambient" in text


def rest_task(path, q) -> str:
    """A trajectory CSV holding the Panda at ``q`` (rad) for 2 s: speeds and accelerations given as zero."""
    header = ["t", *JOINTS, *(f"qd_{n}" for n in JOINTS), *(f"qdd_{n}" for n in JOINTS)]
    rows = [[t, *q, *[0.0] * 14] for t in (0.0, 1.0, 2.0)]
    path.write_text(",".join(header) + "\n" + "\n".join(",".join(repr(float(v)) for v in r) for r in rows) + "\n")
    return str(path)


def test_declared_exclusive_the_fixed_point_adds_the_drives_by_hand_at_a_static_pose(catalogs, tmp_path):
    motors, gearboxes = catalogs
    q = np.array([0.0, -0.6, 0.0, -2.2, 0.0, 1.6, 0.8])
    task = rest_task(tmp_path / "rest.csv", q)
    robot = EXAMPLE_ROBOTS["panda"]
    limits = DriveLimits(ambient=AMBIENT + ZERO_CELSIUS)

    def sized(included: bool):
        arm = load_urdf(URDF, "panda", tool=robot.tool, locked_joints=robot.locked,
                        link_masses_include_drives=included)
        return mechatron.size(with_payload(arm, PAYLOAD), task, motors=motors, gearboxes=gearboxes, limits=limits)

    included, added = sized(True), sized(False)
    assert included.drive_masses == "included" and added.drive_masses == "added" and added.converged

    # Pinocchio alone: the URDF's gravity torques, the joints' origins and axes and the tool's position at q
    model = pin.buildModelFromUrdf(str(URDF))
    model = pin.buildReducedModel(model, [model.getJointId(n) for n in robot.locked], pin.neutral(model))
    data = model.createData()
    own = pin.computeGeneralizedGravity(model, data, q).copy()
    pin.framesForwardKinematics(model, data, q)
    tool = data.oMf[model.getFrameId(robot.tool)].translation
    origin = [data.oMi[model.getJointId(n)].translation for n in JOINTS]
    axis = [data.oMi[model.getJointId(n)].rotation[:, 2] for n in JOINTS]
    up = np.array([0.0, 0.0, 1.0])

    def held(m: float, p: np.ndarray, j: int) -> float:  # m g ((p − o_j) × ẑ) · z_j
        return m * G * float(np.dot(np.cross(p - origin[j], up), axis[j]))

    payload = np.array([held(PAYLOAD, tool, j) for j in range(7)])
    lever = np.hypot(*(tool - origin[1])[:2])  # joint 2's axis is horizontal here: |τ| = m g r, r horizontal
    assert abs(payload[1]) == pytest.approx(PAYLOAD * G * lever, rel=1e-12) and lever > 0.3
    masses = [j["drive_mass_kg"] for j in added.as_dict()["joints"]]
    drives = np.array([sum(held(masses[k], origin[k], j) for k in range(j + 1, 7)) for j in range(7)])
    assert [j["mounted_on"]["body"] for j in added.as_dict()["joints"]][1:] == [f"panda_link{k}" for k in range(1, 7)]
    for j in range(7):
        scale = 1e-9 * max(1.0, abs(own[j]) + abs(payload[j]) + abs(drives[j]))
        assert np.allclose(included.joints[j].duty.torque, own[j] + payload[j], rtol=0, atol=scale), JOINTS[j]
        assert np.allclose(added.joints[j].duty.torque, own[j] + payload[j] + drives[j], rtol=0, atol=scale)
    # the drives' weight changes the holding torques (joint 4 lifts them all: larger) — the issue's double count
    assert abs(drives[3]) > 10.0 and abs(added.joints[3].duty.torque[0]) > abs(included.joints[3].duty.torque[0])
