"""The lean path of one state (or a batch of one) of inverse_dynamics / forward_dynamics / mass_matrix: the bits of
Pinocchio's own calls, and the same clean errors as the full checks for every bad input it lets through to them."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import mechatron
from mechatron.dynamics import tree
from mechatron.errors import InputError
from mechatron.library import available_robots

ROBOTS = ("puma560", "ur5")
WORLD = pin.Convention.WORLD


def states(mech, rng, n):
    return mech.random_configuration(rng, n), rng.normal(size=(n, mech.nv)), rng.normal(size=(n, mech.nv))


@pytest.mark.parametrize("name", ROBOTS)
def test_one_state_and_batches_are_pinocchio_bit_for_bit(rng, name):
    mech = mechatron.load(name)
    model, data = mech.model, mech.model.createData()
    Q, V, A = states(mech, rng, 40)
    tau = np.array([pin.rnea(model, data, q, v, a) for q, v, a in zip(Q, V, A)])
    acc = np.array([pin.aba(model, data, q, v, t, WORLD) for q, v, t in zip(Q, V, tau)])
    M = np.array([pin.crba(model, data, q) for q in Q])
    np.testing.assert_array_equal(M, np.swapaxes(M, 1, 2))  # the binding returns M symmetric, bit for bit
    for i in range(len(Q)):  # one state, (nv,); a batch of one, (1, nv)
        np.testing.assert_array_equal(tree.inverse_dynamics(mech, Q[i], V[i], A[i]), tau[i])
        np.testing.assert_array_equal(tree.forward_dynamics(mech, Q[i], V[i], tau[i]), acc[i])
        np.testing.assert_array_equal(tree.mass_matrix(mech, Q[i]), M[i])
        np.testing.assert_array_equal(tree.inverse_dynamics(mech, Q[i:i + 1], V[i:i + 1], A[i:i + 1]), tau[i:i + 1])
        np.testing.assert_array_equal(tree.forward_dynamics(mech, Q[i:i + 1], V[i:i + 1], tau[i:i + 1]),
                                      acc[i:i + 1])
        np.testing.assert_array_equal(tree.mass_matrix(mech, Q[i:i + 1]), M[i:i + 1])
    np.testing.assert_array_equal(tree.inverse_dynamics(mech, Q, V, A), tau)
    np.testing.assert_array_equal(tree.forward_dynamics(mech, Q, V, tau), acc)
    np.testing.assert_array_equal(tree.mass_matrix(mech, Q), M)
    # results are fresh arrays: a later call does not overwrite an earlier result
    first = tree.inverse_dynamics(mech, Q[0], V[0], A[0])
    tree.inverse_dynamics(mech, Q[1], V[1], A[1])
    np.testing.assert_array_equal(first, tau[0])
    first = tree.forward_dynamics(mech, Q[0], V[0], tau[0])
    tree.forward_dynamics(mech, Q[1], V[1], tau[1])
    np.testing.assert_array_equal(first, acc[0])


@pytest.mark.parametrize("name", ROBOTS)
def test_other_dtypes_views_and_lists_give_the_same_bits(rng, name):
    mech = mechatron.load(name)
    Q, V, A = states(mech, rng, 2)
    tau, M = tree.inverse_dynamics(mech, Q[0], V[0], A[0]), tree.mass_matrix(mech, Q[0])
    Qi = np.round(Q * 100)  # whole numbers: exact as int64
    ints = tree.inverse_dynamics(mech, Qi[0], V[0], A[0])
    np.testing.assert_array_equal(tree.inverse_dynamics(mech, Qi[0].astype(int), V[0], A[0]), ints)
    np.testing.assert_array_equal(tree.inverse_dynamics(mech, Q[0], V[0], A[0].astype(np.float32)),
                                  tree.inverse_dynamics(mech, Q[0], V[0], A[0].astype(np.float32).astype(float)))
    np.testing.assert_array_equal(tree.inverse_dynamics(mech, Q[0].tolist(), V[0].tolist(), A[0].tolist()), tau)
    np.testing.assert_array_equal(tree.mass_matrix(mech, Q[0].tolist()), M)
    np.testing.assert_array_equal(tree.mass_matrix(mech, Qi[0].astype(int)), tree.mass_matrix(mech, Qi[0]))
    wide = np.zeros((3, 2 * mech.nv))
    wide[0, ::2], wide[1, ::2], wide[2, ::2] = Q[0], V[0], A[0]  # strided views
    np.testing.assert_array_equal(tree.inverse_dynamics(mech, wide[0, ::2], wide[1, ::2], wide[2, ::2]), tau)
    np.testing.assert_array_equal(tree.inverse_dynamics(mech, Q[0], V[0], A[0], threads=1), tau)
    np.testing.assert_array_equal(tree.mass_matrix(mech, Q[0], threads=1), M)


BAD_VALUES = (np.nan, np.inf, -np.inf)


@pytest.mark.parametrize("name", ROBOTS)
def test_bad_values_raise_naming_the_argument(rng, name):
    """A NaN/inf in any entry of any argument, single state or batch of one, as an array or a list."""
    mech = mechatron.load(name)
    q, v, a = (x[0] for x in states(mech, rng, 1))
    calls = {"inverse_dynamics": (tree.inverse_dynamics, ("q", "v", "a")),
             "forward_dynamics": (tree.forward_dynamics, ("q", "v", "a")),  # the full check calls τ "a"
             "mass_matrix": (tree.mass_matrix, ("q",))}
    for function, names in calls.values():
        for k, argument in enumerate(names):
            for bad in BAD_VALUES:
                for j in (0, mech.nv - 1):
                    args = [x.copy() for x in (q, v, a)[:len(names)]]
                    args[k][j] = bad
                    for form in (lambda x: x, lambda x: x[None], lambda x: x.tolist()):
                        with pytest.raises(InputError, match=rf"^{argument} must be finite"):
                            function(mech, *(form(x) for x in args))


@pytest.mark.parametrize("name", ROBOTS)
def test_wrong_shapes_raise_naming_the_argument(rng, name):
    mech = mechatron.load(name)
    q, v, a = (x[0] for x in states(mech, rng, 1))
    n = mech.nv
    short, column, two = np.zeros(n - 1), np.zeros((n, 1)), np.zeros((2, n))
    for bad, argument in ((short, "v"), (column, "v"), (two, "v"), (short[None], "v"), (np.zeros((1, 1, n)), "v")):
        with pytest.raises(InputError, match=rf"^{argument} must have shape"):
            tree.inverse_dynamics(mech, q, bad, a)
        with pytest.raises(InputError, match=rf"^{argument} must have shape"):
            tree.forward_dynamics(mech, q, bad, a)
        with pytest.raises(InputError, match="^a must have shape"):
            tree.inverse_dynamics(mech, q, v, bad)
    for bad in (short, np.zeros(n + 1), short[None], np.zeros(n + 1).tolist()):
        for call in (lambda x: tree.inverse_dynamics(mech, x, v, a), lambda x: tree.forward_dynamics(mech, x, v, a),
                     lambda x: tree.mass_matrix(mech, x)):
            with pytest.raises(InputError, match="^q must have"):
                call(bad)
    # one state's v with a batch of one: the full check takes it as that batch (as before the lean path)
    np.testing.assert_array_equal(tree.inverse_dynamics(mech, q[None], v, a[None]),
                                  tree.inverse_dynamics(mech, q, v, a)[None])
    with pytest.raises(InputError, match="^a must have shape"):
        tree.inverse_dynamics(mech, q[None], v[None], np.zeros((2, n)))


def test_overflow_raises_instead_of_returning_inf(rng):
    """Finite inputs whose results overflow: an InputError saying so, on the lean path and on batches."""
    mech = mechatron.load("puma560")
    q, v, a = (x[0] for x in states(mech, rng, 1))
    huge = np.full(mech.nv, 1e200)  # sums stay finite; q̇² and τ = M q̈ overflow
    with pytest.raises(InputError, match="overflows"):
        tree.inverse_dynamics(mech, q, huge, a)
    with pytest.raises(InputError, match="overflows"):
        tree.inverse_dynamics(mech, q, v, np.full(mech.nv, 1e308))
    with pytest.raises(InputError, match="overflows"):
        tree.forward_dynamics(mech, q, huge, a)
    with pytest.raises(InputError, match="overflows"):
        tree.inverse_dynamics(mech, np.tile(q, (3, 1)), np.tile(huge, (3, 1)), np.tile(a, (3, 1)))
    with pytest.raises(InputError, match="overflows"):
        tree.forward_dynamics(mech, np.tile(q, (3, 1)), np.tile(huge, (3, 1)), np.tile(a, (3, 1)))
    slider = mechatron.load("cylindrical_rpp")  # prismatic joints: M grows with q²
    far = np.array([0.0, 1e160, 1e160])
    with pytest.raises(InputError, match="overflows"):
        tree.mass_matrix(slider, far)
    with pytest.raises(InputError, match="overflows"):
        tree.mass_matrix(slider, np.tile(far, (3, 1)))


def test_the_mass_matrix_of_revolute_joints_is_bounded(rng):
    """Revolute joints about one axis: M(q) depends on q only through cos q and sin q, so its entries are bounded by
    the masses and lengths — at q = 1e300 as at any angle: M equals Pinocchio's and is not checked for overflow
    (the single and batched paths skip that check for such mechanisms only)."""
    for name in ("puma560", "ur5"):
        mech = mechatron.load(name)
        assert tree._revolute_only(mech)
        q = np.full(mech.nq, 1e300)
        M = pin.crba(mech.model, mech.model.createData(), q)
        assert np.isfinite(M).all()
        np.testing.assert_array_equal(tree.mass_matrix(mech, q), M)
        np.testing.assert_array_equal(tree.mass_matrix(mech, np.tile(q, (3, 1)))[2], M)
        bound = np.abs(np.array([pin.crba(mech.model, mech.model.createData(), x)
                                 for x in mech.random_configuration(rng, size=200)])).max()
        assert np.abs(M).max() <= 1.5 * bound
    assert not tree._revolute_only(mechatron.load("cylindrical_rpp"))


def test_the_result_check_catches_every_bad_acceleration_and_torque(rng):
    """The argument of ``_one_state``: a NaN/inf in q̈ (RNEA) or τ (ABA) makes the result non-finite, on every
    robot of the library at random states, while a bad q or q̇ need not (hence their own check)."""
    unseen = []
    for name in available_robots():
        mech = mechatron.load(name)
        model, data = mech.model, mech.model.createData()
        for _ in range(2):
            q, v, x = rng.uniform(-3, 3, model.nq), rng.normal(size=model.nv), rng.normal(size=model.nv)
            for k in range(model.nv):
                for bad in BAD_VALUES:
                    y = x.copy()
                    y[k] = bad
                    assert not np.isfinite(pin.rnea(model, data, q, v, y)).all(), (name, k, bad)
                    assert not np.isfinite(pin.aba(model, data, q, v, y, WORLD)).all(), (name, k, bad)
                    w = v.copy()
                    w[k] = bad
                    if np.isfinite(pin.rnea(model, data, q, w, x)).all():
                        unseen.append((name, k))
    assert ("crank_slider", 2) in unseen  # a NaN slider velocity gives finite torques: q̇ needs its own check
    mech = mechatron.load("crank_slider")
    with pytest.raises(InputError, match="^v must be finite"):
        tree.inverse_dynamics(mech, np.zeros(3), np.array([0.0, 0.0, np.nan]), np.zeros(3))
    with pytest.raises(InputError, match="^q must be finite"):  # M does not depend on the first angle
        tree.mass_matrix(mechatron.load("puma560"), np.array([np.nan, 0, 0, 0, 0, 0]))
