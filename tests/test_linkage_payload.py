r"""The linkage analysis' cylinder forces carry a task's payload and loads (issue 32, item 3), on the scissor lift
of examples/data/scissor_lift.toml, against its hand closed form (tests/test_scissor_lift.py derives it) and against
the ``dynamics`` analysis of the same task at rest.

The closed form: arm 1 (ℓ = 1.2 m) turns about foot1 by θ, the cylinder runs from P = (0.5, −0.15) m to the bracket
Q = f ℓ (cos θ, sin θ), f = 0.75, so with ρ = |P|, α = atan2(P_y, P_x), k = (f²ℓ² + ρ² − c²)/(2 f ℓ ρ):
θ = α + arccos k, and θ_c = c / (f ℓ ρ sin(θ − α)). The platform stays level, its deck at x = 0.6 m and height
h = ℓ sin θ + 0.08 m, so ∂h/∂c = ℓ cos θ θ_c and ∂x/∂c = 0. Virtual work at rest, F δc = δV, what the platform carries
moving as the deck does (a rigid translation): F = (g (m_p + m_a + m) − F_y) ∂h/∂c with the platform's
m_p = 500 kg, m_a = 30 kg for the two 30 kg arms (each arm's middle rises half as fast as the deck), the
task's payload m = 200 kg (its centre 0.1 m, 0.05 m off the deck: the same translation) and the task's load
F = (300, −1000) N on the deck (F_x does no work: x is fixed).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import mechatron
from mechatron.errors import InputError
from mechatron.studies.analyses import analysis

ROOT = Path(__file__).resolve().parent.parent
LIFT = ROOT / "examples" / "data" / "scissor_lift.toml"
G, ELL, F_Q, P = 9.81, 1.2, 0.75, (0.5, -0.15)
M_PLATFORM, M_ARMS, PAYLOAD, LOAD = 500.0, 30.0, 200.0, (300.0, -1000.0)


def theta(c: float) -> float:
    rho, alpha = math.hypot(*P), math.atan2(P[1], P[0])
    return alpha + math.acos((F_Q**2 * ELL**2 + rho**2 - c**2) / (2 * F_Q * ELL * rho))


def dh_dc(c: float) -> float:
    rho, alpha = math.hypot(*P), math.atan2(P[1], P[0])
    t = theta(c)
    return ELL * math.cos(t) * c / (F_Q * ELL * rho * math.sin(t - alpha))


def hand_force(c: float, task: bool) -> float:
    """The static cylinder force (N) at length c by virtual work (the module docstring)."""
    weight = G * (M_PLATFORM + M_ARMS + (PAYLOAD if task else 0.0)) - (LOAD[1] if task else 0.0)
    return weight * dh_dc(c)


@pytest.fixture(scope="module")
def lift():
    return mechatron.load(str(LIFT))


@pytest.fixture
def task(tmp_path):
    """A task holding the cylinder at 0.7 m (a trajectory CSV at rest) with a payload and a load on the deck."""
    (tmp_path / "hold.csv").write_text("t,cyl\n0,0.7\n1,0.7\n2,0.7\n")
    path = tmp_path / "hold.toml"
    path.write_text(f'payload = {PAYLOAD}\npayload_at = "deck"\npayload_com = [0.1, 0.05, 0.0]\n'
                    'trajectory = "hold.csv"\n[[loads]]\nframe = "deck"\n'
                    f'force = [{LOAD[0]}, {LOAD[1]}, 0.0]\n')
    return path


def test_a_poses_cylinder_force_is_the_dynamics_of_the_same_task_and_the_virtual_work(lift, task):
    linkage, dynamics = analysis("linkage"), analysis("dynamics")
    options = {"task": str(task), "samples": 11, "poses": [{"name": "mid", "inputs": {"cyl": 0.7}}]}
    linkage.check(lift, options)
    out = linkage.outputs(lift, options, seed=0)
    at_rest = dynamics.outputs(lift, {"task": str(task)}, seed=0)["cyl_peak_N"]
    assert out["mid.cyl_max_force_N"] == pytest.approx(at_rest, rel=1e-9)
    assert out["mid.cyl_max_force_N"] == pytest.approx(hand_force(0.7, task=True), rel=1e-8)
    assert out["mid.height_m"] == pytest.approx(ELL * math.sin(theta(0.7)) + 0.08, abs=1e-9)
    # without the task: the mechanism's own weights only
    bare = linkage.outputs(lift, {"samples": 11, "poses": [{"name": "mid", "inputs": {"cyl": 0.7}}]}, seed=0)
    assert bare["mid.cyl_max_force_N"] == pytest.approx(hand_force(0.7, task=False), rel=1e-8)
    # the task's files are the analysis' input files (a study's identity)
    assert [p.name for p in linkage.input_files(lift, options)] == ["hold.toml", "hold.csv"]


def test_the_sweeps_largest_force_carries_the_payload(lift, task):
    out = analysis("linkage").outputs(lift, {"task": str(task), "samples": 11}, seed=0)
    stroke = np.linspace(0.5, 0.84, 11)
    assert out["cyl_max_force_N"] == pytest.approx(max(abs(hand_force(c, True)) for c in stroke), rel=1e-8)


def test_forces_with_a_task_have_no_exact_gradient_and_a_missing_task_is_refused(lift, task, tmp_path):
    linkage = analysis("linkage")
    names = linkage.gradient_outputs(lift, {"task": str(task)})
    assert "cyl_max_force_N" not in names and "reach_m" in names
    assert "cyl_max_force_N" in linkage.gradient_outputs(lift, {})
    with pytest.raises(InputError, match="no such file|not found|does not exist"):
        linkage.check(lift, {"task": str(tmp_path / "missing.toml")})
