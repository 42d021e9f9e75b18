"""The pages of docs/ and the sample inputs of examples/data/ agree with the readers and with each other.

- every complete example embedded in a page (a fenced block after ``<!-- example: PATH -->``) is the shipped file
  PATH, character for character, and its text is read without error by the real reader;
- every file of examples/data/ is read by its reader for the robot it is made for, and is named in a page;
- the unit table, the catalog columns and the command options the pages list are those of the code;
- the links between pages resolve and every citation's key is in docs/references.md;
- a numeric check per sample where one is independent of mechatron (closed forms, physics of the data, Chebyshev's
  formula), and the numbers the pages quote.
"""

from __future__ import annotations

import argparse
import functools
import math
import re
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

import mechatron

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"
DATA = ROOT / "examples" / "data"
EXAMPLE = re.compile(r"<!-- example: (?P<path>\S+) -->\n```(?P<lang>\w+)\n(?P<body>.*?)```", re.S)
FORMAT_PAGES = ("robot_file.md", "urdf.md", "task_file.md", "trajectory_csv.md", "catalogs.md", "tolerances_csv.md",
                "poses_csv.md", "structure_file.md", "front_shovel_design.md", "mechanism_file.md", "design_file.md",
                "measurements_csv.md")
DEG = math.pi / 180


def pages() -> dict[str, str]:
    return {p.name: p.read_text(encoding="utf-8") for p in sorted(DOCS.glob("*.md"))}


def embedded_examples() -> list[tuple[str, str, str]]:
    """(page, path, text) of every complete example in the pages."""
    return [(name, m["path"], m["body"]) for name, text in pages().items() for m in EXAMPLE.finditer(text)]


@functools.cache
def robot(name: str, **parameters: float) -> mechatron.Mechanism:
    return mechatron.load(name, **parameters)


# ------------------------------------------------------------------------------------------------ the readers
def _robot_file(path: Path):
    from mechatron.model.robotfile import read_robot_file

    return read_robot_file(path).mechanism()


def _urdf(path: Path):
    from mechatron.model.urdf import load_urdf

    return load_urdf(path)


def _srdf(path: Path):
    import pinocchio as pin

    model = pin.buildModelFromUrdf(str(DATA / "turret_arm.urdf"))
    pin.loadRotorParameters(model, str(path), False)
    return model


def _task(robot_name: str) -> Callable[[Path], object]:
    def read(path: Path):
        from mechatron.dynamics.task import read_task

        return read_task(path, robot(robot_name))
    return read


def _trajectory(robot_name: str) -> Callable[[Path], object]:
    def read(path: Path):
        from mechatron.dynamics.motion import read_trajectory

        return read_trajectory(path, robot(robot_name))
    return read


def _catalog(kind: str) -> Callable[[Path], object]:
    def read(path: Path):
        from mechatron.drives.catalogs import read_catalog

        return read_catalog(path, kind)
    return read


def _tolerances(robot_name: str, need: str = "tolerance") -> Callable[[Path], object]:
    def read(path: Path):
        from mechatron.accuracy.sources import read_tolerances

        return read_tolerances(path, robot(robot_name), need)
    return read


def _cost_models(robot_name: str) -> Callable[[Path], object]:
    def read(path: Path):
        from mechatron.accuracy.costs import read_cost_models

        return read_cost_models(path, robot(robot_name), DATA / "processes_puma560.csv")
    return read


def _processes(path: Path):
    from mechatron.accuracy.costs import read_processes

    return read_processes(path)


def _poses(robot_name: str) -> Callable[[Path], object]:
    def read(path: Path):
        from mechatron.accuracy.sources import read_poses

        return read_poses(path, robot(robot_name))
    return read


def _measurements(robot_name: str) -> Callable[[Path], object]:
    def read(path: Path):
        from mechatron.accuracy.measurements import read_measurements

        return read_measurements(path, robot(robot_name))
    return read


def _structure(path: Path):
    from mechatron.structure.description import read_structure

    return read_structure(path)


