"""Shared helpers for the test suite: random states and finite differences."""

from __future__ import annotations

import numpy as np
import pytest

import mechatron

DH_ROBOTS = ["planar_2r", "planar_3r", "cylindrical_rpp", "articulated_rrr", "scara", "puma560"]


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(20261121)


def random_state(mech: mechatron.Mechanism, rng: np.random.Generator):
    """A configuration inside the limits and arbitrary joint velocities and accelerations."""
    return mech.random_configuration(rng), rng.normal(size=mech.nv), rng.normal(size=mech.nv)


def central_difference(f, x: np.ndarray, h: float = 1e-6) -> np.ndarray:
    """Jacobian of f at x by central differences, shape f(x).shape + (len(x),)."""
    columns = []
    for k in range(len(x)):
        dx = np.zeros_like(x)
        dx[k] = h
        columns.append((np.asarray(f(x + dx)) - np.asarray(f(x - dx))) / (2 * h))
    return np.stack(columns, axis=-1)


def time_derivative(f, t0: float = 0.0, h: float = 1e-5) -> np.ndarray:
    """d f(t) / dt at t0 by a fourth-order central difference."""
    return (-np.asarray(f(t0 + 2 * h)) + 8 * np.asarray(f(t0 + h)) - 8 * np.asarray(f(t0 - h))
            + np.asarray(f(t0 - 2 * h))) / (12 * h)
