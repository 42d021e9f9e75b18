"""Catalog files: the shipped ones load, units convert to SI, and every kind of bad input names the file, the row
and the column."""

import math

import pytest

from mechatron.drives.catalogs import DEFAULT_FILES, SCHEMAS, default_catalog, read_catalog
from mechatron.errors import InputError

MOTOR_HEADER = "key,rated_torque,peak_torque,rated_speed_rpm,max_speed_rpm,rotor_inertia_kgcm2,mass"


def write(tmp_path, text, name="motors.csv"):
    path = tmp_path / name
    path.write_text(text)
    return path


@pytest.mark.parametrize("kind", list(DEFAULT_FILES))
def test_shipped_catalogs_load(kind):
    table = default_catalog(kind)
    assert len(table) >= 5
    required = [f.name for f in SCHEMAS[kind] if f.required]
    assert all(name in table for name in required)


def test_example_catalog_sizes_cover_the_benchmark():
    assert len(default_catalog("motors")) >= 100
    assert len(default_catalog("gearboxes")) >= 30


def test_units_convert_to_si(tmp_path):
    path = write(tmp_path, MOTOR_HEADER + "\nM1,1.2,3.6,3000,6000,1.5,2.1\n")
    row = read_catalog(path, "motors").iloc[0]
    assert row["rated_speed"] == pytest.approx(3000 * 2 * math.pi / 60)
    assert row["max_speed"] == pytest.approx(6000 * 2 * math.pi / 60)
    assert row["rotor_inertia"] == pytest.approx(1.5e-4)
    cylinders = write(tmp_path, "key,bore_mm,rod_mm,max_stroke_mm,max_pressure_bar\nC1,100,56,2000,250\n", "c.csv")
    c = read_catalog(cylinders, "cylinders").iloc[0]
    assert (c["bore"], c["rod"], c["max_stroke"], c["max_pressure"]) == pytest.approx((0.1, 0.056, 2.0, 25e6))
    backlash = read_catalog(default_catalog_path("gearboxes"), "gearboxes")["backlash"].iloc[0]
    assert backlash == pytest.approx(5 * math.pi / 10800)  # 5 arcmin


def default_catalog_path(kind):
    from mechatron.io.data import data_dir

    return data_dir("catalogs") / DEFAULT_FILES[kind]


@pytest.mark.parametrize("row, field, message", [
    ("M2,,3.6,3000,6000,1.5,2", "rated_torque", "missing value"),
    ("M2,-0.5,3.6,3000,6000,1.5,2", "rated_torque", "must be > 0"),
    ("M2,1.2,3.6,3000,6000,abc,2", "rotor_inertia_kgcm2", "not a number"),
    ("M2,1.2,3.6,3000,6000,inf,2", "rotor_inertia_kgcm2", "not a finite number"),
    ("M2,1.2,0.6,3000,6000,1.5,2", "peak_torque", "peak_torque is below rated_torque"),
    ("M2,1.2,3.6,3000,2000,1.5,2", "max_speed_rpm", "max_speed is below rated_speed"),
    ("M1,1.2,3.6,3000,6000,1.5,2", "key", "repeats an earlier row"),
])
def test_bad_rows_name_file_row_and_field(tmp_path, row, field, message):
    path = write(tmp_path, MOTOR_HEADER + "\nM1,1.2,3.6,3000,6000,1.5,2.1\n" + row + "\n")
    with pytest.raises(InputError, match=message) as info:
        read_catalog(path, "motors")
    error = info.value
    assert error.file == str(path) and error.row == 3
    assert error.field == field
    assert "motors.csv: row 3: field" in str(error)


def test_unknown_unit_and_missing_column(tmp_path):
    path = write(tmp_path, MOTOR_HEADER.replace("rated_speed_rpm", "rated_speed_rmp") + "\nM1,1,3,3000,6000,1,2\n")
    with pytest.raises(InputError, match="unknown unit 'rmp' for rated_speed") as info:
        read_catalog(path, "motors")
    assert info.value.file == str(path) and info.value.field == "rated_speed_rmp"
    path = write(tmp_path, MOTOR_HEADER.replace(",peak_torque", "") + "\nM1,1,3000,6000,1,2\n")
    with pytest.raises(InputError, match="missing column 'peak_torque'"):
        read_catalog(path, "motors")
    price = write(tmp_path, "key,bore,rod,max_stroke,max_pressure,price\nC,0.1,0.05,1,2e7,10\n", "c.csv")
    with pytest.raises(InputError, match="give the unit in the column name"):
        read_catalog(price, "cylinders")


def test_fraction_bounds_and_relations(tmp_path):
    gear = default_catalog_path("gearboxes").read_text().splitlines()
    header, first = gear[1], gear[2].split(",")
    columns = header.split(",")
    first[columns.index("efficiency")] = "1.2"
    path = write(tmp_path, header + "\n" + ",".join(first) + "\n", "g.csv")
    with pytest.raises(InputError, match="must be <= 1") as info:
        read_catalog(path, "gearboxes")
    assert info.value.row == 2 and info.value.field == "efficiency"
    for rod_mm in (60, 50):  # a rod as wide as the bore leaves no annulus: not a cylinder either
        rod = write(tmp_path, f"key,bore_mm,rod_mm,max_stroke_mm,max_pressure_MPa\nC,50,{rod_mm},500,25\n", "c.csv")
        with pytest.raises(InputError, match="bore is not above rod"):
            read_catalog(rod, "cylinders")


