"""Calibration from measurements: known offsets recovered from simulated measurements (noise-free to 1e-9; with
noise within their standard errors, which agree with the spread over seeds), the Jacobian against central
differences, unidentifiable sets named, the calibrated files read back, the robot writer, the measurements reader
and the command line's bad inputs."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from protocol import check_result

import mechatron
from mechatron.accuracy.calibration import CalibrationProblem, calibrate
from mechatron.accuracy.measurements import Measurements, read_measurements
from mechatron.accuracy.study import configurations
from mechatron.cli import main
from mechatron.errors import InputError
from mechatron.model.robot_writer import write_robot_file

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "data" / "measurements_puma560.csv"
#: The PUMA as built in the tests (m, rad) and its encoder offsets (rad): q_model = q_read + offset.
BUILT = {"a2": 0.4318 + 4e-4, "d3": 0.15005 - 3e-4, "d4": 0.4318 + 1e-4, "a3": 0.0203 + 2e-4,
         "alpha2": math.radians(0.01), "alpha3": -math.pi / 2 + math.radians(0.02)}
OFFSETS = {"q2": math.radians(0.02), "q3": math.radians(-0.015), "q5": math.radians(0.03)}


def simulate(mech, built, offsets, read, frame=None, noise=0.0, rotation_noise=0.0, rng=None, orientation=True):
    """Measurements of ``built`` (the machine) at the encoder readings ``read`` (N, n_c), ``offsets`` added to them,
    with normal noise of σ ``noise`` (m) per axis and ``rotation_noise`` (rad) per rotation-vector component."""
    frame = frame or mech.tool_frame
    true = read.copy()
    names = mech.actuated if mech.closures else mech.joint_names
    for name, offset in offsets.items():
        true[:, names.index(name)] += offset
    Q = configurations(built, true)
    positions, rotations = [], []
    for q in Q:
        placement = mechatron.frame_placement(built, q, frame)
        positions.append(placement.translation + (rng.normal(0, noise, 3) if noise else 0.0))
        turn = pin.exp3(rng.normal(0, rotation_noise, 3)) if rotation_noise else np.eye(3)
        rotations.append(turn @ placement.rotation)
    n = len(read)
    return Measurements(read, np.array(positions), np.array(rotations) if orientation else None,
                        np.full(n, noise or 1e-3), np.full(n, rotation_noise or 1e-3),
                        tuple(str(i + 1) for i in range(n)))


@pytest.fixture(scope="module")
def puma():
    return mechatron.load("puma560")


@pytest.fixture(scope="module")
def readings(puma):
    return puma.random_configuration(np.random.default_rng(7), size=40)


# ------------------------------------------------------------------------------------------ recovery
def test_noise_free_puma_recovers_dh_offsets_and_joint_offsets(puma, readings):
    measured = simulate(puma, puma.with_parameters(BUILT), OFFSETS, readings)
    result = calibrate(puma, measured, [*BUILT, *OFFSETS])
    assert result.converged and result.identifiability.identifiable
    for name, value in {**BUILT, **OFFSETS}.items():
        assert result.unknown(name).identified == pytest.approx(value, abs=1e-9)
    assert result.statistics()["max_position_after"] < 1e-9
    assert result.statistics()["rms_position_before"] > 3e-4


def test_noise_free_position_only_with_the_wrist_offset(puma, readings):
    """Position only: the tool of the PUMA is the wrist centre, so a3, d4 and q3 (and the wrist) are told apart by
    orientations alone; a2, d3, d4, α2 and q2, q3 are identifiable from positions."""
    names = ["a2", "d3", "d4", "alpha2", "q2", "q3"]
    built = {k: BUILT[k] for k in names if k in BUILT}
    offsets = {k: OFFSETS[k] for k in ("q2", "q3")}
    measured = simulate(puma, puma.with_parameters(built), offsets, readings, orientation=False)
    result = calibrate(puma, measured, names)
    for name, value in {**built, **offsets}.items():
        assert result.unknown(name).identified == pytest.approx(value, abs=1e-9)


@pytest.mark.parametrize("name, true, frame", [
    ("crank_slider", {"l1": 0.1004, "l2": 0.3995}, None),
    ("examples/data/four_bar.toml", {"a": 0.1003, "b": 0.2996, "c": 0.2502}, "M"),
])
def test_noise_free_closed_loop_link_lengths(name, true, frame):
    mech = mechatron.load(str(ROOT / name) if name.endswith(".toml") else name)
    read = np.linspace(0.2, 6.0, 12)[:, None]
    measured = simulate(mech, mech.with_parameters(true), {}, read, frame, orientation=False)
    result = calibrate(mech, measured, list(true), frame)
    for key, value in true.items():
        assert result.unknown(key).identified == pytest.approx(value, abs=1e-9)


def test_noisy_estimates_within_their_standard_errors_which_match_the_spread_over_seeds(puma):
    """20 seeds of 30 position measurements with σ = 0.02 mm: each estimate within 3.5 standard errors of the
    truth, the reported standard errors within a factor 1.5 of the estimates' spread over the seeds, and their
    average within the normal's 2σ coverage."""
    names = ["a2", "d3", "d4", "alpha2", "q2"]
    built = {k: BUILT[k] for k in names if k in BUILT}
    truth = {**built, "q2": OFFSETS["q2"]}
    estimates, errors = [], []
    for seed in range(20):
        rng = np.random.default_rng(100 + seed)
        read = puma.random_configuration(rng, size=30)
        measured = simulate(puma, puma.with_parameters(built), {"q2": OFFSETS["q2"]}, read, noise=2e-5, rng=rng,
                            orientation=False)
        result = calibrate(puma, measured, names)
        estimates.append([result.unknown(n).identified - truth[n] for n in names])
        errors.append([result.unknown(n).std_error for n in names])
        assert result.sigma == pytest.approx(1.0, rel=0.35)  # σ̂ in units of the σ given: 1 when right
    estimates, errors = np.array(estimates), np.array(errors)
    assert np.all(np.abs(estimates) <= 3.5 * errors)
    spread = estimates.std(axis=0, ddof=1)
    ratio = spread / errors.mean(axis=0)
    assert np.all((ratio > 1 / 1.5) & (ratio < 1.5)), ratio
    assert np.mean(np.abs(estimates) <= 2 * errors) >= 0.85


