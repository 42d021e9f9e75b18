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