def _mechanism(path: Path):
    from mechatron.model.linkage import build_linkage
    from mechatron.model.linkage_file import read_linkage_file

    return build_linkage(read_linkage_file(path))


def _design(path: Path):
    from mechatron.machines.excavator import read_design

    return read_design(str(path))


def _design_file(path: Path):
    """A design file, read beside the files it names (the example's mechanism file is copied next to it)."""
    import shutil

    from mechatron.optimal.reader import read_problem as read_design

    folder = ROOT / "examples" / "design"
    if path.parent != folder:
        shutil.copy(folder / "my_crank.toml", path.parent / "my_crank.toml")
    return read_design(path)


#: The reader of every sample input and every file a page embeds, by its path from the top of the source tree.
READERS: dict[str, Callable[[Path], object]] = {
    "robots/scara.toml": _robot_file,
    "examples/data/turret_arm.urdf": _urdf,
    "examples/data/turret_arm.srdf": _srdf,
    "examples/data/pick_and_place.toml": _task("puma560"),
    "examples/data/pick_and_release.toml": _task("puma560"),
    "examples/data/cartesian_line.toml": _task("planar_2r"),
    "examples/data/puma560_move.csv": _trajectory("puma560"),
    "examples/data/scara_move.csv": _trajectory("scara"),
    "examples/data/planar_2r_move.csv": _trajectory("planar_2r"),
    "examples/data/motors.csv": _catalog("motors"),
    "examples/data/gearboxes.csv": _catalog("gearboxes"),
    "examples/data/linear_drives.csv": _catalog("linear"),
    "examples/data/hydraulic_cylinders.csv": _catalog("cylinders"),
    "examples/data/tolerances_puma560.csv": _tolerances("puma560"),
    "examples/data/tolerances_crank_slider.csv": _tolerances("crank_slider", "error"),
    "examples/data/tolerances_scara.csv": _tolerances("scara"),
    "examples/data/tolerances_puma560_costs.csv": _cost_models("puma560"),
    "examples/data/processes_puma560.csv": _processes,
    "examples/data/poses_puma560.csv": _poses("puma560"),
    "examples/data/measurements_puma560.csv": _measurements("puma560"),
    "examples/data/four_bar_structure.toml": _structure,
    "examples/data/front_shovel_design.toml": _design,
    "examples/data/four_bar.toml": _mechanism,
    "examples/data/tolerances_four_bar.csv": _tolerances(str(DATA / "four_bar.toml")),
    "examples/data/scissor_lift.toml": _mechanism,
    "examples/data/tolerances_scissor_lift.csv": _tolerances(str(DATA / "scissor_lift.toml")),
    "examples/design/crank_reach.toml": _design_file,
}
SCRIPTS = {"make_samples.py", "make_calibration_puma560.py"}


def read(relative: str):
    return READERS[relative](ROOT / relative)


# ------------------------------------------------------------------------------------- docs ↔ files ↔ readers
@pytest.mark.parametrize("page, path, text", embedded_examples(), ids=lambda v: v if "\n" not in v else "text")
def test_embedded_example_is_the_shipped_file_and_reads(page, path, text, tmp_path):
    shipped = ROOT / path
    assert shipped.is_file(), f"{page} embeds {path}, which does not ship"
    assert text == shipped.read_text(encoding="utf-8"), f"{page}: the example differs from {path}"
    copy = tmp_path / shipped.name
    copy.write_text(text, encoding="utf-8")
    assert READERS[path](copy) is not None


def test_every_format_page_has_a_complete_example():
    found = {page for page, _, _ in embedded_examples()}
    assert set(FORMAT_PAGES) <= found


def test_every_sample_has_a_reader_and_a_page():
    samples = {f"examples/data/{p.name}" for p in DATA.iterdir() if p.is_file() and p.name not in SCRIPTS}
    assert samples == {k for k in READERS if k.startswith("examples/data/")}
    text = "\n".join(pages().values())
    for sample in samples:
        assert Path(sample).name in text, f"{sample} is in no page of docs/"


