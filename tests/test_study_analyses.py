"""The ``sizing`` and ``accuracy`` analyses of a study (mechatron/studies/analyses): their outputs against the
sizing called directly, a hand calculation of the payload's gravity torque, closed forms of a planar 2R's error,
finite differences of a closed loop's tool position, and the refusals of bad options."""

from __future__ import annotations

import json
import math
import types
from pathlib import Path

import numpy as np
import pytest
from scipy.stats import norm

import mechatron
from mechatron.drives.catalogs import read_catalog
from mechatron.drives.sizing import size_mechanism
from mechatron.dynamics.task import read_task
from mechatron.errors import InputError, MechatronError, MechatronWarning
from mechatron.kinematics.frames import frame_position
from mechatron.kinematics.loops import assemble
from mechatron.studies.analyses import analysis

ROOT = Path(__file__).resolve().parent.parent
sizing = analysis("sizing")
accuracy = analysis("accuracy")
PUMA_A2, PUMA_A3, PUMA_D4 = 0.4318, 0.0203, 0.43180


@pytest.fixture(scope="module")
def puma():
    return mechatron.load("puma560")


@pytest.fixture(scope="module")
def bucket():
    return mechatron.load("six_bar_bucket")


def write(folder: Path, name: str, text: str) -> str:
    path = folder / name
    path.write_text(text)
    return str(path)


# ------------------------------------------------------------------------------------------------------ sizing
@pytest.mark.parametrize("scale", [(1.0, 1.0, 1.0), (1.1, 0.9, 1.1)])
def test_sizing_outputs_equal_the_sizing_called_directly(puma, scale):
    """A PUMA design (a2, a3, d4 scaled): the outputs are the totals of size_mechanism for the same task and
    catalogs (mass, cost, smallest margin, energy, peak power)."""
    design = puma.with_parameters(a2=PUMA_A2 * scale[0], a3=PUMA_A3 * scale[1], d4=PUMA_D4 * scale[2])
    out = sizing.outputs(design, {}, seed=0)
    assert set(out) == set(sizing.OUTPUTS)
    json.dumps(out, allow_nan=False)  # plain numbers, none NaN or infinite
    task = read_task(ROOT / "robots" / "tasks" / "puma560.toml", design)
    catalogs = {kind: read_catalog(ROOT / "catalogs" / name, kind) for kind, name in
                (("motors", "servo_motors.csv"), ("gearboxes", "gearboxes.csv"))}
    direct = size_mechanism(task.mechanism, task.trajectory, **catalogs, loads=task.loads, task=task.name)
    assert out["feasible"] is True and direct.feasible
    assert out["drive_mass_kg"] == pytest.approx(sum(j.drive_mass() for j in direct.joints), rel=1e-12)
    assert out["drive_cost"] == pytest.approx(sum(j.drive_price() for j in direct.joints), rel=1e-12)
    assert out["smallest_margin"] == pytest.approx(min(j.smallest_margin() for j in direct.joints), rel=1e-12)
    totals = direct.totals()
    assert out["energy_per_cycle_J"] == pytest.approx(totals["energy_per_cycle_J"], rel=1e-9)
    assert out["peak_power_W"] == pytest.approx(totals["peak_bus_power_W"], rel=1e-9)
    assert out["cycle_time_s"] == pytest.approx(task.trajectory.t[-1] - task.trajectory.t[0], rel=1e-9)