def test_the_shipped_example_recovers_its_offsets_within_three_standard_errors():
    """examples/data/make_calibration_puma560.py: a2 +0.4 mm, d3 −0.3 mm, d4 +0.2 mm, α2 +0.01°, α3 −0.008°,
    q2 +0.02°, q3 −0.015°."""
    truth = {"a2": 0.4318 + 0.4e-3, "d3": 0.15005 - 0.3e-3, "d4": 0.4318 + 0.2e-3, "alpha2": math.radians(0.01),
             "alpha3": math.radians(-90 - 0.008), "q2": math.radians(0.02), "q3": math.radians(-0.015)}
    result = calibrate(mechatron.load("puma560"), EXAMPLE, list(truth))
    for name, value in truth.items():
        u = result.unknown(name)
        assert abs(u.identified - value) <= 3 * u.std_error, name
    stats = result.statistics()
    assert stats["rms_position_after"] < 0.1 * stats["rms_position_before"]


# ------------------------------------------------------------------------------------------ the Jacobian
@pytest.mark.parametrize("case", ["puma", "crank_slider"])
def test_jacobian_against_central_differences(case, puma, readings):
    if case == "puma":
        mech, names, offsets = puma, ("a2", "d3", "alpha3", "theta4", "a3"), ("q2", "q5")
        measured = simulate(puma, puma.with_parameters(BUILT), OFFSETS, readings[:8])
    else:
        mech, names, offsets = mechatron.load("crank_slider"), ("l1", "l2", "A_x", "B_y"), ("q1",)
        read = np.linspace(0.3, 5.5, 6)[:, None]
        measured = simulate(mech, mech.with_parameters({"l1": 0.101}), {}, read)
    problem = CalibrationProblem(mech, measured, names, offsets, mech.tool_frame)
    x = np.full(len(names) + len(offsets), 1e-4)
    _, J, _ = problem.evaluate(x)
    h = 1e-6
    numeric = np.column_stack([(problem.residuals(x + h * e)[0] - problem.residuals(x - h * e)[0])
                               / (2 * h) for e in np.eye(len(x))])
    scale = np.abs(numeric).max()
    assert np.abs(J - numeric).max() <= 1e-6 * scale


