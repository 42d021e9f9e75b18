"""Scooping with the grab (seed 003): the paper's own 13-unknown formulation (7 absolute coordinates and 6
multipliers, eq. 8) against the Pinocchio tree with closures, energy balance and constraint drift.

The paper's eq. (18) prints ∂Φ6/∂φ10 = r24 cos(φ20 + φ24); Φ6 does not depend on φ10 and the entry belongs to φ20
(the model derives T from Φ). Its loads are symbols only; the closing rope, the cutting resistance and gravity are
set out in mechatron.machines.grab.ScoopingLoads.
"""

from __future__ import annotations

import numpy as np
import pytest

import mechatron
from mechatron.dynamics import constrained as cd
from mechatron.kinematics.frames import frame_placement
from mechatron.kinematics.loops import assemble
from mechatron.machines.grab import GrabGeometry, PaperModel, ScoopingLoads, mechanism_loads


@pytest.fixture(scope="module")
def runs():
    g, loads = GrabGeometry(), ScoopingLoads()
    paper = PaperModel(g, loads).simulate(g.open_angle, 0.0, 1.0, 1e-3)
    mech = mechatron.load("grab")
    sim = cd.simulate(mech, assemble(mech, {"phi1": g.open_angle}), np.zeros(mech.nv), paper["t"][-1], 1e-3,
                      loads_at=mechanism_loads(mech, loads), stop=lambda t, q, v: q[1] >= 0.0)
    return g, paper, mech, sim


def test_jaw_closes(runs):
    g, paper, _, _ = runs
    assert paper["X"][0, 2] == pytest.approx(g.open_angle)
    assert paper["X"][-1, 2] >= 0.0 and 0.3 < paper["t"][-1] < 0.6  # the rope closes the jaw in about 0.4 s


def test_two_formulations_agree(runs):
    _, paper, mech, sim = runs
    n = min(len(paper["t"]), len(sim.t))
    np.testing.assert_allclose(sim.q[:n, 1], paper["X"][:n, 2], atol=1e-6)  # jaw angle φ10
    np.testing.assert_allclose(sim.v[:n, 1], paper["Xd"][:n, 2], atol=1e-5)
    # upper crosshead height and rods' angle
    crosshead = np.array([frame_placement(mech, q, "C3").translation[1] for q in sim.q[:n:20]])
    np.testing.assert_allclose(crosshead, paper["X"][:n:20, 6], atol=1e-6)


def test_energy_balance_and_drift(runs):
    _, paper, _, sim = runs
    energy = paper["kinetic"] + paper["potential"]
    # work of the rope and the resistance = change of kinetic + potential energy
    assert np.abs(energy - energy[0] - paper["work"]).max() < 1e-5 * np.abs(paper["work"]).max()
    assert np.abs(sim.energy - sim.energy[0] - sim.work).max() < 1e-5 * np.abs(sim.work).max()
    pm = PaperModel(GrabGeometry(), ScoopingLoads())
    drift = max(np.abs(pm.constraints(X)[0]).max() for X in paper["X"])
    assert drift < 1e-8 and sim.residual.max() < 1e-8


def test_printed_jacobian_misprint():
    """Φ6 = y20 + r24 sin(φ20 + φ24) − y30 − r34 sin φ34 depends on φ20, not on φ10 (eq. 18)."""
    pm = PaperModel(GrabGeometry(), ScoopingLoads())
    X, _ = pm.initial_state(-0.5)
    _, J = pm.constraints(X)
    assert J[5, 2] == 0.0 and J[5, 5] != 0.0
    h = 1e-7
    for k in range(7):
        e = np.zeros(7)
        e[k] = h
        np.testing.assert_allclose(J[:, k], (pm.constraints(X + e)[0] - pm.constraints(X - e)[0]) / (2 * h),
                                   atol=1e-7)


def test_pin_forces_from_the_multipliers(runs):
    """The multipliers are the pin forces: the jaw–rod pin carries the rope pull towards the upper crosshead."""
    _, paper, _, _ = runs
    lam = paper["multipliers"]
    assert lam.shape[1] == 6 and np.all(np.isfinite(lam))
    jaw_rod = np.hypot(lam[:, 2], lam[:, 3])
    assert jaw_rod.max() > ScoopingLoads().rope_tension  # of the order of the tackle force
