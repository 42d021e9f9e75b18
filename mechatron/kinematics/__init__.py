"""Kinematics: frames and points of serial chains ([Egorov, 4.40–4.57]), position, velocity and acceleration
analysis of closed loops, transfer functions, planar geometry (transmission angles, lever arms), sweeps over the
inputs' strokes and drawings of mechanisms."""

from .._exports import lazy_exports

_EXPORTS = {
    **dict.fromkeys(["frame_placement", "frame_position", "frame_rotation", "frame_jacobian", "fk_and_jacobian",
                     "point_jacobian", "point_velocity", "point_acceleration", "angular_velocity",
                     "angular_acceleration", "link_angular_velocities", "link_angular_accelerations"], ".frames"),
    **dict.fromkeys(["LoopSolver", "loop_solver", "assemble", "joint_velocity", "joint_acceleration"], ".loops"),
    **dict.fromkeys(["TransferFunctions", "transfer_functions", "point_state", "link_angle"], ".transfer"),
    **dict.fromkeys(["point_positions", "line_angle", "lever_arm", "distance", "transmission_angles", "lever_arms",
                     "measure_values"], ".geometry"),
    **dict.fromkeys(["SweepResult", "sweep", "default_inputs"], ".sweep"),
}
__getattr__, __dir__ = lazy_exports(globals(), _EXPORTS)
__all__ = sorted(_EXPORTS)
