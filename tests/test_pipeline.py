"""Issue 11's pipeline: a synthesis writes a mechanism file, and every command reads it.

- The shipped robots/six_bar_bucket.toml and robots/front_shovel.toml are what the syntheses write now.
- From the command line, on a user's excavator file made by ``mechatron excavator --design … -o my_shovel.toml``:
  ``linkage``, ``dynamics --move``, ``size`` and ``tolerance`` run, and their numbers agree with independent
  references: the tooth tip at both ends of the strokes with the report's closed form [Shovel, 2.2, 3.2–3.7] and the
  design's asked height; the work of the boom cylinder with the rise of the potential energy; the cylinders' peak
  flow with count·πD²/4·v; the worst-case tolerance with finite differences of the models rebuilt from the file.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import tomllib

import mechatron
from mechatron.cli import main
from mechatron.kinematics.geometry import point_positions
from mechatron.kinematics.loops import assemble
from mechatron.machines import bucket as bk
from mechatron.machines import excavator as ex

ROOT = Path(__file__).resolve().parent.parent
DESIGN = ROOT / "examples" / "data" / "front_shovel_design.toml"
DEG = math.pi / 180


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def same_toml(a: object, b: object, path: str = "") -> None:
    """Two parsed TOML documents are equal: the same keys, lists and text, numbers to 1e-12 (relative)."""
    if isinstance(a, dict):
        assert isinstance(b, dict) and list(a) == list(b), f"{path}: keys {list(a)} != {list(b)}"
        for key in a:
            same_toml(a[key], b[key], f"{path}.{key}")
    elif isinstance(a, list):
        assert isinstance(b, list) and len(a) == len(b), path
        for k, (x, y) in enumerate(zip(a, b)):
            same_toml(x, y, f"{path}[{k}]")
    elif isinstance(a, float):
        assert b == pytest.approx(a, rel=1e-12, abs=1e-12), path
    else:
        assert a == b, path


# ------------------------------------------------------------------------------------------- the shipped files
@pytest.mark.parametrize("name, write", [("six_bar_bucket", lambda path: bk.write_bucket(None, path)),
                                         ("front_shovel", lambda path: ex.write_shovel(None, path))])
def test_the_shipped_file_is_what_the_synthesis_writes(tmp_path, name, write):
    """robots/NAME.toml is the synthesis' output with the default inputs (regenerate it with
    ``bk.write_bucket(None, "robots/six_bar_bucket.toml")`` or ``mechatron excavator -o robots/front_shovel.toml``
    after a change of the synthesis); ``load(NAME)`` reads that file."""
    shipped = Path(mechatron.load(name).source)
    assert shipped == ROOT / "robots" / f"{name}.toml"
    written = write(tmp_path / f"{name}.toml")
    same_toml(tomllib.loads(shipped.read_text()), tomllib.loads(written.read_text()))


# ------------------------------------------------------------------------------------------- the user's file
@pytest.fixture(scope="module")
def design():
    return tomllib.loads(DESIGN.read_text())


@pytest.fixture(scope="module")
def shovel_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("pipeline") / "my_shovel.toml"
    assert main(["excavator", "--design", str(DESIGN), "-o", str(path)]) == 0
    return path


def test_excavator_writes_the_file_the_api_writes(shovel_file, tmp_path, capsys):
    """``-o`` writes the design's file and says so; without it the report is printed (tests/test_excavator.py)."""
    api = ex.write_shovel(ex.read_design(DESIGN), tmp_path / "my_shovel.toml")
    assert shovel_file.read_text() == api.read_text()
    code, out, _ = run(capsys, "excavator", "--design", DESIGN, "-o", tmp_path / "again.toml")
    assert code == 0 and out == f"wrote {tmp_path / 'again.toml'}\n"
    mech = mechatron.load(shovel_file)
    assert mech.name == "my_shovel" and mech.actuated == ["L1", "L2", "L3"] and mech.cylinders["L1"].count == 2