def test_extra_columns_are_kept_as_text(tmp_path):
    path = write(tmp_path, "key,bore_mm,rod_mm,max_stroke_mm,max_pressure_MPa,order_code,note\n"
                           "C,50,28,500,25,HC-50/28,spare\n", "c.csv")
    table = read_catalog(path, "cylinders")
    assert table.loc[0, "order_code"] == "HC-50/28" and table.loc[0, "note"] == "spare"
    assert table.loc[0, "bore"] == pytest.approx(0.05) and table.loc[0, "rod"] == pytest.approx(0.028)


def test_unreadable_files(tmp_path):
    with pytest.raises(InputError, match="no such file"):
        read_catalog(tmp_path / "none.csv", "motors")
    with pytest.raises(InputError, match="no rows"):
        read_catalog(write(tmp_path, MOTOR_HEADER + "\n"), "motors")
    with pytest.raises(InputError, match="unknown catalog kind"):
        read_catalog(write(tmp_path, MOTOR_HEADER + "\n"), "brakes")


# ------------------------------------------------------------------------------ the optional columns of issue 12
ELECTRICAL = MOTOR_HEADER + ",torque_constant_Nm_A,resistance_ohm,voltage_V"


@pytest.mark.parametrize("row, field", [
    ("M2,1.2,3.6,3000,6000,1.5,2,0.5,,400", "resistance_ohm"),  # voltage without resistance
    ("M2,1.2,3.6,3000,6000,1.5,2,0.5,2.0,", "voltage_V"),  # resistance without voltage
    ("M2,1.2,3.6,3000,6000,1.5,2,,2.0,400", "torque_constant_Nm_A"),  # no torque constant
])
def test_half_filled_electrical_columns_name_file_row_and_column(tmp_path, row, field):
    path = write(tmp_path, ELECTRICAL + "\nM1,1.2,3.6,3000,6000,1.5,2.1,0.5,2.0,400\n" + row + "\n")
    with pytest.raises(InputError, match="electrical columns are half filled") as info:
        read_catalog(path, "motors")
    assert (info.value.file, info.value.row, info.value.field) == (str(path), 3, field)
    assert str(info.value).count("\n") == 0 and f"motors.csv: row 3: field '{field}'" in str(info.value)


def test_electrical_columns_all_or_none(tmp_path):
    """A row with all three, a row with none and a row with the torque constant alone are all fine; the units
    convert (mΩ)."""
    header = MOTOR_HEADER + ",torque_constant,resistance_mohm,voltage"
    path = write(tmp_path, header + "\nM1,1.2,3.6,3000,6000,1.5,2.1,0.5,2500,400\nM2,1.2,3.6,3000,6000,1.5,2,,,\n"
                                    "M3,1.2,3.6,3000,6000,1.5,2,0.6,,\n")
    table = read_catalog(path, "motors")
    assert table.loc[0, "resistance"] == pytest.approx(2.5) and table.loc[0, "voltage"] == 400
    assert table[["resistance", "voltage"]].iloc[1:].isna().all().all()


def test_example_motors_pass_their_voltage_limit_wherever_their_curve_lets_them_run():
    """The voltage k_t n + R T/k_t is linear in (n, T), so over the intermittent zone it is largest at a corner:
    (n_r, T_p), (n_max, T_r n_r/n_max) or (n_max, 0); at each the examples stay below their 400 V."""
    from mechatron.io.data import data_dir

    motors = read_catalog(data_dir("examples/data") / "motors.csv", "motors")
    kt, R, U = motors["torque_constant"], motors["resistance"], motors["voltage"]
    n_r, n_max = motors["rated_speed"], motors["max_speed"]
    corners = [(n_r, motors["peak_torque"]), (n_max, motors["rated_torque"] * n_r / n_max), (n_max, 0.0)]
    for n, torque in corners:
        assert ((kt * n + R * torque / kt) < U).all()


@pytest.mark.parametrize("text, field, message", [
    ("S,ball screw,16,5,0.9,3000,13.3,bolted", "end_fixing", "unknown end fixing 'bolted'"),
    ("S,ball screw,16,5,0.9,3000,16,fixed-pinned", "diameter_mm", "diameter is not above root_diameter"),
])
def test_bad_screw_columns(tmp_path, text, field, message):
    path = write(tmp_path, "key,type,diameter_mm,lead_mm,efficiency,max_speed_rpm,root_diameter_mm,end_fixing\n"
                           + text + "\n", "s.csv")
    with pytest.raises(InputError, match=message) as info:
        read_catalog(path, "linear")
    assert (info.value.row, info.value.field) == (2, field)


def test_screw_and_rack_columns_convert(tmp_path):
    path = write(tmp_path, "key,type,diameter_mm,lead_mm,efficiency,max_speed_rpm,root_diameter_mm,end_fixing,"
                           "max_length_mm,permitted_force_kN\nS,ball screw,16,5,0.9,3000,13.3,fixed-pinned,1500,\n"
                           "R,rack,40,125.66,0.96,3000,,,,4\n", "s.csv")
    table = read_catalog(path, "linear")
    assert table.loc[0, ["root_diameter", "max_length"]].tolist() == pytest.approx([0.0133, 1.5])
    assert table.loc[0, "end_fixing"] == "fixed-pinned" and table.loc[1, "permitted_force"] == pytest.approx(4000)