@pytest.mark.parametrize("path", sorted(READERS))
def test_sample_reads_for_its_robot(path):
    assert read(path) is not None


def test_links_between_pages_resolve_and_index_lists_every_page():
    for name, text in pages().items():
        for target in re.findall(r"\]\(([^)#\s]+)\)", text):
            if "://" not in target:
                assert (DOCS / target).exists(), f"{name} links to {target}, which does not exist"
    index = pages()["index.md"]
    for name in pages():
        if name != "index.md":
            assert f"]({name})" in index, f"index.md does not list {name}"


def test_citations_use_the_keys_of_references_md():
    references = pages()["references.md"]
    keys = set(re.findall(r"^\| ([^|]+?) \| ", references, re.M)) - {"key", "---"}
    assert {"Egorov", "Shovel", "ISO 286-1", "ISO 6015", "Biagiotti"} <= keys
    for name, text in pages().items():
        for key in re.findall(r"\[([A-Z][A-Za-z]*(?: [\d-]+)?)(?:, [^\]]+)?\](?!\()", text):
            assert key in keys, f"{name} cites [{key}], which is not in references.md"
        # `notes` (a field of mechanism files) and mech.notes are no citation
        assert not re.search(r"\bseed \d|(?<![`.])\bnotes\b|\bline \d", text), \
            f"{name} cites material the user does not have"


def test_units_page_lists_the_unit_table():
    from mechatron.units import UNITS

    text = pages()["units.md"]
    table = text.split("<!-- units-table -->", 1)[1].strip().split("\n\n", 1)[0]
    rows = {cells[0]: cells[2] for cells in (
        [c.strip() for c in line.strip("|").split("|")] for line in table.splitlines()[2:])}
    assert set(rows) == set(UNITS)
    for kind, units in UNITS.items():
        assert set(re.findall(r"`([^`]+)`", rows[kind])) == {s for s in units if s}, kind


@pytest.mark.parametrize("kind, heading", [("motors", "## Servo motors"), ("gearboxes", "## Gearboxes"),
                                           ("linear", "## Linear drives"), ("cylinders", "## Hydraulic cylinders"),
                                           ("resistors", "## Braking resistors"), ("drives", "## Servo drives")])
def test_catalog_page_lists_every_field_and_unit(kind, heading):
    from mechatron.drives.catalogs import SCHEMAS
    from mechatron.units import UNITS

    section = pages()["catalogs.md"].split(heading, 1)[1].split("\n## ", 1)[0]
    rows = {line.split("|")[1].strip(): line for line in section.splitlines() if line.startswith("| `")}
    assert set(rows) == {f"`{f.name}`" for f in SCHEMAS[kind]}
    for field in SCHEMAS[kind]:
        row = rows[f"`{field.name}`"]
        assert ("| yes |" in row) == field.required, field.name
        for suffix in UNITS[field.kind]:
            column = f"{field.name}_{suffix}" if suffix else field.name
            assert f"`{column}`" in row, f"{kind}: column {column} is not documented"


def test_cli_page_lists_every_command_and_option():
    from mechatron.cli import build_parser

    text = pages()["cli.md"]
    common = text.split("## Common options", 1)[1].split("\n## ", 1)[0]
    subparsers = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    for name, parser in subparsers.choices.items():
        assert f"## `mechatron {name}`" in text, f"cli.md has no section for {name}"
        section = text.split(f"## `mechatron {name}`", 1)[1].split("\n## ", 1)[0]
        for action in parser._actions:
            if isinstance(action, argparse._HelpAction):
                continue
            names = action.option_strings or [action.metavar or action.dest]
            assert any(re.search(rf"`{re.escape(n)}[` ,]", section + common) for n in names), \
                f"{name}: {names} not in cli.md"


