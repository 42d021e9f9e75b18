"""Dynamics: the tree's inverse and forward dynamics (RNEA, ABA, CRBA), energies and joint wrenches; closed loops
through their Lagrange multipliers; motions and trajectories; the one-mass (reduced) model; kinetostatics; tasks;
one integrator on the configuration manifold; exact sensitivities of positions, velocities and actuator forces to the
geometric parameters. Every analysis returns a result of the result protocol
(:class:`~mechatron.report.result.Result`): :class:`Trajectory`, :class:`Simulation`, :class:`Kinetostatics`,
:class:`ReducedModel`, :class:`ReducedMotion`, :class:`MotionRegimes`, :class:`ParameterSensitivities`."""

from .._exports import lazy_exports

_EXPORTS = {
    **dict.fromkeys(["inverse_dynamics", "forward_dynamics", "mass_matrix", "bias_forces", "gravity_torques",
                     "kinetic_energy", "potential_energy", "mechanical_energy", "joint_wrenches", "external_forces",
                     "generalized_forces"], ".tree"),
    **dict.fromkeys(["forward", "inverse", "reactions", "simulate", "project", "Simulation", "Reactions",
                     "Actuation", "LoadsAt"], ".constrained"),
    **dict.fromkeys(["closed_loop_states", "actuator_forces", "holding_forces"], ".trajectory"),
    **dict.fromkeys(["Trajectory", "move", "cycle", "make_profile", "read_trajectory", "PROFILES",
                     "coordinate_names", "coordinate_limits"], ".motion"),
    **dict.fromkeys(["reduced_inertia", "reduced_inertia_derivative", "reduced_moment", "reduced_table",
                     "ReducedModel", "ReducedMotion", "MotionRegimes", "Cycle", "default_values",
                     "differential_form", "energy_form", "motion_regimes", "velocity_map"], ".reduced"),
    **dict.fromkeys(["kinetostatics", "Kinetostatics", "InertiaLoad", "inertia_loads", "zhukovsky"],
                    ".kinetostatics"),
    **dict.fromkeys(["Task", "read_task", "default_task", "generic_task"], ".task"),
    **dict.fromkeys(["parameter_sensitivities", "ParameterSensitivities"], ".sensitivity"),
    **dict.fromkeys(["joint_reactions", "JointReactions"], ".joint_reactions"),
    **dict.fromkeys(["PayloadSchedule"], ".segments"),
    "rk4_step": ".integrate",
}
__getattr__, __dir__ = lazy_exports(globals(), _EXPORTS)
__all__ = sorted(_EXPORTS)

# ``kinetostatics`` is both a module and the function it defines: imported here so that the package's name is always
# the function (importing the module would otherwise bind the name to the module).
from .kinetostatics import kinetostatics  # noqa: E402, F401
