"""The model layer: :class:`Mechanism` (a Pinocchio model with named frames, parameters, drives and closures), how
mechanisms are built (DH tables, URDF, robot files, planar linkages drawn in one position) and the data they carry
(closures, loads, payloads)."""

from .closures import Closure, Gear, OnCurve, Pin, Slider
from .loads import Load, Loads, as_loads
from .mechanism import Cylinder, Measure, Mechanism, Parameter, SketchLine, find_frame, unknown_name_error

__all__ = ["Closure", "Cylinder", "Gear", "Load", "Loads", "Measure", "Mechanism", "OnCurve", "Parameter", "Pin",
           "SketchLine", "Slider", "as_loads", "find_frame", "unknown_name_error"]