# ------------------------------------------------------------------------------------ numeric checks per sample
def test_four_bar_mobility_by_chebyshev():
    """W = 3n − 2p₅ − p₄ [Egorov, 3.3] from the parsed description: 3·3 − 2·4 = 1; one loop, K = Σp − n (3.10)."""
    desc = read("examples/data/four_bar_structure.toml")
    lower = sum(1 for p in desc.pairs if p.cls >= 3)
    higher = sum(1 for p in desc.pairs if p.cls <= 2)
    assert desc.planar and (len(desc.links), lower, higher) == (3, 4, 0)
    assert 3 * len(desc.links) - 2 * lower - higher == 1
    assert len(desc.pairs) - len(desc.links) == len(desc.loops) == 1
    assert [p.name for p in desc.pairs if p.actuated] == ["A"]
    assert mechatron.analyse_structure(DATA / "four_bar_structure.toml").formulas["chebyshev_3_3"] == 1


def test_planar_2r_move_is_the_quintic_in_closed_form():
    t = read("examples/data/planar_2r_move.csv")
    tau = t.t / 1.0
    s = 10 * tau**3 - 15 * tau**4 + 6 * tau**5
    ds = 30 * tau**2 - 60 * tau**3 + 30 * tau**4
    dds = 60 * tau - 180 * tau**2 + 120 * tau**3
    delta = np.array([0.5, -1.0])
    assert np.allclose(t.t, np.arange(11) * 0.1, atol=1e-12)
    assert np.allclose(t.q, np.outer(s, delta), rtol=1e-5, atol=1e-9)  # 6 significant digits in the file
    assert np.allclose(t.v, np.outer(ds, delta), rtol=1e-5, atol=1e-9)
    assert np.allclose(t.a, np.outer(dds, delta), rtol=1e-5, atol=1e-9)


def test_scara_move_velocities_are_the_derivatives_of_its_positions():
    """Central differences of the positions (and of the velocities) within h² j_max/3 of the given columns."""
    t = read("examples/data/scara_move.csv")
    assert t.q.shape == (181, 4) and t.names == ["q1", "q2", "q3", "q4"]
    v = np.gradient(t.q, t.t, axis=0, edge_order=2)
    a = np.gradient(t.v, t.t, axis=0, edge_order=2)
    h = float(np.max(np.diff(t.t)))
    jerk = np.array([150.0, 200.0, 50.0, 400.0])  # the move's jerk limits (make_samples.py)
    assert np.all(np.abs(v - t.v) <= h**2 * jerk / 3 + 1e-9)
    inner = slice(1, -1)  # the acceleration has kinks: a one-step error h·j at most
    assert np.all(np.abs(a[inner] - t.a[inner]) <= h * jerk + 1e-9)
    assert np.allclose(t.q[0], 0) and np.allclose(t.q[-1], 0) and np.allclose(t.v[[0, -1]], 0)
    assert t.q[:, 2].min() >= 0 and t.q[:, 2].max() == pytest.approx(0.15)  # the quill goes 0.15 m down and back


def test_puma560_move_rests_at_both_ends_inside_the_limits():
    t = read("examples/data/puma560_move.csv")
    puma = robot("puma560")
    assert len(t) == 339 and np.all(np.diff(t.t) > 0)
    assert np.allclose(t.q[0], np.radians([0, 45, -180, 0, 45, 0])) and np.allclose(t.q[-1], t.q[0])
    assert np.all(t.q >= puma.model.lowerPositionLimit) and np.all(t.q <= puma.model.upperPositionLimit)
    assert np.allclose(t.v[[0, -1]], 0, atol=2e-3)  # one-sided differences at the ends
    assert np.all(np.abs(t.v) <= np.radians([90, 90, 90, 180, 180, 180]) * 1.01)