def test_sizing_longer_upper_arm_loads_the_shoulder_by_the_weight_times_the_extra_length(puma):
    """a2 + 10 %: everything beyond joint 2 — links 2…6 (their centres are fixed in their own frames, which sit at
    the far ends of the links) and the 2.5 kg payload — moves Δa2 along link 2, whose axis x2 has the horizontal
    component cos q2, so the gravity torque at the shoulder grows by M g Δa2 cos q2 with
    M = 17.4 + 4.8 + 0.82 + 0.34 + 0.09 + 2.5 = 25.95 kg (robots/puma560.toml, robots/tasks/puma560.toml). The
    outputs that follow the torque grow; the drives' mass cannot shrink."""
    options = {"single_pass": True}  # weightless drives: the masses above are all that moves
    base, longer = puma, puma.with_parameters(a2=1.1 * PUMA_A2)
    results = [sizing.run(m, options) for m in (base, longer)]
    shoulder = [next(j for j in r.joints if j.joint == "q2") for r in results]
    q2 = read_task(ROOT / "robots" / "tasks" / "puma560.toml", base).trajectory.q[:, 1]
    expected = 25.95 * 9.81 * (0.1 * PUMA_A2) * np.cos(q2)
    np.testing.assert_allclose(shoulder[1].duty.static_torque - shoulder[0].duty.static_torque, expected,
                               rtol=1e-9, atol=1e-9)
    before, after = (sizing.summary(m, r) for m, r in zip((base, longer), results))
    assert after["drive_mass_kg"] >= before["drive_mass_kg"]
    assert after["energy_per_cycle_J"] > before["energy_per_cycle_J"]
    assert after["peak_power_W"] > before["peak_power_W"]


def test_sizing_infeasible_design_is_a_row_of_the_closest_drives(puma, tmp_path):
    """Only the three smallest motors of the example catalog: no drive passes, feasible is false, the smallest
    margin negative, and the mass and cost those of the closest pairs, added up from the catalog files by key."""
    lines = (ROOT / "catalogs" / "servo_motors.csv").read_text().splitlines()
    motors = write(tmp_path, "small_motors.csv", "\n".join(lines[:5]) + "\n")
    out = sizing.outputs(puma, {"motors": motors, "single_pass": True}, seed=0)
    assert out["feasible"] is False and out["smallest_margin"] < 0
    assert all(math.isfinite(v) for v in out.values())
    result = sizing.run(puma, {"motors": motors, "single_pass": True})
    rows = {}
    for path in (Path(motors), ROOT / "catalogs" / "gearboxes.csv"):
        for line in path.read_text().splitlines()[2:]:
            cells = line.split(",")
            rows[cells[0]] = (float(cells[-2]), float(cells[-1]))  # every catalog here ends with mass, price
    mass = cost = 0.0
    for joint in result.joints:
        first = joint.closest.iloc[0] if not joint.feasible else joint.ranking.iloc[0]
        for key in (first["motor"], first["converter"]):
            mass += rows.get(key, (0.0, 0.0))[0]
            cost += rows.get(key, (0.0, 0.0))[1]
    assert out["drive_mass_kg"] == pytest.approx(mass, rel=1e-12)
    assert out["drive_cost"] == pytest.approx(cost, rel=1e-12)


def test_sizing_of_a_cylinder_mechanism(bucket):
    """The bucket's cylinder: the catalog's mass and price, the pump's peak power as the peak power."""
    out = sizing.outputs(bucket, {"objective": "cost"}, seed=0)
    result = sizing.run(bucket, {"objective": "cost"})
    assert out["feasible"] is True
    assert out["drive_cost"] == pytest.approx(result.joints[0].ranking["price"].min(), rel=1e-12)
    assert out["peak_power_W"] == pytest.approx(result.totals()["peak_pump_power_W"], rel=1e-12)


@pytest.mark.parametrize("options, field", [
    ({"motor": "x.csv"}, "motor"),
    ({"motors": "no_such_catalog.csv"}, "motors"),
    ({"gearboxes": "no_such_catalog.csv"}, "gearboxes"),
    ({"task": "no_such_task.toml"}, "task"),
    ({"objective": "speed"}, "objective"),
    ({"pressure_MPa": -1}, "pressure_MPa"),
    ({"max_iterations": 2.5}, "max_iterations"),
    ({"direct": "yes"}, "direct"),
    ({"stop_torque": 1.0, "stop_current": 2.0}, "stop_current"),
])
def test_sizing_check_refuses_bad_options_naming_the_field(puma, options, field):
    with pytest.raises(InputError, match=rf"^\[analyses\.sizing\] {field}: "):
        sizing.check(puma, options)


