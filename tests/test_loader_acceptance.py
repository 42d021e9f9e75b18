r"""The wheel-loader case of issue 32 as tests, on its own small files (tests/data/loader/): a lift arm whose boom
rides on a pair of lift cylinders (``count = 2``) and whose bucket tilts through a Z-bar bell crank
(``loader_arm.toml``), a 1,500 kg lift-and-dump task (``lift_dump.toml``), an own cylinder catalog
(``cylinders.csv``) and a design file moving the lift cylinders' base pin (``loader_design.toml``).

References:

* **Free-body diagrams** at the drawn pose (the link and the cylinders are weightless, so each is a two-force
  member along its pins; ``×`` is the planar cross product r_x F_y − r_y F_x, W_i = (0, −m_i g)):
  the bucket about its hinge H, with the link's tension f along E→L,
  f (E − H) × u_EL + Σ_bucket (c_i − H) × W_i = 0;
  the bell crank about its pivot K, with the tilt cylinder's push F_t along C→T,
  F_t (T − K) × u_CT + f (L − K) × u_LE = 0 (its own weight acts at K);
  the boom with everything it carries about the boom pivot O, with the lift cylinders' push F along A→B,
  F (B − O) × u_AB + F_t (T − O) × u_CT + Σ_all (c_i − O) × W_i = 0.
  F is the force of both lift cylinders together (what ``dynamics`` reports for ``count = 2``).
* **``mechatron dynamics``** of the same payload at rest (a trajectory CSV with zero speeds and accelerations): the
  study's linkage forces at a pose and over its sweep, and of the same waypoints: the study's dynamics analysis.
* **The optimum's own report**: ``mechatron optimize -o`` writes a design that, read back as a file and run through
  ``mechatron study``, gives the reported outputs.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from mechatron.cli import main
from mechatron.io.toml import tomllib

DATA = Path(__file__).resolve().parent / "data" / "loader"
ARM, TASK, DESIGN = DATA / "loader_arm.toml", DATA / "lift_dump.toml", DATA / "loader_design.toml"
G, PAYLOAD = 9.81, 1500.0
FILE = tomllib.loads(ARM.read_text())
POINTS = {name: np.array(xy, dtype=float) for name, xy in FILE["points"].items()}
DRAWN = {"lift": math.dist(POINTS["A"], POINTS["B"]), "tilt": math.dist(POINTS["C"], POINTS["T"])}  # m


def cross(r: np.ndarray, f: np.ndarray) -> float:
    return float(r[0] * f[1] - r[1] * f[0])


def unit(a: str, b: str) -> np.ndarray:
    d = POINTS[b] - POINTS[a]
    return d / np.linalg.norm(d)


def weights(*bodies: str) -> list[tuple[np.ndarray, np.ndarray]]:
    """(centre, weight) of the bodies named, from the file's masses and centres (a point name or coordinates)."""
    out = []
    for body in FILE["bodies"]:
        if body["name"] in bodies and body.get("mass", 0.0) > 0:
            com = body["com"]
            centre = POINTS[com] if isinstance(com, str) else np.array(com, dtype=float)
            out.append((centre, np.array([0.0, -body["mass"] * G])))
    return out


def hand_forces() -> tuple[float, float]:
    """The lift cylinders' total force and the tilt cylinder's (N, pushing > 0) holding the drawn pose with the
    payload at P: the three free-body diagrams of the module docstring."""
    p = POINTS
    bucket = weights("bucket") + [(p["P"], np.array([0.0, -PAYLOAD * G]))]
    f = -sum(cross(c - p["H"], w) for c, w in bucket) / cross(p["E"] - p["H"], unit("E", "L"))
    tilt = -f * cross(p["L"] - p["K"], unit("L", "E")) / cross(p["T"] - p["K"], unit("C", "T"))
    everything = bucket + weights("boom", "bellcrank")
    moment = sum(cross(c - p["O"], w) for c, w in everything) + tilt * cross(p["T"] - p["O"], unit("C", "T"))
    return -moment / cross(p["B"] - p["O"], unit("A", "B")), tilt


def at_rest(path: Path, poses: list[tuple[float, float]]) -> Path:
    """A trajectory CSV at rest at each pose (lift, tilt in m) in turn: speeds and accelerations given as zero."""
    poses = [(float(lift), float(tilt)) for lift, tilt in poses]
    rows = [f"{k},{lift!r},{tilt!r},0,0,0,0" for k, (lift, tilt) in enumerate(poses)]
    path.write_text("t,lift,tilt,qd_lift,qd_tilt,qdd_lift,qdd_tilt\n" + "\n".join(rows + [
        f"{len(poses)},{poses[-1][0]!r},{poses[-1][1]!r},0,0,0,0"]) + "\n")
    return path


