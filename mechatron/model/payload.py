"""Payloads: a rigid body carried at a frame of a mechanism (a part in a gripper, a tool)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike

from ..errors import InputError
from ..io.values import number
from .dh import inertial_problem
from .mechanism import Mechanism


def with_payload(mech: Mechanism, mass: float, frame: str | None = None, com: ArrayLike = (0.0, 0.0, 0.0),
                 inertia: ArrayLike | None = None) -> Mechanism:
    """A copy of ``mech`` carrying a payload of ``mass`` (kg) rigidly at ``frame`` (a frame name, default the
    mechanism's tool frame ``mech.tool_frame``), its centre ``com`` (m) in that frame and its ``inertia`` (3×3,
    kg·m², about the centre, the frame's axes; default a point mass). The payload becomes part of the body of the
    frame's joint (Pinocchio's ``appendBodyToJoint``), so every dynamics call carries its weight and inertia.

    On a serial arm ``frame`` is any frame (``tool``, ``link3``). On a closed loop every named point is a frame of
    the body that carries it (a pin shared by two bodies is ``P`` on its first body and ``P@body`` on the others),
    and the payload joins that body: ``with_payload(mech, 500, "P")`` is the same mechanism as one whose file gives
    that body the combined mass, centre and inertia.

    The inertia must be a rigid body's: symmetric, zero or positive definite, its principal moments obeying
    I1 + I2 ≥ I3 (:func:`~mechatron.model.dh.inertial_problem`), and not without mass."""
    mass = number("payload mass", mass, minimum=0.0, unit="kg")
    frame = frame or mech.tool_frame
    fid = mech.frame_id(frame)
    model = pin.Model(mech.model)
    placement = model.frames[fid].placement
    centre = np.asarray(com, dtype=float)
    tensor = np.zeros((3, 3)) if inertia is None else np.asarray(inertia, dtype=float)
    if centre.shape != (3,) or tensor.shape != (3, 3) or not (np.all(np.isfinite(centre))
                                                             and np.all(np.isfinite(tensor))):
        raise InputError(f"a payload's com must be 3 finite numbers (m) and its inertia a finite 3×3 matrix (kg·m²), "
                         f"got com {com!r}")
    problem = inertial_problem(float(mass), tensor)
    if problem is None and np.any(tensor) and not mass > 0:
        problem = "an inertia without mass is not a body's"
    if problem:
        raise InputError(f"payload: {problem}", field="inertia")
    body = pin.Inertia(float(mass), centre, tensor)
    model.appendBodyToJoint(model.frames[fid].parentJoint, body, placement)
    return replace(mech, model=model, rebuild=None, derivatives=None)