def test_sizing_reads_the_old_spelling_of_the_pressure_with_a_warning(puma):
    # pressure_mpa was the option's spelling before the quantities' registry (mechatron.quantities.RENAMED)
    with pytest.warns(MechatronWarning, match=r"^\[analyses\.sizing\] pressure_mpa: renamed pressure_MPa"):
        old = sizing.arguments(puma, {"pressure_mpa": 20})
    assert old["pressure"] == 20e6 == sizing.arguments(puma, {"pressure_MPa": 20})["pressure"]
    with pytest.raises(InputError, match=r"^\[analyses\.sizing\] pressure_mpa: give pressure_MPa only"):
        sizing.check(puma, {"pressure_mpa": 20, "pressure_MPa": 20})


def test_sizing_check_refuses_a_bad_catalog_naming_file_row_and_field(puma, tmp_path):
    lines = (ROOT / "catalogs" / "servo_motors.csv").read_text().splitlines()
    bad = lines[2].split(",")
    bad[3] = "-1"  # rated torque
    path = write(tmp_path, "bad.csv", "\n".join([lines[1], ",".join(bad)]) + "\n")
    with pytest.raises(InputError, match=r"^\[analyses\.sizing\] motors: .*bad\.csv: row 2: field 'rated_torque'"):
        sizing.check(puma, {"motors": path})


def test_sizing_check_refuses_a_mechanism_without_actuated_joints():
    frame = types.SimpleNamespace(name="frame", closures=[], actuated=[], joint_names=[])
    with pytest.raises(InputError, match=r"^\[analyses\.sizing\] frame has no actuated joint"):
        sizing.check(frame, {})


# ---------------------------------------------------------------------------------------------------- accuracy
def planar_2r_files(folder: Path) -> dict:
    poses = write(folder, "poses.csv", "label,q1_deg,q2_deg\nA,0,90\nB,30,-60\nC,-120,150\n")
    tolerances = write(folder, "tolerances.csv", "parameter,tolerance,distribution\n"
                       "a1,2e-4,normal\na2,1e-4,normal\nq1,1e-3,normal\nq2,5e-4,normal\n")
    return {"tolerances": tolerances, "poses": poses, "limit_mm": 5.0, "samples": 2000}


def test_accuracy_worst_case_and_rss_of_a_planar_2r_are_the_closed_forms(tmp_path):
    """r = (l1 c1 + l2 c12, l1 s1 + l2 s12): ∂r/∂l1 = (c1, s1), ∂r/∂l2 = (c12, s12), ∂r/∂q1 = (−y, x),
    ∂r/∂q2 = (−l2 s12, l2 c12). Worst case per axis Σ|∂r/∂e| t, its modulus [Egorov, 8.6]; RSS with normal errors
    (σ = t/3, k = 3) √Σ(∂r/∂e t)² per axis; both the largest over the poses."""
    options = planar_2r_files(tmp_path)
    mech = mechatron.load("planar_2r")
    accuracy.check(mech, options)
    out = accuracy.outputs(mech, options, seed=7)
    assert set(out) == set(accuracy.OUTPUTS)
    json.dumps(out, allow_nan=False)
    l1, l2, t = 0.5, 0.4, np.array([2e-4, 1e-4, 1e-3, 5e-4])
    worst, rss = [], []
    for q1, q2 in np.radians([[0, 90], [30, -60], [-120, 150]]):
        x, y = l1 * math.cos(q1) + l2 * math.cos(q1 + q2), l1 * math.sin(q1) + l2 * math.sin(q1 + q2)
        J = np.array([[math.cos(q1), math.cos(q1 + q2), -y, -l2 * math.sin(q1 + q2)],
                      [math.sin(q1), math.sin(q1 + q2), x, l2 * math.cos(q1 + q2)]])
        worst.append(np.hypot(*(np.abs(J) @ t)))
        rss.append(np.hypot(*np.sqrt((J * t) ** 2 @ np.ones(4))))
    assert out["worst_case_mm"] == pytest.approx(max(worst) * 1e3, rel=1e-9)
    assert out["rss_mm"] == pytest.approx(max(rss) * 1e3, rel=1e-9)
    assert 0 < out["mc_quantile_mm"] < out["worst_case_mm"]
    assert out["yield"] == 1.0  # 5 mm: about 15 standard deviations of |Δr|