def test_pick_and_place_task_moves_through_its_waypoints_within_its_limits():
    task = read("examples/data/pick_and_place.toml")
    assert task.name == "pick and place, 2 kg" and task.payload == 2.0
    assert [(load.frame, list(load.force)) for load in task.loads] == [("tool", [0.0, 5.0, -15.0])]
    waypoints = np.radians([[-45, 35, -165, 0, 40, -45], [-45, 47, -158, 0, 21, -45], [45, 35, -165, 0, 40, 45],
                            [45, 47, -158, 0, 21, 45]])
    q = task.trajectory.q
    for point in waypoints:
        assert np.min(np.abs(q - point).max(axis=1)) < 1e-12
    assert np.all(np.abs(task.trajectory.v) <= np.radians([100, 100, 100, 200, 200, 200]) * (1 + 1e-9))
    assert np.all(np.abs(task.trajectory.a) <= np.radians([300, 300, 300, 600, 600, 600]) * (1 + 1e-9))
    # as docs/task_file.md says
    assert task.duration == pytest.approx(6.816, abs=5e-4) and len(task.trajectory) == 1367
    # the payload's centre, 60 mm along the tool z axis, moves the mass at the tool: 2 kg more than the bare arm
    assert task.mechanism.total_mass == pytest.approx(robot("puma560").total_mass + 2.0)


def test_motor_catalog_is_physically_consistent():
    """Rated power = T_r · n_r, torque constant · rated current = T_r (to 1 %); peak about 3 × rated."""
    motors = read("examples/data/motors.csv")
    assert 5 <= len(motors) <= 10 and motors["rated_torque"].between(0.1, 10).all()
    assert np.allclose(motors["rated_power"], motors["rated_torque"] * motors["rated_speed"], rtol=0.01)
    assert np.allclose(motors["torque_constant"] * motors["rated_current"], motors["rated_torque"], rtol=0.01)
    assert (motors["peak_torque"] / motors["rated_torque"]).between(2.9, 3.1).all()
    assert motors["rated_speed"].eq(3000 * 2 * math.pi / 60).all()


def test_gearbox_catalog_holds_harmonic_and_planetary_units():
    gearboxes = read("examples/data/gearboxes.csv")
    assert 5 <= len(gearboxes) <= 10
    assert set(gearboxes["type"]) == {"harmonic", "planetary"}
    harmonic = gearboxes[gearboxes["type"] == "harmonic"]
    assert harmonic["ratio"].ge(50).all() and harmonic["backlash"].le(1.01 * math.pi / 10800).all()
    assert gearboxes["efficiency"].between(0.7, 0.97).all()


def test_linear_drives_follow_steel_shafts():
    """Screw inertia per metre πρd⁴/32 and mass per metre πρd²/4 (ρ = 7850 kg/m³, to 1 %); a pinion's lead is π d."""
    drives = read("examples/data/linear_drives.csv")
    screws = drives[drives["type"] == "ball screw"]
    d = screws["diameter"].to_numpy()
    assert np.allclose(screws["inertia_per_length"], math.pi * 7850 * d**4 / 32, rtol=0.01)
    assert np.allclose(screws["mass_per_length"], math.pi * 7850 * d**2 / 4, rtol=0.01)
    rack = drives[drives["type"] == "rack and pinion"].iloc[0]
    assert rack["lead"] == pytest.approx(math.pi * rack["diameter"], rel=1e-5)


def test_hydraulic_cylinders_follow_steel_tube_and_rod():
    """Mass per metre of stroke ρπ/4 (0.44 D² + d²): a tube of wall 0.1 D and a solid rod (to 1 %)."""
    cylinders = read("examples/data/hydraulic_cylinders.csv")
    D, d = cylinders["bore"].to_numpy(), cylinders["rod"].to_numpy()
    assert np.all(d < D)
    assert np.allclose(cylinders["mass_per_stroke"], 7850 * math.pi / 4 * (0.44 * D**2 + d**2), rtol=0.01)


