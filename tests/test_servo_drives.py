"""Servo drives from a catalog (mechatron.drives.servo): the drive's peak current limiting the motor's peak torque,
the two-level foldback, the shipped catalog and bad drive catalogs, by hand numbers."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from mechatron.drives.catalogs import default_catalog, read_catalog
from mechatron.drives.duty import JointDuty
from mechatron.drives.joint import size_joint
from mechatron.drives.servo import overload, pair_drives
from mechatron.errors import InputError

# A motor of k_t = 0.5 N·m/A, T_r = 1.5 N·m, T_p = 3 N·m (peak current 6 A), direct on a joint at rest.
MOTOR = pd.DataFrame([{"key": "M", "rated_torque": 1.5, "peak_torque": 3.0, "rated_speed": 300.0, "max_speed": 500.0,
                       "rotor_inertia": 1e-4, "torque_constant": 0.5, "mass": 2.0}])


def _drive(key, rated, peak, t_peak, mass):
    return {"key": key, "rated_current": rated, "peak_current": peak, "peak_time": t_peak, "dc_link_min": 300.0,
            "dc_link_max": 750.0, "mass": mass}


def _duty(t, tau):
    return JointDuty("q", "revolute", t, np.zeros_like(t), np.zeros_like(t), tau, tau, 0.0)


def test_the_drive_limits_the_peak_torque():
    """2 N·m for 0.5 s of 2 s, 0.5 N·m else: the light drive's 3 A gives k_t I_p = 1.5 N·m < 2 (fails), the heavier
    one's 5 A gives 2.5 N·m: the choice moves to it; RMS current √((4·0.5 + 0.25·1.5)/2)/0.5 = 2.18 A ≤ 2.5 A."""
    t = np.linspace(0, 2, 2001)
    duty = _duty(t, np.where(t < 0.5 - 1e-9, 2.0, 0.5))
    drives = pd.DataFrame([_drive("small", 2.5, 3.0, 2.0, 0.5), _drive("big", 2.5, 5.0, 2.0, 1.0)])
    result = size_joint(duty, pair_drives(MOTOR, drives))
    checks = {c.name: c for c in result.checks}
    assert result.feasible and result.motor == "M + big"
    assert checks["peak torque"].limit == pytest.approx(2.5)
    assert checks["drive RMS current"].value == pytest.approx(np.sqrt((4 * 0.5 + 0.25 * 1.5) / 2) / 0.5, rel=2e-3)
    assert checks["drive overload time"].value == pytest.approx(0.5)
    assert result.ranking["mass"].iloc[0] == pytest.approx(3.0)  # motor 2 kg + drive 1 kg
    only = size_joint(duty, pair_drives(MOTOR, drives.iloc[:1]))
    assert not only.feasible and "peak torque" in only.closest["failed"].iloc[0]


@pytest.mark.parametrize(("peak", "passes"), [(3.0, False), (1.5, True)])
def test_foldback(peak, passes):
    """3 A (1.5 N·m) for ``peak`` s of a 20 s cycle on a drive of 2 A rated, 6 A for 2 s: 3 s fails, 1.5 s passes."""
    t = np.linspace(0, 20, 2001)
    tau = np.where(t < peak - 1e-9, 1.5, 0.0)
    assert overload(t, tau / 0.5, 2.0)[1] == pytest.approx(peak)
    result = size_joint(_duty(t, tau), pair_drives(MOTOR, pd.DataFrame([_drive("D", 2.0, 6.0, 2.0, 1.0)])))
    assert result.feasible is passes


def test_a_run_through_the_end_counts_once():
    """Above rated for the last 1 s and the first 1 s of a repeated 10 s task: one run of 2 s."""
    t = np.linspace(0, 10, 101)
    current = np.where((t < 1 - 1e-9) | (t >= 9 - 1e-9), 5.0, 0.0)
    assert overload(t, current, 2.0)[1] == pytest.approx(2.0)


def test_the_shipped_catalog_reads():
    drives = default_catalog("drives")
    assert (drives["peak_current"] >= drives["rated_current"]).all()


@pytest.mark.parametrize(("cell", "field", "message"), [("peak_current_A", "peak_current_A", "is below rated_current"),
                                                         ("rated_current_A", "rated_current_A", "must be")])
def test_bad_drive_catalogs(tmp_path, cell, field, message):
    """A drive whose peak current is below its rated, or a NaN or negative value: one error naming file, row, field."""
    good = {"key": "D", "rated_current_A": "4", "peak_current_A": "12", "peak_time_s": "2", "dc_link_min_V": "300",
            "dc_link_max_V": "750"}
    for bad in (["3"] if cell == "peak_current_A" else ["nan", "-1"]):
        path = tmp_path / "drives.csv"
        row = {**good, cell: bad}
        path.write_text(",".join(row) + "\n" + ",".join(row.values()) + "\n")
        with pytest.raises(InputError) as error:
            read_catalog(path, "drives")
        text = str(error.value)
        assert "drives.csv" in text and "row 2" in text and field in text


def test_no_motor_to_pair():
    with pytest.raises(InputError, match="torque constant"):
        pair_drives(MOTOR.drop(columns=["torque_constant"]), pd.DataFrame([_drive("D", 2.0, 6.0, 2.0, 1.0)]))


@pytest.mark.parametrize(("cell", "bad", "message"), [("peak_current_A", "3", "is below rated_current"),
                                                      ("rated_current_A", "nan", "rated_current_A"),
                                                      ("rated_current_A", "-1", "rated_current_A")])
def test_bad_drive_catalogs_through_the_cli(tmp_path, cell, bad, message):
    """``mechatron size … --drives bad.csv``: exit 2 and one line naming the file, the row and the field."""
    import subprocess
    import sys

    good = {"key": "D", "rated_current_A": "4", "peak_current_A": "12", "peak_time_s": "2", "dc_link_min_V": "300",
            "dc_link_max_V": "750"}
    path = tmp_path / "bad.csv"
    path.write_text(",".join(good) + "\n" + ",".join(good.values()) + "\n"
                    + ",".join({**good, "key": "E", cell: bad}.values()) + "\n")
    cli = subprocess.run([sys.executable, "-m", "mechatron", "size", "puma560", "--drives", str(path)],
                         capture_output=True, text=True)
    lines = cli.stderr.strip().splitlines()
    assert cli.returncode == 2 and len(lines) == 1, cli.stderr
    assert str(path) in lines[0] and "row 3" in lines[0] and cell in lines[0] and message in lines[0]


def test_the_drive_is_its_own_field_of_the_report():
    """The chosen drive next to the motor: JSON ``drive`` (None without drives) and the text's headline."""
    t = np.linspace(0, 2, 201)
    duty = _duty(t, np.full_like(t, 1.0))
    result = size_joint(duty, pair_drives(MOTOR, pd.DataFrame([_drive("D", 2.5, 5.0, 2.0, 1.0)])))
    assert result.drive == "D" and result.as_dict()["drive"] == "D" and result.as_dict()["motor"] == "M + D"
    assert result.headline() == "q: motor M with servo drive D: 2.5 A rated, 5 A peak for 2 s, 1 kg + direct drive"
    plain = size_joint(duty, MOTOR)
    assert plain.drive is None and plain.as_dict()["drive"] is None and plain.headline() == "q: motor M + direct drive"
