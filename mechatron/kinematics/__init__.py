"""Kinematics: frames and points of serial chains ([Egorov, 4.40–4.57]), position, velocity and acceleration
analysis of closed loops, transfer functions ([Egorov, 4.1–4.16]), planar geometry (transmission angles, lever
arms), sweeps over the inputs' strokes, the workspace of two inputs, velocity and acceleration plans ([Egorov,
fig. 4.10]), drawings of mechanisms, and the results of ``mechatron show``, ``fk`` and ``jacobian``.

Every function takes the :class:`~mechatron.model.Mechanism` first, e.g.
``point_velocity(mech, q, v, "H")``; names are imported on first use.
"""

from .._exports import lazy_exports

_EXPORTS = {
    **dict.fromkeys(["frame_placement", "frame_position", "frame_rotation", "frame_jacobian", "fk_and_jacobian",
                     "point_jacobian", "point_velocity", "point_acceleration", "angular_velocity",
                     "angular_acceleration", "link_angular_velocities", "link_angular_accelerations",
                     "reference_frame"], ".frames"),
    **dict.fromkeys(["LoopSolver", "loop_solver", "assemble", "joint_velocity", "joint_acceleration"], ".loops"),
    **dict.fromkeys(["TransferFunctions", "transfer_functions", "point_state", "link_angle"], ".transfer"),
    **dict.fromkeys(["point_positions", "line_angle", "lever_arm", "distance", "transmission_angles", "lever_arms",
                     "distances", "measure_values"], ".geometry"),
    **dict.fromkeys(["SweepResult", "sweep", "default_inputs"], ".sweeps"),
    **dict.fromkeys(["WorkspaceResult", "workspace"], ".workspaces"),
    **dict.fromkeys(["Plans", "plans"], ".vector_plans"),
    **dict.fromkeys(["MechanismSummary", "mechanism_summary", "FramePose", "frame_pose", "JacobianSummary",
                     "jacobian_summary"], ".summary"),
    **dict.fromkeys(["draw_mechanism", "draw_positions", "draw_stick_figure", "draw_plan", "configuration_figure",
                     "key_below"],
                    ".drawing"),
}
__getattr__, __dir__ = lazy_exports(globals(), _EXPORTS)
__all__ = sorted(_EXPORTS)