# ------------------------------------------------------------------------------------------ identifiability
def test_unidentifiable_sets_are_named_and_refused(puma, readings):
    """θ1 and the encoder offset of q1 add; d2 and d3 slide along the parallel axes z1 ∥ z2 (α2 = 0)."""
    measured = simulate(puma, puma, {}, readings)
    with pytest.raises(InputError, match="cannot tell apart: theta1 and q1; d2 and d3"):
        calibrate(puma, measured, ["theta1", "q1", "d2", "d3", "a2"])


def test_allowed_unidentifiable_sets_get_the_minimum_norm_change(puma, readings):
    measured = simulate(puma, puma.with_parameters({"theta1": 1e-3}), {}, readings)
    result = calibrate(puma, measured, ["theta1", "q1", "a2"], allow_unidentifiable=True)
    ident = result.identifiability
    assert ident.rank == 2 and ident.groups == (("theta1", "q1"),) and math.isinf(ident.condition)
    # the minimum-norm split of θ1 + δq1 = 1e-3 rad: half each
    assert result.unknown("theta1").identified == pytest.approx(5e-4, abs=1e-10)
    assert result.offsets()["q1"] == pytest.approx(5e-4, abs=1e-10)
    assert result.unknown("a2").identified == pytest.approx(0.4318, abs=1e-10)
    assert result.unknown("theta1").std_error is None and result.unknown("a2").std_error is not None
    data = check_result(result)
    assert data["identifiability"]["cannot_be_told_apart"] == [["theta1", "q1"]]
    assert data["identifiability"]["condition_number"] is None
    assert result.statistics()["max_position_after"] < 1e-9


# ------------------------------------------------------------------------------------------ files
def test_robot_writer_reads_back_every_shipped_arm(tmp_path):
    for name in ("puma560", "scara", "cylindrical_rpp", "planar_2r"):
        arm = mechatron.load(name)
        path = write_robot_file(arm.dh, tmp_path / f"{name}_copy.toml", description=arm.description)
        back = mechatron.load(str(path))
        assert back.parameter_values() == arm.parameter_values()
        q = arm.random_configuration(np.random.default_rng(1), size=5)
        for qi in q:
            assert np.array_equal(mechatron.frame_placement(back, qi, "tool").homogeneous,
                                  mechatron.frame_placement(arm, qi, "tool").homogeneous)
        assert np.array_equal(back.model.armature, arm.model.armature)
        assert [i.mass for i in back.model.inertias] == [i.mass for i in arm.model.inertias]


def test_calibrated_robot_file_and_urdf_read_back(puma, readings, tmp_path):
    measured = simulate(puma, puma.with_parameters(BUILT), OFFSETS, readings)
    result = calibrate(puma, measured, [*BUILT, *OFFSETS])
    robot = mechatron.load(str(result.write(tmp_path / "puma_built.toml")[0]))
    urdf = mechatron.load(str(result.write(tmp_path / "puma_built.urdf")[0]))
    values = robot.parameter_values()
    for name in BUILT:
        assert values[name] == pytest.approx(result.values()[name], abs=1e-12)
    # the offsets folded into θ: θ2 = δq2, θ3 = δq3, θ5 = δq5
    for name, offset in result.offsets().items():
        assert values[f"theta{name[1:]}"] == pytest.approx(offset, abs=1e-12)
    for q, p in zip(measured.coordinates, measured.positions):  # the files, read as the encoders read
        assert np.allclose(mechatron.frame_placement(robot, q, "tool").translation, p, atol=1e-10)
        assert np.allclose(mechatron.frame_placement(urdf, q, "tool").translation, p, atol=1e-10)
    # the stops stay on the machine: q_read = q_model − δq, so each limit moves by −δq in both files
    for written in (robot, urdf):
        index = {name: puma.model.joints[puma.joint_id(name)].idx_q for name in result.offsets()}
        for name, offset in result.offsets().items():
            i = index[name]
            assert written.model.lowerPositionLimit[i] == pytest.approx(puma.model.lowerPositionLimit[i] - offset,
                                                                        abs=1e-12)
            assert written.model.upperPositionLimit[i] == pytest.approx(puma.model.upperPositionLimit[i] - offset,
                                                                        abs=1e-12)