def test_accuracy_monte_carlo_is_seeded_and_within_its_standard_error(tmp_path):
    """One source, l1 ± t normal (σ = t/3): Δr = Δl1 (c1, s1) exactly, so |Δr| is half-normal: its p quantile is
    σ Φ⁻¹((1 + p)/2) with standard error √(p(1 − p)/n) / f, f = 2 φ(z)/σ its density there, and the yield
    within L = σ is erf(1/√2) with standard error √(y(1 − y)/n). The same seed gives the same row, another seed
    another row within 4 standard errors of the closed forms."""
    t, p, n = 3e-4, 0.9, 20000
    sigma = t / 3
    tolerances = write(tmp_path, "l1.csv", f"parameter,tolerance,distribution\na1,{t},normal\n")
    options = {"tolerances": tolerances, "samples": n, "quantile": p, "limit_mm": sigma * 1e3}
    mech = mechatron.load("planar_2r")
    first, again, other = (accuracy.outputs(mech, options, seed) for seed in (11, 11, 12))
    assert first == again
    assert first != other
    z = norm.ppf((1 + p) / 2)
    quantile, quantile_se = sigma * z, math.sqrt(p * (1 - p) / n) / (2 * norm.pdf(z) / sigma)
    share = math.erf(1 / math.sqrt(2))
    share_se = math.sqrt(share * (1 - share) / n)
    for out in (first, other):
        assert abs(out["mc_quantile_mm"] * 1e-3 - quantile) < 4 * quantile_se
        assert abs(out["yield"] - share) < 4 * share_se
        assert out["worst_case_mm"] == pytest.approx(t * 1e3, rel=1e-12)


@pytest.mark.parametrize("scale", [(1.05, 0.95), (0.95, 1.05)])
def test_accuracy_of_a_closed_loop_design_is_the_finite_difference_stack_up(bucket, tmp_path, scale):
    """The bucket with c and L2 ± 5 %: the worst case Σ|∂r/∂e| t of the tool K per axis, ∂r/∂e by central
    differences of the rebuilt and re-assembled mechanism at the same cylinder length, the largest over the
    poses; the Monte Carlo of the full loops within it."""
    values = bucket.parameter_values()
    design = bucket.with_parameters(c=values["c"] * scale[0], L2=values["L2"] * scale[1])
    poses = write(tmp_path, "poses.csv", "label,L1\nin,1.3\nout,1.8\n")
    tolerances = write(tmp_path, "tolerances.csv", "parameter,tolerance_mm,distribution\nc,0.5,normal\n"
                       "L2,0.3,normal\n")
    options = {"tolerances": tolerances, "poses": poses, "limit_mm": 5.0, "samples": 500}
    out = accuracy.outputs(design, options, seed=3)
    parameters = design.parameter_values()

    def tool(name: str, step: float, length: float) -> np.ndarray:
        moved = design.with_parameters({name: parameters[name] + step})
        return frame_position(moved, assemble(moved, {"L1": length}), "K")

    worst = []
    for length in (1.3, 1.8):
        stack = sum(np.abs(tool(name, 1e-6, length) - tool(name, -1e-6, length)) / 2e-6 * t
                    for name, t in (("c", 0.5e-3), ("L2", 0.3e-3)))
        worst.append(np.linalg.norm(stack))
    assert out["worst_case_mm"] == pytest.approx(max(worst) * 1e3, rel=1e-5)
    assert 0 < out["mc_quantile_mm"] < out["worst_case_mm"]
    assert 0 <= out["yield"] <= 1


def test_accuracy_of_puma_designs(puma):
    """The PUMA with a2, a3, d4 ± 10 % over the example poses: finite outputs, the Monte Carlo quantile below the
    worst case; a longer arm magnifies the joint errors: a larger worst case."""
    options = {"tolerances": str(ROOT / "examples" / "data" / "tolerances_puma560.csv"),
               "poses": str(ROOT / "examples" / "data" / "poses_puma560.csv"), "limit_mm": 0.3, "samples": 1000}
    rows = [accuracy.outputs(puma.with_parameters(a2=PUMA_A2 * s, a3=PUMA_A3 * s, d4=PUMA_D4 * s), options, 5)
            for s in (0.9, 1.1)]
    for row in rows:
        assert all(math.isfinite(v) for v in row.values())
        assert 0 < row["mc_quantile_mm"] < row["worst_case_mm"] and 0 <= row["yield"] <= 1
    assert rows[1]["worst_case_mm"] > rows[0]["worst_case_mm"]