def test_crank_slider_given_errors_give_the_books_displacement():
    """[Egorov, fig. 8.3]: x_C = l1 cos q1 + √(l2² − l1² sin² q1) at l1 = 0.2 m, l2 = 0.346 m, q1 = 60°; the file's
    errors Δl1 = 1 mm, Δl2 = 1.5 mm, Δq1 = 1e-3 rad move C by +1.500914 mm (first order)."""
    sources = {s.name: s for s in read("examples/data/tolerances_crank_slider.csv")}
    errors = np.array([sources[n].error for n in ("l1", "l2", "q1")])
    assert errors == pytest.approx([1e-3, 1.5e-3, 1e-3])
    assert [sources[n].tolerance for n in ("l1", "l2", "q1")] == pytest.approx(errors)
    l1, l2, q1 = 0.2, 0.346, math.pi / 3
    D = math.sqrt(l2**2 - l1**2 * math.sin(q1) ** 2)
    gradient = np.array([math.cos(q1) - l1 * math.sin(q1) ** 2 / D, l2 / D,
                         -l1 * math.sin(q1) - l1**2 * math.sin(q1) * math.cos(q1) / D])
    assert gradient @ errors == pytest.approx(1.500914e-3, rel=1e-6)
    mech = robot("crank_slider", l1=l1, l2=l2)
    result = mechatron.tolerance_study(mech, DATA / "tolerances_crank_slider.csv", methods=["given"], frame="C")
    assert result.poses.iloc[0]["dx_given"] == pytest.approx(gradient @ errors, rel=1e-6)


def test_puma560_tolerances_grades_and_units():
    """IT7 of 431.8 mm and IT8 of 150.05 mm are 63 µm [ISO 286-1], AT8 of 300 mm is 40″: t = half the zone."""
    sources = {s.name: s for s in read("examples/data/tolerances_puma560.csv")}
    assert sources["a2"].tolerance == pytest.approx(31.5e-6) and sources["d4"].tolerance == pytest.approx(31.5e-6)
    assert sources["d3"].tolerance == pytest.approx(31.5e-6) and sources["d3"].bias == pytest.approx(10e-6)
    assert sources["alpha3"].tolerance == pytest.approx(20 * math.pi / 648000)
    assert sources["alpha2"].tolerance == pytest.approx(math.pi / 10800)
    assert sources["d1"].tolerance == pytest.approx(50e-6) and sources["a3"].distribution == "uniform"
    assert sources["q1"].kind == "coordinate" and sources["q1"].tolerance == pytest.approx(30 * math.pi / 648000)
    scara = {s.name: s for s in read("examples/data/tolerances_scara.csv")}
    assert scara["q3"].unit == "m" and scara["q3"].tolerance == pytest.approx(10e-6)
    assert scara["a1"].tolerance == pytest.approx(36e-6 / 2)  # IT6, 315–400 mm: 36 µm


def test_puma560_poses_and_the_tool_positions_the_pages_quote():
    values, labels = read("examples/data/poses_puma560.csv")
    puma = robot("puma560")
    assert labels[0] == "nominal" and len(labels) == 6
    assert np.allclose(values[0], np.radians([0, 45, -180, 0, 45, 0]))
    assert np.all(values >= puma.model.lowerPositionLimit) and np.all(values <= puma.model.upperPositionLimit)
    tool = mechatron.frame_placement(puma, values[0], "tool").translation
    assert tool == pytest.approx([0.596303, -0.15005, 0.657476], abs=1e-6)  # docs/poses_csv.md
    scara = robot("scara")
    assert mechatron.frame_placement(scara, np.zeros(4)).translation == pytest.approx([0.6, 0, 0.35])
    q = np.array([math.pi / 2, -math.pi / 2, 0.1, 0.0])
    assert mechatron.frame_placement(scara, q).translation == pytest.approx([0.275, 0.325, 0.25])