def test_calibrated_mechanism_file_reads_back(tmp_path):
    four_bar = mechatron.load(str(ROOT / "examples/data/four_bar.toml"))
    true = {"a": 0.1003, "b": 0.2996}
    measured = simulate(four_bar, four_bar.with_parameters(true), {}, np.linspace(0.2, 6.0, 10)[:, None], "M",
                        orientation=False)
    result = calibrate(four_bar, measured, list(true), "M")
    back = mechatron.load(str(result.write(tmp_path / "four_bar_built.toml")[0]))
    for name, value in true.items():
        assert back.parameter_values()[name] == pytest.approx(value, abs=1e-9)
    with pytest.raises(InputError, match="is the file four_bar was read from"):
        result.write(ROOT / "examples/data/four_bar.toml")


# ------------------------------------------------------------------------------------------ the reader
def test_reader_units_orientation_and_weights(puma, tmp_path):
    path = tmp_path / "m.csv"
    path.write_text("label,q1_deg,q2,q3,q4,q5,q6,x_mm,y,z_um,roll_deg,pitch,yaw,sigma_um,sigma_rot_arcsec\n"
                    "a,90,0,0,0,0,0,100,0.2,300,90,0,0,20,2\n")
    m = read_measurements(path, puma)
    assert m.coordinates[0, 0] == pytest.approx(math.pi / 2)
    assert m.positions[0] == pytest.approx([0.1, 0.2, 3e-4])
    assert m.rotations[0] == pytest.approx(np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0]]), abs=1e-15)
    assert m.sigma[0] == pytest.approx(2e-5) and m.sigma_rot[0] == pytest.approx(2 * math.pi / 648000)
    assert m.labels == ("a",) and m.rows == (2,)


# ------------------------------------------------------------------------------------------ command line
def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_cli_calibrates_the_example_and_writes_the_robot_file(capsys, tmp_path):
    out_file, csv = tmp_path / "puma_built.toml", tmp_path / "cal.csv"
    code, out, err = run(capsys, "calibrate", "puma560", "--measurements", EXAMPLE, "--parameters",
                         "a2,d3,d4,alpha2,alpha3,q2,q3", "-o", out_file, "--csv", csv, "--json")
    assert code == 0, err
    data = json.loads(out)
    assert data["identifiability"]["rank"] == 7 and data["measurements"] == 50
    assert [u["name"] for u in data["unknowns"]] == ["a2", "d3", "d4", "alpha2", "alpha3", "q2", "q3"]
    back = mechatron.load(str(out_file))
    assert back.parameter_values()["a2"] == pytest.approx(data["unknowns"][0]["identified"], abs=1e-15)
    assert csv.read_text().startswith("name,kind,unit,nominal,identified,change,std_error,identifiable")



def test_cli_report_holds_the_unknowns_method_and_residuals(capsys, tmp_path):
    """``--report``: one HTML file with the identified values (as the JSON gives them), the method and identifiability
    sections and the residual chart."""
    import re

    report = tmp_path / "cal.html"
    code, out, err = run(capsys, "calibrate", "puma560", "--measurements", EXAMPLE, "--parameters", "a2,d3",
                         "--report", report, "--json")
    assert code == 0, err
    text, data = report.read_text(encoding="utf-8"), json.loads(out)
    assert re.findall(r"<h2[^>]*>(.*?)</h2>", text)[1:] == ["Unknowns", "Method", "Identifiability", "Residuals"]
    assert "Levenberg" in text and "<img" in text
    identified = data["unknowns"][0]["identified"]
    assert f"{identified:.6g}" in text  # the table shows 6 significant digits