def test_accuracy_design_whose_loops_do_not_close_raises_with_the_pose(bucket, tmp_path):
    """L2 = 0.4 m: the bucket builds at its drawing but the loops do not close at the retracted cylinder."""
    poses = write(tmp_path, "poses.csv", "label,L1\nretracted,1.1\nextended,2.0\n")
    tolerances = write(tmp_path, "tolerances.csv", "parameter,tolerance_mm\nc,0.5\n")
    options = {"tolerances": tolerances, "poses": poses, "limit_mm": 5.0, "samples": 100}
    with pytest.raises(MechatronError, match=r"pose retracted: .*loops do not close") as caught:
        accuracy.outputs(bucket.with_parameters(L2=0.4), options, seed=0)
    assert not isinstance(caught.value, InputError)  # the design's failure, a row's reason, not a bad spec


@pytest.mark.parametrize("change, field", [
    ({"tolerance": "x.csv"}, "tolerance"),
    ({"tolerances": None}, "tolerances"),
    ({"limit_mm": None}, "limit_mm"),
    ({"limit_mm": -1}, "limit_mm"),
    ({"quantile": 1.5}, "quantile"),
    ({"quantile": 1.0}, "quantile"),
    ({"samples": 1}, "samples"),
    ({"samples": 2_000_000}, "samples"),
    ({"k": 0}, "k"),
    ({"frame": "nowhere"}, "frame"),
    ({"grid": 3}, "grid"),
    ({"poses": "no_such_poses.csv"}, "poses"),
    ({"tolerances": "no_such_tolerances.csv"}, "tolerances"),
])
def test_accuracy_check_refuses_bad_options_naming_the_field(tmp_path, change, field):
    options = {**planar_2r_files(tmp_path), **change}
    options = {k: v for k, v in options.items() if v is not None}
    with pytest.raises(InputError, match=rf"^\[analyses\.accuracy\] {field}: "):
        accuracy.check(mechatron.load("planar_2r"), options)


def test_accuracy_check_refuses_a_tolerance_of_an_unknown_parameter_naming_the_row(tmp_path):
    options = planar_2r_files(tmp_path)
    write(tmp_path, "tolerances.csv", "parameter,tolerance\na1,1e-4\nl9,1e-4\n")
    with pytest.raises(InputError, match=r"^\[analyses\.accuracy\] tolerances: .*row 3: field 'parameter'"):
        accuracy.check(mechatron.load("planar_2r"), options)


# -------------------------------------------------------------------------------------------------------- docs
def test_the_example_of_the_docs_page_runs_on_puma_designs(puma):
    """The TOML block of docs/study_analyses.md, its paths relative to examples/ (where such a spec sits), checks
    and runs on a PUMA design; its sizing equals the sizing of the same task and catalogs called directly."""
    import tomllib

    text = (ROOT / "docs" / "study_analyses.md").read_text(encoding="utf-8")
    spec = tomllib.loads(text.split("```toml\n", 1)[1].split("```", 1)[0])["analyses"]
    folder = ROOT / "examples"
    for name in ("sizing", "accuracy"):
        for field in ("task", "motors", "gearboxes", "tolerances", "poses"):
            if field in spec[name]:
                spec[name][field] = str(folder / spec[name][field])
        analysis(name).check(puma, spec[name])
    design = puma.with_parameters(a2=PUMA_A2 * 1.05, d4=PUMA_D4 * 0.95)
    out = sizing.outputs(design, spec["sizing"], seed=1)
    task = read_task(folder / "data" / "pick_and_place.toml", design)
    direct = size_mechanism(task.mechanism, task.trajectory, read_catalog(folder / "data" / "motors.csv", "motors"),
                            read_catalog(folder / "data" / "gearboxes.csv", "gearboxes"), loads=task.loads,
                            chain_efficiency=0.95)
    assert out["drive_mass_kg"] == pytest.approx(direct.totals()["drive_mass_kg"], rel=1e-12)
    assert out["feasible"] == direct.feasible
    row = accuracy.outputs(design, spec["accuracy"], seed=1)
    assert all(math.isfinite(v) for v in row.values()) and 0 <= row["yield"] <= 1