def joint_ranges(d: dict) -> tuple[tuple[float, float], tuple[float, float], tuple[float, float]]:
    """θ1, θ2, θ3 ranges (rad) by the report's formulas [Shovel, 3.2–3.7], written out for the design file's numbers
    (the fields it leaves out have the report's values)."""
    l1, l2, l3 = d["boom"], d["stick"], 2.0
    xc, yc = d["boom_foot"]
    R1, H1, H2, R0, zeta, delta = d["max_digging_radius"], 3.2, d["max_digging_height"], 4.2, 25 * DEG, 40 * DEG
    t2max = math.acos((l1**2 + l2**2 - (R1 - l3 - xc) ** 2) / (2 * l1 * l2))
    t2min = math.acos((l1**2 + l2**2 - (yc - l3 * math.sin(zeta)) ** 2 - (R0 - l3 * math.cos(zeta) - xc) ** 2)
                      / (2 * l1 * l2))
    cq = math.sqrt(l1**2 + l2**2 - 2 * l1 * l2 * math.cos(t2max))
    t1max = math.asin((H2 - l3 - yc) / cq) + math.asin(l2 * math.sin(t2max) / cq)
    t1min = math.asin((-H1 - yc + l2 + l3) / l1)
    t3max = max(2.5 * math.pi - t1max - t2max, math.pi + math.asin(l1 * math.sin(t2max) / cq))
    return (t1min, t1max), (t2min, t2max), (2 * math.pi - t1max - t2max - delta, t3max)


def tip(d: dict, t1: float, t2: float, t3: float) -> np.ndarray:
    """The tooth tip V = C + l1∠θ1 + l2∠(θ1 + θ2 − π) + l3∠(θ1 + θ2 + θ3) (m)."""
    e = lambda a: np.array([math.cos(a), math.sin(a)])  # noqa: E731
    return np.array(d["boom_foot"]) + d["boom"] * e(t1) + d["stick"] * e(t1 + t2 - math.pi) + 2.0 * e(t1 + t2 + t3)


def test_linkage_puts_the_tip_where_the_closed_form_does(shovel_file, design, tmp_path, capsys):
    """The sweep runs from all cylinders retracted (θ1min, θ2min, θ3min) to all extended (θ1max, θ2max, θ3max: the
    maximum digging height [Shovel, 2.2], bucket QV pointing up, the tip at the asked 9.6 m)."""
    code, _, err = run(capsys, "linkage", shovel_file, "--samples", "9", "--csv", tmp_path / "sweep.csv")
    assert code == 0, err
    table = pd.read_csv(tmp_path / "sweep.csv")
    assert len(table) == 9
    ranges = joint_ranges(design)
    for row, end in ((0, 0), (8, 1)):
        expected = tip(design, *(r[end] for r in ranges))
        assert table.loc[row, ["V_x", "V_y"]].to_numpy(float) == pytest.approx(expected, abs=1e-6)
    assert table.loc[8, "V_y"] == pytest.approx(design["max_digging_height"], abs=1e-6)
    assert table.loc[8, "q_theta1"] == pytest.approx(ranges[0][1], abs=1e-8)


