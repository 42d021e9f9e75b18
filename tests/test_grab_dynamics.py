"""Scooping with the grab [Mikhailov]: the paper's own 13-unknown formulation (7 absolute coordinates and 6
multipliers, [Mikhailov, 8], in validation/grab.py) against the Pinocchio tree with closures, energy balance and
constraint drift, and the pin forces against the paper's multipliers.

The paper's [Mikhailov, 18] prints ∂Φ6/∂φ10 = r24 cos(φ20 + φ24); Φ6 does not depend on φ10 and the entry belongs to
φ20 (the model derives T from Φ). Its loads are symbols only [Mikhailov, 12]; the closing rope, the cutting
resistance and gravity are set out in mechatron.machines.grab.ScoopingLoads.
"""

from __future__ import annotations

import numpy as np
import pytest

import mechatron
from mechatron.dynamics import constrained as cd
from mechatron.kinematics.frames import frame_placement
from mechatron.kinematics.loops import assemble
from mechatron.machines.grab import GrabGeometry, ScoopingLoads, mechanism_loads, plot_scooping, scooping_forces
from validation.grab import PaperModel


@pytest.fixture(scope="module")
def runs():
    g, loads = GrabGeometry(), ScoopingLoads()
    paper = PaperModel(g, loads).simulate(g.open_angle, 0.0, 1.0, 2e-3)
    mech = mechatron.load("grab")
    sim = cd.simulate(mech, assemble(mech, {"phi1": g.open_angle}), np.zeros(mech.nv), paper["t"][-1], 2e-3,
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
    """Φ6 = y20 + r24 sin(φ20 + φ24) − y30 − r34 sin φ34 depends on φ20, not on φ10 [Mikhailov, 18]."""
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


def test_pin_forces_of_the_model_equal_the_papers_multipliers(runs):
    """The model's pin forces (its closure multipliers and Newton's law for the jaw and the rods) are the paper's
    λ1…λ6: the hinge's horizontal force |λ1|, the cutting edge's normal force |λ2| √(1 + η′²) (the paper's Φ2 is
    y − η(x) too), the jaw–rods pin |(λ3, λ4)| and the rods–crosshead pin |(λ5, λ6)|."""
    _, paper, mech, sim = runs
    n = min(len(paper["t"]), len(sim.t))
    forces = scooping_forces(mech, sim, ScoopingLoads())
    lam = paper["multipliers"][:n]
    g = GrabGeometry()
    tips = np.array([PaperModel(g, ScoopingLoads()).tip(X, Xd)[0] for X, Xd in zip(paper["X"][:n], paper["Xd"][:n])])
    slope = 2 * g.curvature * (tips[:, 0] + g.deepest_x)
    expected = {"hinge_horizontal": np.abs(lam[:, 0]), "cutting_edge_normal": np.abs(lam[:, 1]) * np.hypot(1, slope),
                "jaw_rods_pin": np.hypot(lam[:, 2], lam[:, 3]), "rods_crosshead_pin": np.hypot(lam[:, 4], lam[:, 5])}
    for name, values in expected.items():
        np.testing.assert_allclose(forces[name][:n], values, rtol=1e-4, atol=1.0, err_msg=name)


def test_joint_reactions_carry_the_curve_force(runs):
    """The hinge's horizontal force from the joint wrenches (RNEA with every closure force, the cutting edge's curve
    reaction included) equals the one from Newton's law of the jaw (:func:`scooping_forces`), hence |λ1|."""
    _, _, mech, sim = runs
    law = mechanism_loads(mech, ScoopingLoads())
    expected = scooping_forces(mech, sim, ScoopingLoads())["hinge_horizontal"]
    hinge = mech.joint_names.index("phi1")
    for i in range(0, len(sim.t), 25):
        t, q, v, a, lam = sim.t[i], sim.q[i], sim.v[i], sim.a[i], sim.multipliers[i]
        wrench = cd.reactions(mech, q, v, a, lam, law(t, q, v)).joints[hinge]
        assert abs(wrench[0]) == pytest.approx(expected[i], rel=1e-6)


def test_scooping_plot(runs):
    _, _, mech, sim = runs
    figure = plot_scooping(mech, sim)
    axes = [ax for ax in figure.axes if ax.has_data()]
    assert len(axes) == 3 and all("(" in ax.get_xlabel() and "(" in ax.get_ylabel() for ax in axes)
    assert all(ax.get_legend() is not None for ax in axes)