BAD = [
    ("fewer rows than unknowns", "q1,q2,q3,q4,q5,q6,x,y,z\n0,0,0,0,0,0,0.5,0,0.8\n", "a2,d3,d4,alpha2",
     "m.csv: 1 measurement gives 3 equations (3 per row) for 4 unknowns: give at least 2 rows"),
    ("NaN position", "q1,q2,q3,q4,q5,q6,x,y,z\n0,0,0,0,0,0,nan,0,0.8\n0,1,0,0,0,0,0.5,0,0.8\n", "a2",
     "m.csv: row 2: field 'x': not a finite number: 'nan'"),
    ("unknown parameter", "q1,q2,q3,q4,q5,q6,x,y,z\n0,0,0,0,0,0,0.5,0,0.8\n0,1,0,0,0,0,0.5,0,0.8\n", "a2,a9",
     "unknown parameter or joint of puma560 'a9'"),
    ("missing column", "q1,q2,q3,q4,q5,q6,x,y\n0,0,0,0,0,0,0.5,0\n", "a2",
     "m.csv: field 'z': missing column(s) z"),
    ("wrong unit", "q1,q2,q3,q4,q5,q6,x_deg,y,z\n0,0,0,0,0,0,0.5,0,0.8\n", "a2",
     "m.csv: field 'x_deg': x is a length: unknown unit 'deg'"),
    ("a sigma <= 0", "q1,q2,q3,q4,q5,q6,x,y,z,sigma_mm\n0,0,0,0,0,0,0.5,0,0.8,0\n", "a2",
     "m.csv: row 2: field 'sigma_mm': a standard deviation must be > 0"),
    ("a part of the orientation", "q1,q2,q3,q4,q5,q6,x,y,z,roll\n0,0,0,0,0,0,0.5,0,0.8,0\n", "a2",
     "m.csv: field 'pitch': an orientation is roll, pitch and yaw"),
]


@pytest.mark.parametrize("what, text, parameters, message", BAD, ids=[b[0] for b in BAD])
def test_cli_bad_inputs_exit_2_with_one_line_and_write_nothing(capsys, tmp_path, monkeypatch, what, text,
                                                               parameters, message):
    monkeypatch.chdir(tmp_path)
    Path("m.csv").write_text(text)
    code, out, err = run(capsys, "calibrate", "puma560", "--measurements", "m.csv", "--parameters", parameters,
                         "-o", "built.toml", "--csv", "cal.csv")
    assert code == 2 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], err
    assert not Path("built.toml").exists() and not Path("cal.csv").exists()


def test_cli_refuses_an_output_of_another_kind_before_any_work(capsys, tmp_path):
    code, _, err = run(capsys, "calibrate", "puma560", "--measurements", EXAMPLE, "--parameters", "a2",
                       "-o", tmp_path / "built.csv")
    assert code == 2 and "a calibrated mechanism is a robot or mechanism file (.toml) or a URDF (.urdf)" in err


def test_result_protocol(puma, readings):
    measured = simulate(puma, puma.with_parameters(BUILT), OFFSETS, readings[:10], noise=2e-5,
                        rotation_noise=1e-5, rng=np.random.default_rng(3))
    result = calibrate(puma, measured, ["a2", "d3", "q2"])
    check_result(result)
    table = result.to_frame()
    assert list(table["name"]) == ["a2", "d3", "q2"] and set(table["unit"]) == {"m", "rad"}
    figure = result.plot()
    assert figure.axes[0].get_ylabel() == "position error |Δr| (mm)"
    text = str(result)
    assert "identifiability: rank 3 of 3" in text and "rotation error (deg)" in text
    assert len(result.residuals()) == 10