def test_dynamics_work_of_the_boom_cylinder_is_the_rise_of_potential_energy(shovel_file, design, tmp_path, capsys):
    """A rest-to-rest stroke of the boom cylinders with the others held: ∫ F L̇ dt = ΔV = g Σ m Δy_centre, the
    masses of the design file at the middles of CF, FQ, QV."""
    start, end = (2.5, 2.2, 2.0), (3.3, 2.2, 2.0)
    move = ";".join(",".join(map(str, p)) for p in (start, end))
    code, _, err = run(capsys, "dynamics", shovel_file, "--move", move, "--vmax", "0.2", "--amax", "1", "--dt", "0.002",
                       "--csv", tmp_path / "dyn.csv")
    assert code == 0, err
    table = pd.read_csv(tmp_path / "dyn.csv")
    work = np.trapezoid(table["power_L1"], table["t"])
    mech = mechatron.load(shovel_file)
    masses = {("C", "F"): design["boom_mass"], ("F", "Q"): design["stick_mass"], ("Q", "V"): 3800.0}

    def height(inputs):
        P = dict(zip("CFQV", point_positions(mech, assemble(mech, dict(zip(mech.actuated, inputs))), *"CFQV")))
        return sum(m * (P[a][1] + P[b][1]) / 2 for (a, b), m in masses.items())

    rise = 9.81 * (height(end) - height(start))
    assert rise > 1e5 and work == pytest.approx(rise, rel=1e-4)
    assert np.abs(table["power_L2"]).max() == 0 and np.abs(table["power_L3"]).max() == 0


def test_size_sizes_the_cylinders_of_the_design(shovel_file, design, capsys):
    """The cylinders to size have the design's stroke ratios λ = L_max/L_min (stick 1.75 from the design file, boom
    and bucket the report's 1.7) and the stroke L_max − L_min; the boom cylinders, which set the pace of the generic
    task, move at the file's input rate 0.1 m/s: peak flow = 2·πD²/4·0.1, the twin boom cylinder counted twice."""
    code, out, err = run(capsys, "size", shovel_file, "--json")
    assert code == 0, err
    joints = {j["joint"]: j for j in json.loads(out)["joints"]}
    assert set(joints) == {"L1", "L2", "L3"} and all(j["kind"] == "cylinder" and j["feasible"] for j in joints.values())
    cylinders = mechatron.load(shovel_file).cylinders
    for name, ratio in (("L1", 1.7), ("L2", design["stick_ratio"]), ("L3", 1.7)):
        low, high = cylinders[name].stroke
        assert high / low == pytest.approx(ratio, rel=1e-12)
        stroke = next(c for c in joints[name]["checks"] if c["name"] == "stroke")
        assert stroke["value"] == pytest.approx(high - low, rel=1e-12)
    boom = joints["L1"]
    assert boom["count"] == 2 and boom["peak_flow"] == pytest.approx(2 * math.pi * boom["bore"] ** 2 / 4 * 0.1,
                                                                      rel=1e-9)


def test_tolerance_of_the_file_lengths_and_pins_is_the_finite_difference(shovel_file, tmp_path, capsys):
    """Worst case Σ |∂V/∂p|·t per axis for the file's named lengths and the boom foot's coordinates, against
    central differences of the models rebuilt from the file with each parameter moved."""
    tolerances = {"boom": 1e-3, "stick": 1e-3, "bucket": 1e-3, "C_x": 5e-4, "C_y": 5e-4}
    (tmp_path / "tol.csv").write_text("parameter,tolerance\n" + "".join(f"{k},{v}\n" for k, v in tolerances.items()))
    pose = {"L1": 3.0, "L2": 2.5, "L3": 2.2}
    (tmp_path / "poses.csv").write_text("L1,L2,L3\n3.0,2.5,2.2\n")
    code, out, err = run(capsys, "tolerance", shovel_file, "--tolerances", tmp_path / "tol.csv", "--poses",
                         tmp_path / "poses.csv", "--method", "worst", "--json")
    assert code == 0, err
    worst = json.loads(out)["poses"][0]["methods"]["worst"]
    mech = mechatron.load(shovel_file)
    values, h = mech.parameter_values(), 1e-6
    expected = np.zeros(2)
    for name, t in tolerances.items():
        moved = [mechatron.load(shovel_file, **{name: values[name] + s * h}) for s in (1, -1)]
        plus, minus = (point_positions(m, assemble(m, pose), "V")[0] for m in moved)
        expected += np.abs((plus - minus) / (2 * h)) * t
    assert (worst["dx"], worst["dy"]) == pytest.approx(tuple(expected), rel=1e-5)
