"""Kinematics: frames and points of serial chains ([Egorov, 4.40–4.57]), position, velocity and acceleration
analysis of closed loops, transfer functions ([Egorov, 4.1–4.16]), planar geometry (transmission angles, lever
arms), sweeps over the inputs' strokes, the workspace of two inputs, velocity and acceleration plans ([Egorov,
fig. 4.10]), drawings of mechanisms, and the results of ``mechatron show``, ``fk`` and ``jacobian``.

Every function takes the :class:`~mechatron.model.Mechanism` first, e.g.
``point_velocity(mech, q, v, "H")``; names are imported on first use.
"""

from typing import TYPE_CHECKING

from .._exports import lazy_exports

if TYPE_CHECKING:  # the lazy names below, for editors and type checkers; at run time each loads on first use
    from .drawing import configuration_figure as configuration_figure
    from .drawing import draw_mechanism as draw_mechanism
    from .drawing import draw_plan as draw_plan
    from .drawing import draw_positions as draw_positions
    from .drawing import draw_stick_figure as draw_stick_figure
    from .drawing import key_below as key_below
    from .frames import angular_acceleration as angular_acceleration
    from .frames import angular_velocity as angular_velocity
    from .frames import fk_and_jacobian as fk_and_jacobian
    from .frames import frame_jacobian as frame_jacobian
    from .frames import frame_placement as frame_placement
    from .frames import frame_position as frame_position
    from .frames import frame_rotation as frame_rotation
    from .frames import link_angular_accelerations as link_angular_accelerations
    from .frames import link_angular_velocities as link_angular_velocities
    from .frames import point_acceleration as point_acceleration
    from .frames import point_jacobian as point_jacobian
    from .frames import point_velocity as point_velocity
    from .frames import reference_frame as reference_frame
    from .geometry import distance as distance
    from .geometry import distances as distances
    from .geometry import lever_arm as lever_arm
    from .geometry import lever_arms as lever_arms
    from .geometry import line_angle as line_angle
    from .geometry import measure_values as measure_values
    from .geometry import point_positions as point_positions
    from .geometry import transmission_angles as transmission_angles
    from .loops import LoopSolver as LoopSolver
    from .loops import assemble as assemble
    from .loops import joint_acceleration as joint_acceleration
    from .loops import joint_velocity as joint_velocity
    from .loops import loop_solver as loop_solver
    from .summary import FramePose as FramePose
    from .summary import JacobianSummary as JacobianSummary
    from .summary import MechanismSummary as MechanismSummary
    from .summary import frame_pose as frame_pose
    from .summary import jacobian_summary as jacobian_summary
    from .summary import mechanism_summary as mechanism_summary
    from .sweeps import SweepResult as SweepResult
    from .sweeps import default_inputs as default_inputs
    from .sweeps import sweep as sweep
    from .transfer import TransferFunctions as TransferFunctions
    from .transfer import link_angle as link_angle
    from .transfer import point_state as point_state
    from .transfer import transfer_functions as transfer_functions
    from .vector_plans import Plans as Plans
    from .vector_plans import plans as plans
    from .workspaces import WorkspaceResult as WorkspaceResult
    from .workspaces import workspace as workspace

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
