"""Batched RNEA/ABA/CRBA at every thread count: the same numbers as a plain loop over Pinocchio, threads chosen by
size and idle cores, settable by ``threads=`` and ``MECHATRON_THREADS``."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import mechatron
from mechatron.dynamics import tree
from mechatron.errors import InputError

COUNTS = (None, 1, 2, 3, 64)  # None: chosen automatically; counts above the cores are capped


def states(mech, rng, n):
    return mech.random_configuration(rng, n), rng.normal(size=(n, mech.nv)), rng.normal(size=(n, mech.nv))


@pytest.mark.parametrize("name", ["puma560", "ur5", "scara"])
def test_every_thread_count_gives_the_plain_loop_bit_for_bit(rng, name):
    mech = mechatron.load(name)
    model, data = mech.model, mech.model.createData()
    Q, V, A = states(mech, rng, 301)
    tau = np.array([pin.rnea(model, data, q, v, a) for q, v, a in zip(Q, V, A)])
    acc = np.array([pin.aba(model, data, q, v, t, pin.Convention.WORLD) for q, v, t in zip(Q, V, tau)])
    default = np.array([pin.aba(model, data, q, v, t) for q, v, t in zip(Q, V, tau)])
    M = np.array([pin.crba(model, data, q) for q in Q])
    M = np.triu(M) + np.swapaxes(np.triu(M, 1), 1, 2)
    for threads in COUNTS:
        np.testing.assert_array_equal(tree.inverse_dynamics(mech, Q, V, A, threads=threads), tau)
        ours = tree.forward_dynamics(mech, Q, V, tau, threads=threads)
        np.testing.assert_array_equal(ours, acc)
        np.testing.assert_allclose(ours, default, rtol=1e-12, atol=1e-12 * np.abs(default).max())
        np.testing.assert_array_equal(tree.mass_matrix(mech, Q, threads=threads), M)
    for i in (0, 150):  # one state takes the single-call path and gives the same bits
        np.testing.assert_array_equal(tree.inverse_dynamics(mech, Q[i], V[i], A[i]), tau[i])
        np.testing.assert_array_equal(tree.forward_dynamics(mech, Q[i], V[i], tau[i]), acc[i])
        np.testing.assert_array_equal(tree.mass_matrix(mech, Q[i]), M[i])
    assert tree.forward_dynamics(mech, Q[:1], V[:1], tau[:1]).shape == (1, mech.nv)
    assert tree.inverse_dynamics(mech, Q[:1], V[:1], A[:1]).shape == (1, mech.nv)


def test_forced_threads_beyond_the_cores_still_agree(rng, monkeypatch):
    """A pool resized to more copies than it was built with (the affinity grew) and more threads than states."""
    mech = mechatron.load("puma560")
    model, data = mech.model, mech.model.createData()
    Q, V, A = states(mech, rng, 5)
    tau = np.array([pin.rnea(model, data, q, v, a) for q, v, a in zip(Q, V, A)])
    np.testing.assert_array_equal(tree.inverse_dynamics(mech, Q, V, A, threads=1), tau)
    monkeypatch.setattr(tree, "available_cores", lambda: 4)
    assert tree.thread_count(5, 4) == 4 and tree.thread_count(3, 4) == 3
    np.testing.assert_array_equal(tree.inverse_dynamics(mech, Q, V, A, threads=4), tau)
    assert mech.cached("model_pool", None).size() >= 4


def test_thread_count_by_size_idle_cores_argument_and_environment(monkeypatch):
    monkeypatch.delenv(tree.THREADS_VARIABLE, raising=False)
    monkeypatch.setattr(tree, "available_cores", lambda: 4)
    monkeypatch.setattr(tree, "idle_cores", lambda cores: cores)
    per = tree.SAMPLES_PER_THREAD
    assert [tree.thread_count(n) for n in (1, 64, 1000, per - 1, 2 * per, 3 * per, 100 * per)] == [1, 1, 1, 1, 2, 3, 4]
    monkeypatch.setattr(tree, "idle_cores", lambda cores: 1)  # a busy machine: serial at any size
    assert tree.thread_count(100 * per) == 1
    assert tree.thread_count(10, threads=3) == 3 and tree.thread_count(10, threads=9) == 4  # capped at the cores
    monkeypatch.setenv(tree.THREADS_VARIABLE, "2")
    assert tree.thread_count(10) == 2 and tree.thread_count(10, threads=1) == 1  # the argument wins
    monkeypatch.setenv(tree.THREADS_VARIABLE, "  ")
    assert tree.thread_count(100 * per) == 1
    for bad in (0, -1, 1.5, "two", float("nan")):
        with pytest.raises(InputError, match="threads"):
            tree.thread_count(10, threads=bad)
    monkeypatch.setenv(tree.THREADS_VARIABLE, "0")
    with pytest.raises(InputError, match="MECHATRON_THREADS"):
        tree.thread_count(10)


def test_cores_and_idle_cores_are_bounded():
    cores = tree.available_cores()
    assert 1 <= cores <= (__import__("os").cpu_count() or 1)
    assert 1 <= tree.idle_cores(cores) <= cores


def test_the_shortcut_check_refuses_what_the_full_check_refuses(rng):
    """Float64 arrays take a shortcut check (a finite sum); anything else, and any non-finite entry, the full one."""
    mech = mechatron.load("puma560")
    Q, V, A = states(mech, rng, 3)
    tau = tree.inverse_dynamics(mech, Q, V, A)
    np.testing.assert_array_equal(tree.inverse_dynamics(mech, Q.tolist(), V.tolist(), A.tolist()), tau)
    np.testing.assert_array_equal(tree.inverse_dynamics(mech, Q[0].tolist(), V[0], A[0]), tau[0])
    for bad in (np.nan, np.inf, -np.inf):
        for k in range(3):
            args = [x.copy() for x in (Q, V, A)]
            args[k][1, 2] = bad
            with pytest.raises(InputError, match="finite"):
                tree.inverse_dynamics(mech, *args)
            with pytest.raises(InputError, match="finite"):
                tree.forward_dynamics(mech, *(x[1] for x in args))
        q = Q[1].copy()
        q[0] = bad
        with pytest.raises(InputError, match="finite"):
            tree.mass_matrix(mech, q)
    with pytest.raises(InputError):
        tree.inverse_dynamics(mech, Q, V[:, :5], A)
    huge = np.full(mech.nv, 1e308)  # finite entries whose sum overflows: the full check lets them through ...
    with pytest.raises(InputError, match="overflows"):  # ... and the torques they give overflow
        tree.inverse_dynamics(mech, Q[0], huge, np.zeros(mech.nv))
