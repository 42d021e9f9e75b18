"""Independent reference implementations used by several tests (written from the textbook and Craig, not from
mechatron's code)."""

from __future__ import annotations

import math

import numpy as np


def textbook_A(theta: float, S: float, a: float, alpha: float) -> np.ndarray:
    """Eq. (4.40) written out element by element, translation column corrected to (a cos θ, a sin θ, S)."""
    ct, st, ca, sa = math.cos(theta), math.sin(theta), math.cos(alpha), math.sin(alpha)
    return np.array([
        [ct, -st * ca, st * sa, a * ct],
        [st, ct * ca, -ct * sa, a * st],
        [0.0, sa, ca, S],
        [0.0, 0.0, 0.0, 1.0],
    ])


def craig_A(alpha_prev: float, a_prev: float, theta: float, d: float) -> np.ndarray:
    """Craig's modified-DH link transform written out (Introduction to Robotics, eq. 3.6)."""
    ct, st, ca, sa = math.cos(theta), math.sin(theta), math.cos(alpha_prev), math.sin(alpha_prev)
    return np.array([
        [ct, -st, 0.0, a_prev],
        [st * ca, ct * ca, -sa, -sa * d],
        [st * sa, ct * sa, ca, ca * d],
        [0.0, 0.0, 0.0, 1.0],
    ])


def numpy_chain(table, q: np.ndarray) -> list[np.ndarray]:
    """B_{0,i} for i = 1..n as a product of link matrices (eq. 4.45), without the base placement."""
    out, B = [], np.eye(4)
    for link, qi in zip(table.links, q):
        theta = qi + link.theta if link.joint == "revolute" else link.theta
        S = link.d if link.joint == "revolute" else qi + link.d
        if table.convention == "standard":
            B = B @ textbook_A(theta, S, link.a, link.alpha)
        else:
            B = B @ craig_A(link.alpha, link.a, theta, S)
        out.append(B)
    return out


def textbook_angular_velocities(table, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
    """Ω_i = Σ_{j≤i} σ_j B_{0,j-1} e_z q̇_j for a standard-DH arm with identity base (eq. 4.53-4.56)."""
    frames = [np.eye(4)] + numpy_chain(table, q)
    omega, out = np.zeros(3), []
    for j, link in enumerate(table.links):
        if link.joint == "revolute":
            omega = omega + frames[j][:3, 2] * qd[j]
        out.append(omega.copy())
    return np.array(out)


def textbook_angular_accelerations(table, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray) -> np.ndarray:
    """E_i = Σ_{j≤i} σ_j (z_{j-1} q̈_j + Ω_{j-1} × z_{j-1} q̇_j), the time derivative (4.57) of (4.56)."""
    frames = [np.eye(4)] + numpy_chain(table, q)
    omega, eps, out = np.zeros(3), np.zeros(3), []
    for j, link in enumerate(table.links):
        if link.joint == "revolute":
            z = frames[j][:3, 2]
            eps = eps + z * qdd[j] + np.cross(omega, z) * qd[j]
            omega = omega + z * qd[j]
        out.append(eps.copy())
    return np.array(out)


def file_friction_at_joints(table, qd: np.ndarray) -> np.ndarray:
    """The friction of a robot file's drives seen at the joints, (N, n) (N·m or N): each drive's motor-side
    viscous B·ω_m and Coulomb T_c (the first of its two for ω_m > 0, the second for ω_m < 0, none at rest) at the
    motor speed ω_m = u·q̇, carried to the joint through its gear ratio u (virtual work: τ_joint = u·τ_motor)."""
    qd = np.atleast_2d(np.asarray(qd, dtype=float))
    out = np.zeros_like(qd)
    for k, link in enumerate(table.links):
        drive = link.drive
        if drive is None:
            continue
        w = drive.gear_ratio * qd[:, k]
        coulomb = np.where(w > 0, drive.coulomb_friction[0], np.where(w < 0, drive.coulomb_friction[1], 0.0))
        out[:, k] = drive.gear_ratio * (drive.viscous_friction * w + coulomb)
    return out
