"""Bad cells in the drive catalogs' thermal and gearbox-duty columns (issue 33): through ``mechatron size --motors /
--gearboxes``, each is refused with exit status 2 and one line on stderr naming the file, the row and the column,
every input left byte-identical and no output written; and the legal extremes of mechatron's plausible ranges
(docs/catalogs.md, "Plausible ranges") give finite numbers, those of a closed form.

The mechanism: one link of 2 kg, its centre 0.15 m from a vertical-plane joint (gravity along −y), held still at
q = 0 for 2 s (a trajectory of three samples). The joint holds τ = m g r = 2 · 9.81 · 0.15 = 2.943 N·m the whole
cycle; through a gearbox of ratio u and efficiency η the motor gives T_m = τ/(u η) (holding a load counts as the
load taking power, docs/catalogs.md), a current I = T_m/k_t, and the two-node network's steady state is exact:

    θ_w = R I² R₂₅ (1 + α (T_a − 25 °C + θ_w)),  R = R_wh + R_ha   ⇒   θ_w = R I² R_a / (1 − R I² R₂₅ α),

R_a = R₂₅ (1 + α (T_a − 25 °C)), with k_t constant (β = 0: ``torque_constant_coefficient`` 0) and no speed losses
at rest; where 1 − R I² R₂₅ α ≤ 0 the winding runs away and the check takes R I² R(T_max) (the resistance held at the
limit temperature).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from mechatron.cli import main
from tests.corpus import cli_error

ROBOT = """name = "holder"
gravity = [0.0, -9.81, 0.0]
[[links]]
joint = "revolute"
a = 0.3
mass = {mass}
com = [-0.15, 0.0, 0.0]
"""
HOLD = "t,q1\n0,0\n1,0\n2,0\n"
MOTOR_COLUMNS = {"key": ("M1", "M2"), "rated_torque_Nm": "1.0", "peak_torque_Nm": "3.0", "rated_speed_rpm": "3000",
                 "max_speed_rpm": "5000", "rotor_inertia_kgcm2": "0.5", "torque_constant_Nm_A": "0.5",
                 "resistance_ohm": "1.0", "rth_winding_housing_K_W": "1.0", "rth_housing_ambient_K_W": "2.0",
                 "tau_winding_s": "10", "tau_housing_s": "600", "max_winding_temperature_degC": "155",
                 "temperature_coefficient_per_K": "0.0039", "torque_constant_coefficient_percent_K": "0",
                 "loss_torque_Nm": "0.01", "mass_kg": ("1.0", "1.5"), "price_eur": "100"}
GEARBOX_COLUMNS = {"key": ("G1", "G2"), "type": "planetary", "stages": "1", "ratio": "10", "rated_torque_Nm": "40",
                   "peak_torque_Nm": "60", "emergency_torque_Nm": "100", "max_input_speed_rpm": "6000",
                   "rated_input_speed_rpm": "4000", "efficiency": "0.9", "input_inertia_kgcm2": "0.1",
                   "emergency_stops": "1000", "cycle_rating_per_h": "1000", "shock_factors_per_h": "1000:1;3000:1.2",
                   "mass_kg": ("1.0", "1.2"), "price_eur": "300"}
TAU = 2.0 * 9.81 * 0.15  # N·m, the torque the joint holds


def catalog(columns: dict, changes: dict | None = None) -> str:
    """Two rows (rows 2 and 3 of the file); ``changes``: {column: value of row 3} (a new column: empty in row 2),
    or {column: (its name in another unit, the value of row 2, that of row 3)}."""
    columns = dict(columns)
    rows = [{k: v[i] if isinstance(v, tuple) else v for k, v in columns.items()} for i in range(2)]
    header = list(columns)
    for column, value in (changes or {}).items():
        if isinstance(value, tuple):  # a column in another unit
            new, rows[0][new], value = value
            header[header.index(column)] = new
            del rows[0][column], rows[1][column]
            column = new
        elif column not in header:
            header.append(column)
            rows[0][column] = ""
        rows[1][column] = value
    return "\n".join([",".join(header), *(",".join(row[c] for c in header) for row in rows)]) + "\n"


def files(tmp_path: Path, motors: dict | None = None, gearboxes: dict | None = None, mass: float = 2.0,
          every_motor: dict | None = None, every_gearbox: dict | None = None) -> dict:
    """The robot, the task and the two catalogs: ``motors``/``gearboxes`` change row 3 (:func:`catalog`),
    ``every_motor``/``every_gearbox`` every row."""
    paths = {"robot": tmp_path / "holder.toml", "task": tmp_path / "hold.csv", "motors": tmp_path / "motors.csv",
             "gearboxes": tmp_path / "gearboxes.csv"}
    paths["robot"].write_text(ROBOT.format(mass=mass), encoding="utf-8")
    paths["task"].write_text(HOLD, encoding="utf-8")
    paths["motors"].write_text(catalog(dict(MOTOR_COLUMNS, **(every_motor or {})), motors), encoding="utf-8")
    paths["gearboxes"].write_text(catalog(dict(GEARBOX_COLUMNS, **(every_gearbox or {})), gearboxes),
                                  encoding="utf-8")
    return paths


def argv(paths: dict, *extra: str) -> list[str]:
    return ["size", str(paths["robot"]), "--task", str(paths["task"]), "--motors", str(paths["motors"]),
            "--gearboxes", str(paths["gearboxes"]), *extra]


# (catalog, column, the value in row 3 — or (the column in another unit, row 2's value, row 3's) —, words)
NOT_FINITE, HUGE, POSITIVE, PLAUSIBLE = "not a finite number", "magnitude <= 1e+12", "must be > 0", \
    "(mechatron's plausible range)"
WHOLE, MISSING, THERMAL = "must be a whole number (a count)", "missing value", "the thermal columns are given for some"
CASES = [
    # the two-node network's thermal resistances (K/W)
    ("motors", "rth_housing_ambient_K_W", "1e12", "must be between 0.001 K/W and 1000 K/W " + PLAUSIBLE),
    ("motors", "rth_housing_ambient_K_W", "2000", PLAUSIBLE),
    ("motors", "rth_housing_ambient_K_W", "1e-4", PLAUSIBLE),
    ("motors", "rth_housing_ambient_K_W", "0", POSITIVE),
    ("motors", "rth_housing_ambient_K_W", "-1", POSITIVE),
    ("motors", "rth_housing_ambient_K_W", "nan", NOT_FINITE),
    ("motors", "rth_housing_ambient_K_W", "inf", NOT_FINITE),
    ("motors", "rth_housing_ambient_K_W", "1e308", HUGE),
    ("motors", "rth_housing_ambient_K_W", "hot", "not a number: 'hot'"),
    ("motors", "rth_housing_ambient_K_W", "", THERMAL),
    ("motors", "rth_winding_housing_K_W", "1e12", PLAUSIBLE),
    ("motors", "rth_winding_housing_K_W", "0", POSITIVE),
    ("motors", "rth_winding_housing_K_W", "-inf", NOT_FINITE),
    ("motors", "rth_winding_housing_K_W", "", THERMAL),
    # the time constants (s, or in the column's unit)
    ("motors", "tau_housing_s", ("tau_housing_h", "0.2", "1e12"), "must be between 1 s and 100000 s " + PLAUSIBLE +
     ", got 1e12 h"),
    ("motors", "tau_housing_s", "1e6", PLAUSIBLE),
    ("motors", "tau_housing_s", "0.5", PLAUSIBLE),
    ("motors", "tau_housing_s", "0", POSITIVE),
    ("motors", "tau_housing_s", "nan", NOT_FINITE),
    ("motors", "tau_housing_s", "1e308", HUGE),
    ("motors", "tau_housing_s", "", THERMAL),
    ("motors", "tau_winding_s", "1e-3", "must be between 0.01 s and 10000 s " + PLAUSIBLE),
    ("motors", "tau_winding_s", ("tau_winding_min", "0.5", "1000"), PLAUSIBLE + ", got 1000 min"),
    ("motors", "tau_winding_s", "-1", POSITIVE),
    ("motors", "tau_winding_s", "inf", NOT_FINITE),
    ("motors", "tau_winding_s", "x", "not a number: 'x'"),
    # the limit temperature and the coefficients
    ("motors", "max_winding_temperature_degC", "600", "must be between 273.15 K (0 °C) and 773.15 K (500 °C)"),
    ("motors", "max_winding_temperature_degC", "-300", "must be between"),
    ("motors", "max_winding_temperature_degC", "nan", NOT_FINITE),
    ("motors", "max_winding_temperature_degC", "", THERMAL),
    ("motors", "temperature_coefficient_per_K", "0.05", "must be between 0 1/K and 0.01 1/K " + PLAUSIBLE),
    ("motors", "temperature_coefficient_per_K", "-0.1", "must be >= 0"),
    ("motors", "temperature_coefficient_per_K", "0.5", "must be <= 0.1"),
    ("motors", "torque_constant_coefficient_percent_K", "0.05", "must be between"),
    ("motors", "torque_constant_coefficient_percent_K", "-1.5", "must be between"),
    ("motors", "torque_constant_coefficient_percent_K", "-0.8", "must stay > 0"),
    ("motors", "torque_constant_coefficient_percent_K", "1e308", HUGE),
    ("motors", "loss_torque_Nm", "-1", "must be >= 0"),
    ("motors", "loss_torque_Nm", "nan", NOT_FINITE),
    ("motors", "torque_constant_Nm_A", "", THERMAL),
    ("motors", "resistance_ohm", "", THERMAL),
    # gearbox counts: whole numbers
    ("gearboxes", "stages", "2.5", WHOLE + ", got 2.5"),
    ("gearboxes", "stages", "0", POSITIVE),
    ("gearboxes", "stages", "-1", POSITIVE),
    ("gearboxes", "stages", "11", "must be between 1 and 10 " + PLAUSIBLE),
    ("gearboxes", "stages", "nan", NOT_FINITE),
    ("gearboxes", "stages", "1e308", HUGE),
    ("gearboxes", "stages", "two", "not a number: 'two'"),
    ("gearboxes", "emergency_stops", "2.5", WHOLE),
    ("gearboxes", "emergency_stops", "1e-300", WHOLE),
    ("gearboxes", "emergency_stops", "0", POSITIVE),
    ("gearboxes", "emergency_stops", "-1", POSITIVE),
    ("gearboxes", "emergency_stops", "inf", NOT_FINITE),
    ("gearboxes", "emergency_stops", "many", "not a number"),
    # ratio and efficiency
    ("gearboxes", "ratio", "1e-300", "must be between 1 and 10000 " + PLAUSIBLE),
    ("gearboxes", "ratio", "0.5", PLAUSIBLE),
    ("gearboxes", "ratio", "1e5", PLAUSIBLE),
    ("gearboxes", "ratio", "0", POSITIVE),
    ("gearboxes", "ratio", "", MISSING),
    ("gearboxes", "efficiency", "1e-300", "must be between 0.01 and 1 " + PLAUSIBLE + ", got 1e-300"),
    ("gearboxes", "efficiency", "0.005", PLAUSIBLE),
    ("gearboxes", "efficiency", ("efficiency_percent", "90", "0.5"), PLAUSIBLE + ", got 0.5 percent"),
    ("gearboxes", "efficiency", "1.2", "must be <= 1"),
    ("gearboxes", "efficiency", "0", POSITIVE),
    ("gearboxes", "efficiency", "-1", POSITIVE),
    ("gearboxes", "efficiency", "nan", NOT_FINITE),
    ("gearboxes", "efficiency", "", MISSING),
    # the maker's peak-torque rule
    ("gearboxes", "cycle_rating_per_h", "0", POSITIVE),
    ("gearboxes", "cycle_rating_per_h", "-5", POSITIVE),
    ("gearboxes", "cycle_rating_per_h", "nan", NOT_FINITE),
    ("gearboxes", "shock_factors_per_h", "1000:11", "a shock factor must be <= 10 " + PLAUSIBLE),
    ("gearboxes", "shock_factors_per_h", "1000:0.5", "a shock factor must be >= 1"),
    ("gearboxes", "shock_factors_per_h", "1000:inf", NOT_FINITE),
    ("gearboxes", "shock_factors_per_h", "nan:1", NOT_FINITE),
    ("gearboxes", "shock_factors_per_h", "0:1", "a rate must be > 0"),
    ("gearboxes", "shock_factors_per_h", "2000:1;1000:1.2", "the rates must rise"),
    ("gearboxes", "shock_factors_per_h", "1000-1", "expected rate:factor pairs"),
    ("gearboxes", "peak_rule", "shock", "unknown peak rule 'shock'"),
    ("gearboxes", "peak_rule", "repeated_peak", "a shock_factors table with peak_rule repeated_peak"),
]


@pytest.mark.parametrize("kind, column, value, words", CASES, ids=[f"{c[1]}={c[2]}" for c in CASES])
def test_a_bad_cell_is_one_line_naming_file_row_and_column(tmp_path, capsys, kind, column, value, words):
    """Exit 2, one line ``<file>: row 3: field '<column>': …`` (the column as the file names it), the inputs
    byte-identical, no --csv written."""
    paths = files(tmp_path, **{kind: {column: value}})
    before = {name: path.read_bytes() for name, path in paths.items()}
    out = tmp_path / "sizing.csv"
    code, line = cli_error(capsys, *argv(paths, "--csv", str(out)))
    named = value[0] if isinstance(value, tuple) else column
    assert code == 2
    assert line.startswith(f"mechatron: error: {paths[kind]}: row 3: field '{named}': "), line
    assert words in line, line
    assert {name: path.read_bytes() for name, path in paths.items()} == before
    assert not out.exists() and sorted(p.name for p in tmp_path.iterdir()) == sorted(p.name for p in paths.values())


def test_the_base_catalogs_size_the_holding_arm(tmp_path, capsys):
    """The catalogs the cases edit are good: M1 + G1 holds τ = 2.943 N·m, T_m = τ/(u η) = 2.943/(10 · 0.9) =
    0.327 N·m, and its winding rises by the closed form of the module docstring, 1.3650 K."""
    sized = run_json(capsys, files(tmp_path))
    (joint,) = sized["joints"]
    assert (joint["motor"], joint["gearbox"]) == ("M1", "G1")
    assert check(joint, "peak torque") == pytest.approx(TAU / 9.0, rel=1e-9)
    assert check(joint, "winding temperature rise") == pytest.approx(rise(TAU / 9.0, 3.0, 0.0039, 40.0), rel=1e-6)
    assert rise(TAU / 9.0, 3.0, 0.0039, 40.0) == pytest.approx(1.3650, abs=1e-4)


def run_json(capsys, paths: dict, *extra: str) -> dict:
    code = main(argv(paths, "--json", *extra))
    out, err = capsys.readouterr()
    assert code in (0, 1) and err == "", err
    assert "NaN" not in out and "Infinity" not in out
    return json.loads(out)


def check(joint: dict, name: str) -> float:
    value = next(c["value"] for c in joint["checks"] if c["name"] == name)
    assert value is not None and math.isfinite(value), (name, value)
    return value


def rise(motor_torque: float, total: float, alpha: float, ambient_c: float, limit_c: float = 155.0,
         k_t: float = 0.5, r25: float = 1.0) -> float:
    """The winding's steady rise (K) under a constant motor torque (the module docstring); a runaway: the rise with
    the resistance held at the limit temperature."""
    current2 = (motor_torque / k_t) ** 2
    room = 1 - total * current2 * r25 * alpha
    if room <= 0:
        return total * current2 * r25 * (1 + alpha * (limit_c - 25))
    return total * current2 * r25 * (1 + alpha * (ambient_c - 25)) / room


@pytest.mark.parametrize("mass, runaway", [(0.5, False), (1.0, True)])
def test_the_thermal_extremes_give_the_closed_form(tmp_path, capsys, mass, runaway):
    """Every thermal column at the edge of its plausible range — R_wh = R_ha = 1000 K/W, τ_w = 0.01 s, τ_h = 1e5 s,
    α = 0.01 1/K, T_max = 500 °C — in a 100 °C ambient (--ambient's largest), through a gearbox of u = 10, η = 1:
    the winding's rise is the closed form. 0.5 kg: T_m = 0.0736 N·m, R I² R₂₅ α = 0.433, θ_w = 133.7 K below the
    allowed 400 K; 1 kg: the copper loss outgrows the cooling (R I² R₂₅ α = 1.73), the rise held at R(500 °C) is
    996.0 K, finite, a fail."""
    extremes = {"rth_winding_housing_K_W": "1000", "rth_housing_ambient_K_W": "1000", "tau_winding_s": "0.01",
                "tau_housing_s": "1e5", "temperature_coefficient_per_K": "0.01", "max_winding_temperature_degC": "500"}
    paths = files(tmp_path, mass=mass, every_motor=extremes, every_gearbox={"efficiency": "1.0"})
    sized = run_json(capsys, paths, "--ambient", "100", "--no-direct")
    torque = mass * 9.81 * 0.15 / 10
    expected = rise(torque, 2000.0, 0.01, 100.0, 500.0)
    assert expected == pytest.approx(996.0 if runaway else 133.7, abs=0.05)
    (joint,) = sized["joints"]
    assert joint["thermal"]["runaway"] is runaway and joint["feasible"] is not runaway
    assert check(joint, "peak torque") == pytest.approx(torque, rel=1e-9)
    assert check(joint, "winding temperature rise") == pytest.approx(expected, rel=1e-6)


def test_the_least_plausible_efficiency_gives_finite_torques(tmp_path, capsys):
    """A gearbox efficiency of 0.01, the plausible range's floor (1e-300 used to end in an internal error): the
    arm of 0.2 kg (τ = 0.2943 N·m) takes T_m = τ/(u η) = 0.2943/(10 · 0.01) = 2.943 N·m of the motor, finite, and
    its winding rises by the closed form, R I² R₂₅ α = 3 · 34.65 · 0.0039 = 0.405, θ_w = 3 · 34.65 · 1.0585/(1 −
    0.405) = 185.0 K, above the allowed 115 K: no feasible drive, the closest one shown with finite numbers."""
    paths = files(tmp_path, mass=0.2, every_gearbox={"efficiency": "0.01"})
    sized = run_json(capsys, paths, "--no-direct")
    (joint,) = sized["joints"]
    torque = 0.2 * 9.81 * 0.15 / (10 * 0.01)
    expected = rise(torque, 3.0, 0.0039, 40.0)
    assert expected == pytest.approx(185.0, abs=0.05) and not joint["feasible"]
    assert check(joint, "peak torque") == pytest.approx(torque, rel=1e-9)
    assert check(joint, "winding temperature rise") == pytest.approx(expected, rel=1e-6)


@pytest.mark.parametrize("ambient", ["nan", "inf", "-inf", "1e308", "100.5", "-50.5", "warm", ""])
def test_a_bad_ambient_is_one_line_naming_the_option(tmp_path, capsys, ambient):
    """--ambient outside −50 … 100 °C, or not a finite number: exit 2, one line naming the option, inputs unchanged,
    no --csv written."""
    paths = files(tmp_path)
    before = {name: path.read_bytes() for name, path in paths.items()}
    out = tmp_path / "sizing.csv"
    with pytest.raises(SystemExit) as exit_:
        main(argv(paths, "--ambient", ambient, "--csv", str(out)))
    stdout, err = capsys.readouterr()
    assert exit_.value.code == 2 and stdout == "" and len(err.strip().splitlines()) == 1
    assert err.startswith("mechatron size: error: argument --ambient: must be a finite number >= -50 and <= 100 °C")
    assert {name: path.read_bytes() for name, path in paths.items()} == before and not out.exists()
