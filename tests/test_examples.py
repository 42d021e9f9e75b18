"""The example scripts run and say what they computed."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def test_arm_workspace_example(tmp_path):
    output = tmp_path / "ws.png"
    proc = subprocess.run([sys.executable, str(EXAMPLES / "arm_workspace.py"), "planar_2r", "--samples", "2000",
                           "--output", str(output)], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert output.stat().st_size > 10_000
    # reach of a 0.5 + 0.4 m arm: at most l1 + l2; the manipulability l1·l2·|sin q2| is at most 0.2
    words = proc.stdout.split()
    assert float(words[words.index("…") + 1]) <= 0.9 + 1e-12
    assert float(words[words.index("manipulability") + 1].rstrip(";")) <= 0.2 + 1e-12


def test_bucket_linkage_example(tmp_path):
    proc = subprocess.run([sys.executable, str(EXAMPLES / "bucket_linkage.py"), "--volume", "0.5",
                           "--csv", str(tmp_path / "b.csv"), "--plot", str(tmp_path / "b.png")],
                          capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert "c = 0.4103 m, L2 = 0.4931 m" in proc.stdout  # as tests/test_bucket.py
    assert "turns 160.000000°" in proc.stdout
    assert (tmp_path / "b.png").exists() and (tmp_path / "b.csv").exists()


def test_grab_scooping_example(tmp_path):
    proc = subprocess.run([sys.executable, str(EXAMPLES / "grab_scooping.py"), "--plot", str(tmp_path / "g.png")],
                          capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert "jaw closed after" in proc.stdout and (tmp_path / "g.png").exists()
    import re

    work, energy = (float(x) for x in re.search(r"resistance ([-\d.]+) kJ = change of kinetic \+ potential energy "
                                                r"([-\d.]+) kJ", proc.stdout).groups())
    assert work == pytest.approx(energy, abs=2e-3)


def test_puma_pick_and_place_example(tmp_path):
    proc = subprocess.run([sys.executable, str(EXAMPLES / "puma_pick_and_place.py"), "--charts", str(tmp_path),
                           "--csv", str(tmp_path / "checks.csv")], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert "every joint has a feasible drive" in proc.stdout
    assert len(list(tmp_path.glob("puma560_q*.png"))) == 6
    lines = {line.split()[0]: line for line in proc.stdout.splitlines()[-4:]}
    mass = {k: float(v.split()[1]) for k, v in lines.items()}
    price = {k: float(v.split()[3]) for k, v in lines.items()}
    assert mass["mass"] == min(mass.values()) and price["cost"] == min(price.values())


def test_cylindrical_robot_ratios_example(tmp_path):
    for motor, rule in (("SM60-0.64-30", "min. time"), ("SM130-11-30", "inertia matching")):
        proc = subprocess.run([sys.executable, str(EXAMPLES / "cylindrical_robot_ratios.py"), "--motor", motor,
                               "--plot", str(tmp_path / "r.png")], capture_output=True, text=True)
        assert proc.returncode == 0, proc.stderr
        rows = {line.split()[0]: line.split() for line in proc.stdout.splitlines() if line.startswith("q")}
        assert set(rows) == {"q1", "q2", "q3"} and (tmp_path / "r.png").stat().st_size > 10_000
        # the numerical optimum never takes longer than the book's choice
        for row in rows.values():
            assert float(row[-1]) <= float(row[-2]) + 1e-12
        assert rule in proc.stdout


def test_front_shovel_cylinders_example(tmp_path):
    proc = subprocess.run([sys.executable, str(EXAMPLES / "front_shovel_cylinders.py"), "--charts", str(tmp_path)],
                          capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.count("every joint has a feasible drive") == 2
    assert "L1: 2 × HC" in proc.stdout and "pump flow" in proc.stdout
    assert len(list(tmp_path.glob("front_shovel_L*.png"))) == 3