def test_turret_arm_urdf_tool_in_closed_form_and_rotor_data():
    """Tool at L = 0.6 + extend from the shoulder, 0.5 m above the base: (L cos s cos t, L cos s sin t,
    0.5 + L sin s) for turn t (continuous), shoulder s (axis −y) and extend; armature J·u² from the SRDF."""
    arm = read("examples/data/turret_arm.urdf")
    assert (arm.nq, arm.nv) == (4, 3) and arm.joint_names == ["turn", "shoulder", "extend"]
    for turn, shoulder, extend in ((math.pi / 2, math.pi / 6, 0.1), (2.8, -0.4, 0.0), (-3.0, 1.2, 0.3)):
        q = arm.configuration([turn, shoulder, extend])
        L = 0.6 + extend
        expected = [L * math.cos(shoulder) * math.cos(turn), L * math.cos(shoulder) * math.sin(turn),
                    0.5 + L * math.sin(shoulder)]
        assert mechatron.frame_placement(arm, q, "tool").translation == pytest.approx(expected, abs=1e-12)
        assert arm.coordinates(q) == pytest.approx([turn, shoulder, extend])
    assert arm.model.armature == pytest.approx([3e-5 * 100**2, 3e-5 * 120**2, 1e-5 * 628.3**2])
    assert sorted(arm.parameters) == ["extend_x", "shoulder_z", "turn_z"]


def test_front_shovel_design_reaches_what_it_asks_for():
    """The overridden fields are the file's, the others the assignment's; the special positions, written out from
    the assignment's angles (θ1 boom from the horizontal, θ2 at F, θ3 at Q), put the tip at the asked reach,
    height and depth."""
    from mechatron.machines import excavator as ex

    design = read("examples/data/front_shovel_design.toml")
    default = ex.FrontShovelDesign()
    changed = {"max_digging_radius": 9.2, "max_digging_height": 9.6, "boom": 4.5, "stick": 3.1,
               "boom_foot": (0.5, 2.75), "stick_ratio": 1.75, "boom_cylinders": 2, "boom_mass": 4800.0,
               "stick_mass": 2100.0}
    for name, value in vars(design).items():
        assert value == changed.get(name, getattr(default, name)), name
    shovel = ex.synthesize(design)
    positions = ex.special_positions(shovel)

    def tip(t1: float, t2: float, t3: float) -> np.ndarray:
        e = lambda a: np.array([math.cos(a), math.sin(a)])  # noqa: E731
        return np.array(design.boom_foot) + design.boom * e(t1) + design.stick * e(t1 + t2 - math.pi) \
            + design.bucket * e(t1 + t2 + t3)

    assert tip(*positions["max_digging_radius"])[0] == pytest.approx(9.2, abs=1e-9)
    assert tip(*positions["max_digging_height"])[1] == pytest.approx(9.6, abs=1e-9)
    assert tip(*positions["max_digging_depth"])[1] == pytest.approx(-3.2, abs=1e-9)
    assert tip(*positions["max_ground_radius"])[1] == pytest.approx(0.0, abs=1e-9)


def test_make_samples_writes_the_shipped_trajectories():
    import importlib.util

    spec = importlib.util.spec_from_file_location("make_samples", DATA / "make_samples.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    for make, name in ((module.puma560_move, "puma560_move.csv"), (module.scara_move, "scara_move.csv"),
                       (module.planar_2r_move, "planar_2r_move.csv")):
        shipped = read(f"examples/data/{name}")
        made = make()
        assert np.allclose(made.t, shipped.t, rtol=1e-6, atol=1e-9)
        assert np.allclose(made.q, shipped.q, rtol=1e-5, atol=1e-8)


def test_the_catalog_pages_example_result_is_what_size_chooses():
    """The PUMA 560's drives for the pick-and-place task from the example catalogs, as docs/catalogs.md tables them."""
    from mechatron.drives.catalogs import read_catalog
    from mechatron.dynamics.task import read_task

    page = pages()["catalogs.md"].split("<!-- result: puma560 pick_and_place -->", 1)[1].strip().split("\n\n")[0]
    rows = [[c.strip() for c in line.strip("|").split("|")] for line in page.splitlines()[2:]]
    mech = robot("puma560")
    result = mechatron.size(mech, read_task(DATA / "pick_and_place.toml", mech),
                            motors=read_catalog(DATA / "motors.csv", "motors"),
                            gearboxes=read_catalog(DATA / "gearboxes.csv", "gearboxes"))
    chosen = [[j.joint, j.motor, j.converter if j.converter_kind != "direct" else "direct drive"]
              for j in result.joints]
    assert rows == chosen
