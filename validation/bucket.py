r"""The bucket paper's own analysis [Bucket, 8, 12–22] in closed form: the reference the closed-loop model of
:mod:`mechatron.machines.bucket` is checked against.

The paper prints Φ_t [Bucket, 15] and Φ_tt [Bucket, 21] with four rows (and labels (21) Φ_t); the fifth row is the
driving constraint Φ5 = L1 − L1н − s(t). Its (17) has "=" where a product belongs. The Jacobian [Bucket, 12] and its
time derivative [Bucket, 18] are correct as printed and used here.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mechatron.machines.bucket import BucketLinkage


def analytic_analysis(lk: BucketLinkage, L1: ArrayLike, rate: ArrayLike = 0.1,
                      acceleration: ArrayLike = 0.0) -> dict[str, NDArray[np.float64]]:
    """The paper's own analysis, vectorized over N samples of the cylinder length L1 (m) at the rate V (m/s) and
    acceleration dV/dt (m/s²): positions from the two loops of [Bucket, 8] in closed form (circle intersections on
    the synthesized branch), velocities from Φ_q q̇ = −Φ_t [Bucket, 12, 15–16] and accelerations from
    Φ_q q̈ = −Φ̇_q q̇ − Φ_tt [Bucket, 17–22], with q = (L1, φ1, φ2, φ3, φ4) (m, rad) and Φ_t = (0, 0, 0, 0, −V)ᵀ,
    Φ_tt = (0, 0, 0, 0, −dV/dt)ᵀ (the printed Φ_t and Φ_tt have four rows; the fifth is the driving constraint).

    Returns arrays of q, q̇ and q̈ (N × 5; m, rad, per s and s²) and the tooth tip K with its velocity and
    acceleration (N × 2; m, m/s, m/s²), under the keys q, qd, qdd, K, K_velocity, K_acceleration.
    """
    L1 = np.asarray(L1, dtype=float)
    n = L1.size
    rate = np.broadcast_to(np.asarray(rate, dtype=float), (n,))
    acceleration = np.broadcast_to(np.asarray(acceleration, dtype=float), (n,))
    A = np.array([lk.a, lk.b])
    F = np.array([-lk.c, 0.0])
    # loop I: |B − D| = L2, |B − A| = L1 → φ2 on the side of the synthesized start
    d, theta_A = np.hypot(*A), math.atan2(A[1], A[0])
    branch = np.sign(math.remainder(lk.initial[1] - theta_A, 2 * math.pi))
    phi2 = theta_A + branch * np.arccos((lk.L2**2 + d**2 - L1**2) / (2 * lk.L2 * d))
    B = lk.L2 * np.stack([np.cos(phi2), np.sin(phi2)], axis=1)
    phi1 = np.arctan2((B - A)[:, 1], -(B - A)[:, 0])
    # loop II: |E − F| = L5, |E − C| = L4 → φ4 on the side of the synthesized start
    C = lk.L3 * np.stack([np.cos(phi2 + lk.alpha), np.sin(phi2 + lk.alpha)], axis=1)
    FC = C - F
    e, theta_C = np.hypot(FC[:, 0], FC[:, 1]), np.arctan2(FC[:, 1], FC[:, 0])
    start_FC = lk.pins(lk.L1n, lk.initial, lk.phi4n)["C"] - F
    branch = np.sign(math.remainder(lk.phi4n - math.atan2(start_FC[1], start_FC[0]), 2 * math.pi))
    phi4 = theta_C + branch * np.arccos((lk.L5**2 + e**2 - lk.L4**2) / (2 * lk.L5 * e))
    E = F + lk.L5 * np.stack([np.cos(phi4), np.sin(phi4)], axis=1)
    phi3 = np.arctan2((C - E)[:, 1], (C - E)[:, 0])
    q = np.stack([L1, phi1, phi2, phi3, phi4], axis=1)

    s1, c1, s2, c2 = np.sin(phi1), np.cos(phi1), np.sin(phi2), np.cos(phi2)
    s2a, c2a, s3, c3, s4, c4 = (np.sin(phi2 + lk.alpha), np.cos(phi2 + lk.alpha), np.sin(phi3), np.cos(phi3),
                                np.sin(phi4), np.cos(phi4))
    zero, one = np.zeros(n), np.ones(n)
    Phi_q = np.stack([  # [Bucket, 12]
        np.stack([c1, -L1 * s1, -lk.L2 * s2, zero, zero], axis=1),
        np.stack([-s1, -L1 * c1, lk.L2 * c2, zero, zero], axis=1),
        np.stack([zero, zero, -lk.L3 * s2a, lk.L4 * s3, lk.L5 * s4], axis=1),
        np.stack([zero, zero, -lk.L3 * c2a, lk.L4 * c3, lk.L5 * c4], axis=1),
        np.stack([one, zero, zero, zero, zero], axis=1)], axis=1)
    rhs = np.zeros((n, 5))
    rhs[:, 4] = rate  # −Φ_t
    qd = np.linalg.solve(Phi_q, rhs[..., None])[..., 0]
    L1d, w1, w2, w3, w4 = qd.T
    gamma = np.stack([  # −Φ̇_q q̇ − Φ_tt ([Bucket, 18] multiplied out)
        2 * L1d * w1 * s1 + L1 * c1 * w1**2 + lk.L2 * c2 * w2**2,
        2 * L1d * w1 * c1 - L1 * s1 * w1**2 + lk.L2 * s2 * w2**2,
        lk.L3 * c2a * w2**2 - lk.L4 * c3 * w3**2 - lk.L5 * c4 * w4**2,
        -lk.L3 * s2a * w2**2 + lk.L4 * s3 * w3**2 + lk.L5 * s4 * w4**2,
        acceleration], axis=1)
    qdd = np.linalg.solve(Phi_q, gamma[..., None])[..., 0]
    angle = phi4 + lk.gamma
    K = F + lk.Lk * np.stack([np.cos(angle), np.sin(angle)], axis=1)
    K_velocity = lk.Lk * w4[:, None] * np.stack([-np.sin(angle), np.cos(angle)], axis=1)
    K_acceleration = (lk.Lk * qdd[:, 4, None] * np.stack([-np.sin(angle), np.cos(angle)], axis=1)
                      - lk.Lk * (w4**2)[:, None] * np.stack([np.cos(angle), np.sin(angle)], axis=1))
    return {"q": q, "qd": qd, "qdd": qdd, "K": K, "K_velocity": K_velocity, "K_acceleration": K_acceleration}
