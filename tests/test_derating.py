"""Derating of the S1 torque for the site (mechatron.drives.derating), by hand numbers."""

from __future__ import annotations

import math
import subprocess
import sys

import pandas as pd
import pytest

from mechatron.drives.derating import altitude_factor, ambient_factor, check_altitude, derate
from mechatron.drives.options import SizingOptions
from mechatron.errors import InputError


def test_rise_limited_ambient():
    """Rated at 40 °C for a 100 K rise, run at 65 °C: √(75/100) = 0.866; at or below 40 °C: 1."""
    assert ambient_factor(65.0) == pytest.approx(math.sqrt(0.75))
    assert ambient_factor(65.0) == pytest.approx(0.8660254, abs=1e-7)
    assert ambient_factor(20.0) == 1.0 and ambient_factor(140.0) == 0.0


def test_altitude_rule():
    """10 % per 1,000 m above 1,000 m: 2,500 m keeps 1 − 0.1·1.5 = 0.85; 800 m keeps 1."""
    assert altitude_factor(2500.0) == pytest.approx(0.85)
    assert altitude_factor(800.0) == 1.0


def test_derate_a_catalog():
    """A motor without thermal columns: T_r × 0.866 × 0.85 at 65 °C and 2,500 m; a thermal one: R_ha / 0.85²."""
    motors = pd.DataFrame([{"key": "A", "rated_torque": 2.0}, {"key": "B", "rated_torque": 2.0,
                                                                 "rth_housing_ambient": 1.0}])
    out = derate(motors, 65.0, 2500.0)
    assert out["rated_torque"].tolist() == pytest.approx([2.0 * math.sqrt(0.75) * 0.85, 2.0])
    assert out["rth_housing_ambient"].iloc[1] == pytest.approx(1 / 0.85**2)
    assert derate(motors, 40.0, 0.0) is motors


@pytest.mark.parametrize("altitude", [-1000.0, 1e6, math.nan])
def test_bad_altitude(altitude):
    with pytest.raises(InputError, match="-500"):
        check_altitude(altitude)
    with pytest.raises(InputError, match="altitude"):
        SizingOptions(altitude=altitude)


@pytest.mark.parametrize("altitude", ["-1000", "1e6"])
def test_bad_altitude_cli(altitude):
    """``mechatron size --altitude`` out of range: one line, exit 2."""
    run = subprocess.run([sys.executable, "-m", "mechatron", "size", "planar_2r", f"--altitude={altitude}"],
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 2 and "altitude" in run.stderr
