"""Payloads: a rigid body carried at a frame of a mechanism (a part in a gripper, a tool)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import numpy as np
import pinocchio as pin

from ..errors import InputError
from .mechanism import Mechanism


def with_payload(mech: Mechanism, mass: float, frame: str | None = None, com: Sequence[float] = (0, 0, 0),
                 inertia: Sequence[Sequence[float]] | None = None) -> Mechanism:
    """A copy of ``mech`` carrying a payload (kg) rigidly at ``frame`` (default the tool), its centre ``com`` (m)
    in that frame and its inertia (kg·m², about the centre, frame axes; default a point mass)."""
    if not mass >= 0:
        raise InputError(f"payload mass must be >= 0 kg, got {mass:g}")
    frame = frame or mech.tool_frame
    fid = mech.frame_id(frame)
    model = pin.Model(mech.model)
    placement = model.frames[fid].placement
    body = pin.Inertia(float(mass), np.asarray(com, dtype=float),
                       np.zeros((3, 3)) if inertia is None else np.asarray(inertia, dtype=float))
    model.appendBodyToJoint(model.frames[fid].parentJoint, body, placement)
    return replace(mech, model=model, rebuild=None)
