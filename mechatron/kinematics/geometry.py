"""Planar geometry of a mechanism's points: positions, transmission angles, lever arms, distances, and the measures
a mechanism reports along a motion (:class:`~mechatron.model.mechanism.Measure`).

One implementation each: the vectorized functions take arrays (N, 2) of point positions; the mechanism-level ones
evaluate the points at one configuration and call them.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from ..model.mechanism import Measure, Mechanism


def point_positions(mech: Mechanism, q: ArrayLike, *frames: str) -> list[NDArray[np.float64]]:
    """World (x, y) (m) of the origins of ``frames`` at q (nq,): r = B_{0,i} r_i ([Egorov, 4.44])."""
    pin.forwardKinematics(mech.model, mech.data, np.asarray(q, dtype=float))
    return [pin.updateFramePlacement(mech.model, mech.data, mech.frame_id(f)).translation[:2].copy()
            for f in frames]


def acute_angle(cosine: ArrayLike) -> NDArray[np.float64]:
    """The transmission-angle fold: μ = arccos(min(1, |c|)) (rad, in [0, π/2]), the acute angle between two lines
    whose directions make an angle θ of cosine c = cos θ. θ, π − θ, π + θ and −θ fold onto one μ (θ = 0 and π give 0,
    π/2 and 3π/2 give π/2); a |c| rounded just above 1 gives 0. The one place of this formula: every transmission
    angle, of lines of points (:func:`transmission_angles`) or of a triangle's sides, is this of its cosine."""
    return np.arccos(np.minimum(1.0, np.abs(np.asarray(cosine, dtype=float))))


def transmission_angles(a: ArrayLike, b: ArrayLike, c: ArrayLike, d: ArrayLike) -> NDArray[np.float64]:
    """Angle (rad, in [0, π/2]) between the lines ab and cd for arrays (N, 2) of points (m): the transmission angle
    when ab is the coupler or cylinder and cd the driven lever (90° is ideal; designs ask for at least 30° or so,
    [Shovel, 3.18–3.19]): μ = :func:`acute_angle` of cos θ = (u · w) / (|u| |w|), u = b − a, w = d − c."""
    a, b, c, d = (np.atleast_2d(np.asarray(x, dtype=float)) for x in (a, b, c, d))
    u, w = b - a, d - c
    return acute_angle((u * w).sum(axis=1) / (np.linalg.norm(u, axis=1) * np.linalg.norm(w, axis=1)))


def lever_arms(base: ArrayLike, eye: ArrayLike, pivot: ArrayLike) -> NDArray[np.float64]:
    """Distance (m) from ``pivot`` to the line base–eye for arrays (N, 2) of points: the arm of a cylinder's force
    about the pivot; for a cylinder across a revolute joint it equals dL/dθ."""
    base, eye, pivot = (np.atleast_2d(np.asarray(x, dtype=float)) for x in (base, eye, pivot))
    axis, r = eye - base, pivot - base
    return np.abs(axis[:, 0] * r[:, 1] - axis[:, 1] * r[:, 0]) / np.linalg.norm(axis, axis=1)


def distances(a: ArrayLike, b: ArrayLike) -> NDArray[np.float64]:
    """Distance (m) between the points of two arrays (N, 2)."""
    return np.linalg.norm(np.atleast_2d(b) - np.atleast_2d(a), axis=1)


def line_angle(mech: Mechanism, q: ArrayLike, a: str, b: str, c: str, d: str) -> float:
    """Angle (rad, in [0, π/2]) between the lines ab and cd of four points of ``mech`` at q
    (:func:`transmission_angles`)."""
    return float(transmission_angles(*point_positions(mech, q, a, b, c, d))[0])


def lever_arm(mech: Mechanism, q: ArrayLike, base: str, eye: str, pivot: str) -> float:
    """Distance (m) from the point ``pivot`` to the line base–eye of ``mech`` at q (:func:`lever_arms`)."""
    return float(lever_arms(*point_positions(mech, q, base, eye, pivot))[0])


def distance(mech: Mechanism, q: ArrayLike, a: str, b: str) -> float:
    """Distance (m) between two points of ``mech`` at q."""
    return float(distances(*point_positions(mech, q, a, b))[0])


MEASURES: dict[str, Callable[..., NDArray[np.float64]]] = {
    "transmission_angle": transmission_angles, "lever_arm": lever_arms, "distance": distances}


def measure_values(measure: Measure, positions: Mapping[str, ArrayLike]) -> NDArray[np.float64]:
    """Values of ``measure`` (rad or m) for arrays (N, 2) of the positions of its points."""
    try:
        function = MEASURES[measure.kind]
    except KeyError:
        raise InputError(f"unknown measure kind {measure.kind!r}; expected one of: {', '.join(MEASURES)}") from None
    return function(*(positions[name] for name in measure.points))