def test_the_generator_writes_the_shipped_measurements():
    import importlib.util

    spec = importlib.util.spec_from_file_location("make_calibration", EXAMPLE.parent / "make_calibration_puma560.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    assert module.measurements() == EXAMPLE.read_text()


def test_a_urdf_arm_with_a_continuous_joint_calibrates_and_writes_its_urdf(tmp_path):
    """turret_arm.urdf: two joint-origin parameters and the offsets of its continuous and revolute joints,
    recovered noise-free; the URDF written reads back as the machine measured."""
    arm = mechatron.load(str(ROOT / "examples/data/turret_arm.urdf"))
    nominal = arm.parameter_values()
    true = {"shoulder_z": nominal["shoulder_z"] + 1e-3, "extend_x": nominal["extend_x"] - 5e-4}
    offsets = {"turn": 1e-3, "shoulder": -2e-3}
    rng = np.random.default_rng(0)
    read = np.column_stack([rng.uniform(-3, 3, 20), rng.uniform(-0.5, 1.5, 20), rng.uniform(0, 0.3, 20)])
    measured = simulate(arm, arm.with_parameters(true), offsets, read)
    result = calibrate(arm, measured, [*true, *offsets])
    for name, value in {**true, **offsets}.items():
        assert result.unknown(name).identified == pytest.approx(value, abs=1e-9)
    back = mechatron.load(str(result.write(tmp_path / "turret_built.urdf")[0]))
    for q, p in zip(measured.coordinates, measured.positions):
        assert np.allclose(mechatron.frame_placement(back, back.configuration(q), "tool").translation, p, atol=1e-10)
    with pytest.raises(InputError, match="write it as .urdf"):
        result.write(tmp_path / "turret_built.toml")


FULL = ["a2", "d3", "d4", "alpha2", "alpha3", "q2", "q3"]  # the offsets the example was simulated with


def test_residuals_consistent_with_their_sigma_give_no_note():
    """The shipped example identifies every simulated offset: σ̂ ≈ 1 and the χ² test accepts it."""
    result = calibrate(mechatron.load("puma560"), EXAMPLE, FULL)
    assert result.notes == () and 0.7 < result.sigma < 1.3


def test_a_missing_error_source_fails_the_chi2_test():
    """Without the twist and encoder offsets the residuals are far above the σ of the file: a note says so."""
    result = calibrate(mechatron.load("puma560"), EXAMPLE, ["a2", "d3", "d4"])
    assert result.sigma > 5 and len(result.notes) == 1 and "χ² test rejects" in result.notes[0]
    assert result.as_dict()["notes"] == list(result.notes) and "note: the residuals" in str(result)


def test_an_outlier_is_named(tmp_path):
    """One measurement 3 mm off (150 σ) in x: the note names it by label and row."""
    lines = EXAMPLE.read_text(encoding="utf-8").splitlines()
    header = next(i for i, line in enumerate(lines) if not line.startswith("#"))
    columns = lines[header].split(",")
    target = header + 17  # the 17th measurement
    cells = lines[target].split(",")
    label = cells[0]
    cells[columns.index("x_mm")] = f"{float(cells[columns.index('x_mm')]) + 3.0:.6f}"
    lines[target] = ",".join(cells)
    path = tmp_path / "outlier.csv"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    result = calibrate(mechatron.load("puma560"), path, FULL)
    assert len(result.notes) == 1 and f"measurement {label} (row {target + 1})" in result.notes[0]


def test_readings_outside_the_joint_limits_warn(tmp_path):
    puma = mechatron.load("puma560")
    upper = puma.model.upperPositionLimit[0]
    path = tmp_path / "m.csv"
    rows = [f"{q1},0,0,0,0,0,0.5,0,0.8" for q1 in (0.0, 0.3, upper + 0.5)]
    path.write_text("label,q1,q2,q3,q4,q5,q6,x,y,z\n" + "\n".join(f"p{i + 1}," + r for i, r in enumerate(rows)),
                    encoding="utf-8")
    with pytest.warns(mechatron.LimitWarning, match="measurement p3"):
        calibrate(puma, path, ["a2"])