def dynamics(capsys, *args: str) -> dict[str, dict]:
    """``mechatron dynamics loader_arm.toml ARGS --payload 1500 --payload-at P --json``: per coordinate."""
    assert main(["dynamics", str(ARM), *args, "--payload", str(PAYLOAD), "--payload-at", "P", "--json"]) == 0
    return {c["coordinate"]: c for c in json.loads(capsys.readouterr().out)["coordinates"]}


def test_the_holding_forces_at_the_drawn_pose_are_the_free_body_diagrams(tmp_path, capsys):
    lift, tilt = hand_forces()
    assert lift == pytest.approx(106862.22, rel=1e-7) and tilt == pytest.approx(34888.185, rel=1e-7)
    hold = at_rest(tmp_path / "hold.csv", [(DRAWN["lift"], DRAWN["tilt"])])
    out = dynamics(capsys, "--trajectory", str(hold))
    assert out["lift"]["cylinders"] == 2 and out["lift"]["load"] == "force"
    assert out["lift"]["peak_force"] == pytest.approx(lift, rel=1e-9)
    assert out["tilt"]["peak_force"] == pytest.approx(tilt, rel=1e-9)
    # the signs: both cylinders push (the CSV's signed forces)
    assert main(["dynamics", str(ARM), "--trajectory", str(hold), "--payload", str(PAYLOAD), "--payload-at", "P",
                 "--csv", str(tmp_path / "forces.csv")]) == 0
    capsys.readouterr()
    table = pd.read_csv(tmp_path / "forces.csv")
    assert np.allclose(table["tau_lift"], lift, rtol=1e-9) and np.allclose(table["tau_tilt"], tilt, rtol=1e-9)


STUDY = """mechanism = "{arm}"
[parameters.A_x]
values = [0.55, 0.6]           # m: the lift cylinders' base pin, the drawing's 0.6 and 0.55
[designs]
method = "grid"
[analyses.linkage]
samples = 5
task = "{task}"
[[analyses.linkage.poses]]
name = "drawn"
inputs = {{ lift = {lift!r}, tilt = {tilt!r} }}
[[analyses.linkage.poses]]
name = "dumped"
inputs = {{ lift = 1.12, tilt = 1.32 }}
[analyses.dynamics]
task = "{task}"
"""


def test_a_studys_cylinder_forces_are_the_dynamics_of_the_same_task_and_payload(tmp_path, capsys):
    spec = tmp_path / "loader_study.toml"
    spec.write_text(STUDY.format(arm=ARM, task=TASK, **DRAWN))
    assert main(["study", str(spec), "--out", str(tmp_path / "study")]) == 0
    capsys.readouterr()
    rows = pd.read_parquet(tmp_path / "study" / "designs.parquet").set_index("A_x")
    assert list(rows["status"]) == ["ok", "ok"]
    task = tomllib.loads(TASK.read_text())
    assert task["payload"] == PAYLOAD and task["payload_at"] == "P"
    stroke = {j["name"]: np.array(j["stroke_mm"]) / 1000 for j in FILE["joints"] if j["type"] == "cylinder"}
    sweep = list(zip(np.linspace(*stroke["lift"], 5), np.linspace(*stroke["tilt"], 5)))
    move = ";".join(",".join(str(v) for v in w) for w in task["waypoints"])
    for a_x, row in rows.iterrows():
        design = ["--set", f"A_x={a_x!r}"]
        for pose, inputs in (("drawn", (DRAWN["lift"], DRAWN["tilt"])), ("dumped", (1.12, 1.32))):
            out = dynamics(capsys, *design, "--trajectory", str(at_rest(tmp_path / f"{pose}.csv", [inputs])))
            for cylinder in ("lift", "tilt"):
                assert row[f"{pose}.{cylinder}_max_force_N"] == pytest.approx(out[cylinder]["peak_force"], rel=1e-9)
        # over the sweep (both strokes end to end together): the largest of the forces at rest at its positions
        out = dynamics(capsys, *design, "--trajectory", str(at_rest(tmp_path / "sweep.csv", sweep)))
        for cylinder in ("lift", "tilt"):
            assert row[f"{cylinder}_max_force_N"] == pytest.approx(out[cylinder]["peak_force"], rel=1e-9)
        # the dynamics analysis of the lift-and-dump task: the same waypoints and profile on the command line
        out = dynamics(capsys, *design, "--move", move, "--vmax", str(task["vmax"]), "--amax", str(task["amax"]),
                       "--dwell", str(task["dwell"]), "--dt", str(task["dt"]))
        for cylinder in ("lift", "tilt"):
            assert row[f"{cylinder}_peak_N"] == pytest.approx(out[cylinder]["peak_force"], rel=1e-9)
            assert row[f"{cylinder}_rms_N"] == pytest.approx(out[cylinder]["rms_force"], rel=1e-9)
    # the drawing's design at its drawn pose: the free-body diagrams, the payload included (without it the same
    # diagrams give half the lift force, 53.1 kN: the item 3)
    lift, tilt = hand_forces()
    assert rows.loc[0.6, "drawn.lift_max_force_N"] == pytest.approx(lift, rel=1e-9)
    assert rows.loc[0.6, "drawn.tilt_max_force_N"] == pytest.approx(tilt, rel=1e-9)
    assert rows.loc[0.6, "lift_peak_N"] > rows.loc[0.6, "lift_max_force_N"] > lift  # lifting higher, and moving


