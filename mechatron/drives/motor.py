"""Speed–torque limits of a servo motor from its catalog data (vectorized over motors).

The catalogs give rated torque T_r, peak torque T_p, rated speed n_r and maximum speed n_max. The limits used:

- continuous (S1) zone: T_r up to n_r, then constant power T_r·n_r/n up to n_max;
- intermittent (peak) zone: T_p up to n_r, then falling linearly to T_r·n_r/n_max at n_max (the voltage limit);
- no torque beyond n_max.

Real curves differ in detail from maker to maker; a user's catalog with measured curves would refine this.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray


def continuous_torque(speed: ArrayLike, rated_torque: ArrayLike, rated_speed: ArrayLike,
                      max_speed: ArrayLike) -> NDArray[np.float64]:
    """S1 torque (N·m) available at |speed| (rad/s): T_r up to n_r, T_r n_r / n up to n_max, 0 beyond; torques in
    N·m, speeds in rad/s; arrays broadcast together."""
    n = np.abs(speed)
    out = np.where(n <= rated_speed, rated_torque, rated_torque * rated_speed / np.maximum(n, 1e-300))
    return np.where(n <= max_speed, out, 0.0)


def peak_torque_limit(speed: ArrayLike, peak_torque: ArrayLike, rated_torque: ArrayLike,
                      rated_speed: ArrayLike, max_speed: ArrayLike) -> NDArray[np.float64]:
    """Intermittent torque (N·m) available at |speed| (rad/s): T_p up to n_r, then linear down to T_r n_r / n_max
    at n_max, 0 beyond; torques in N·m, speeds in rad/s; arrays broadcast together."""
    n = np.abs(speed)
    at_max = rated_torque * rated_speed / max_speed
    fraction = np.clip((n - rated_speed) / np.maximum(max_speed - rated_speed, 1e-300), 0.0, 1.0)
    out = peak_torque + (at_max - peak_torque) * fraction
    return np.where(n <= max_speed, out, 0.0)