def test_the_optimum_with_a_moved_pin_is_written_and_reads_back_to_its_outputs(tmp_path, capsys):
    out = tmp_path / "loader_best"
    assert main(["optimize", str(DESIGN), "-o", str(out)]) == 0
    printed = capsys.readouterr().out
    best = json.loads((out / "optimum.json").read_text())["best"]
    a = np.array([best["A_x"], best["A_y"]])
    assert best["A_x"] > 0.6 and best["height_m"] >= 2.2 - 1e-6
    # the pin moved so far that the file's drawing, with A there, has the lift cylinders outside their stroke:
    assert math.dist(a, POINTS["B"]) < 0.85  # stroke [850, 1150] mm (issue 32, item 1)
    path = out / "design-000.toml"
    assert f"wrote {path}" in printed
    written = tomllib.loads(path.read_text())
    drawn = {name: np.array(xy) for name, xy in written["points"].items()}
    np.testing.assert_allclose(drawn["A"], a, atol=1e-12)
    # drawn where the search evaluated it: the cylinders at the length the file holds them at
    assert math.dist(drawn["A"], drawn["B"]) == pytest.approx(DRAWN["lift"], abs=1e-9)
    assert math.dist(drawn["C"], drawn["T"]) == pytest.approx(DRAWN["tilt"], abs=1e-9)
    for body in ("boom", "bucket"):  # a centre of mass given by coordinates rides with its body
        old = next(b for b in FILE["bodies"] if b["name"] == body)
        new = next(b for b in written["bodies"] if b["name"] == body)
        pin = "O" if body == "boom" else "H"
        assert math.dist(new["com"], drawn[pin]) == pytest.approx(math.dist(old["com"], POINTS[pin]), abs=1e-9)
    # read back through `mechatron study`: the same outputs as the optimum reported
    spec = tmp_path / "read_back.toml"
    spec.write_text(f'mechanism = "{path}"\n[parameters.samples]\ntarget = "linkage.samples"\nvalues = [5]\n'
                    f'[designs]\nmethod = "grid"\n[analyses.linkage]\ntask = "{TASK}"\n')
    assert main(["study", str(spec), "--out", str(tmp_path / "back")]) == 0
    capsys.readouterr()
    (row,) = pd.read_parquet(tmp_path / "back" / "designs.parquet").to_dict(orient="records")
    assert row["status"] == "ok"
    outputs = [k for k in best if k.endswith(("_m", "_N"))]
    assert {"lift_max_force_N", "tilt_max_force_N", "height_m"} <= set(outputs)
    for name in outputs:
        assert row[name] == pytest.approx(best[name], rel=1e-9, abs=1e-12), name


def test_the_own_cylinder_catalog_sizes_each_twin_with_half_the_force(capsys):
    """``size`` with the own catalog: each of the two lift cylinders is checked with half the force of both (the
    lift-and-dump task's peak by ``dynamics``) over its piston area π b²/4, the flow of both at the task's 0.1 m/s
    is 2 · π b²/4 · 0.1, and their mass is 2 · (mass + mass per stroke · stroke) of the catalog row."""
    task = tomllib.loads(TASK.read_text())
    move = ";".join(",".join(str(v) for v in w) for w in task["waypoints"])
    peak = dynamics(capsys, "--move", move, "--vmax", str(task["vmax"]), "--amax", str(task["amax"]),
                    "--dwell", str(task["dwell"]), "--dt", str(task["dt"]))["lift"]["peak_force"]
    cylinders = DATA / "cylinders.csv"
    code = main(["size", str(ARM), "--task", str(TASK), "--cylinders", str(cylinders), "--pressure-mpa", "20",
                 "--json"])
    data = json.loads(capsys.readouterr().out)
    assert code == 0 and data["feasible"]
    lift = next(j for j in data["joints"] if j["joint"] == "lift")
    assert lift["cylinder"] == "WL90/50" and lift["count"] == 2  # the smallest row passes
    area = math.pi * 0.090**2 / 4
    push = next(c for c in lift["checks"] if c["name"] == "push pressure")
    assert push["value"] == pytest.approx(peak / 2 / area, rel=1e-9)
    assert lift["peak_flow"] == pytest.approx(2 * area * task["vmax"], rel=1e-9)
    assert lift["drive_mass_kg"] == pytest.approx(2 * (14.0 + 38.0 * 0.300), rel=1e-12)  # stroke 850-1150 mm
