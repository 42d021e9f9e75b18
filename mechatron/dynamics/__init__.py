"""Dynamics: the tree's inverse and forward dynamics (RNEA, ABA, CRBA), energies and joint wrenches; closed loops
through their Lagrange multipliers; motions and trajectories; the one-mass (reduced) model; kinetostatics; tasks;
one integrator on the configuration manifold; exact sensitivities of positions, velocities and actuator forces to the
geometric parameters. Every analysis returns a result of the result protocol
(:class:`~mechatron.report.result.Result`): :class:`Trajectory`, :class:`Simulation`, :class:`Kinetostatics`,
:class:`ReducedModel`, :class:`ReducedMotion`, :class:`MotionRegimes`, :class:`ParameterSensitivities`."""

from typing import TYPE_CHECKING

from .._exports import lazy_exports

if TYPE_CHECKING:  # the lazy names below, for editors and type checkers; at run time each loads on first use
    from .constrained import Actuation as Actuation
    from .constrained import LoadsAt as LoadsAt
    from .constrained import Reactions as Reactions
    from .constrained import Simulation as Simulation
    from .constrained import forward as forward
    from .constrained import inverse as inverse
    from .constrained import project as project
    from .constrained import reactions as reactions
    from .constrained import simulate as simulate
    from .integrate import rk4_step as rk4_step
    from .joint_reactions import JointReactions as JointReactions
    from .joint_reactions import joint_reactions as joint_reactions
    from .kinetostatics import InertiaLoad as InertiaLoad
    from .kinetostatics import Kinetostatics as Kinetostatics
    from .kinetostatics import inertia_loads as inertia_loads
    from .kinetostatics import kinetostatics as kinetostatics
    from .kinetostatics import zhukovsky as zhukovsky
    from .motion import PROFILES as PROFILES
    from .motion import Trajectory as Trajectory
    from .motion import coordinate_limits as coordinate_limits
    from .motion import coordinate_names as coordinate_names
    from .motion import cycle as cycle
    from .motion import make_profile as make_profile
    from .motion import move as move
    from .motion import read_trajectory as read_trajectory
    from .reduced import Cycle as Cycle
    from .reduced import MotionRegimes as MotionRegimes
    from .reduced import ReducedModel as ReducedModel
    from .reduced import ReducedMotion as ReducedMotion
    from .reduced import default_values as default_values
    from .reduced import differential_form as differential_form
    from .reduced import energy_form as energy_form
    from .reduced import motion_regimes as motion_regimes
    from .reduced import reduced_inertia as reduced_inertia
    from .reduced import reduced_inertia_derivative as reduced_inertia_derivative
    from .reduced import reduced_moment as reduced_moment
    from .reduced import reduced_table as reduced_table
    from .reduced import velocity_map as velocity_map
    from .segments import PayloadSchedule as PayloadSchedule
    from .sensitivity import ParameterSensitivities as ParameterSensitivities
    from .sensitivity import parameter_sensitivities as parameter_sensitivities
    from .task import Task as Task
    from .task import default_task as default_task
    from .task import generic_task as generic_task
    from .task import read_task as read_task
    from .trajectory import actuator_forces as actuator_forces
    from .trajectory import closed_loop_states as closed_loop_states
    from .trajectory import holding_forces as holding_forces
    from .tree import bias_forces as bias_forces
    from .tree import external_forces as external_forces
    from .tree import forward_dynamics as forward_dynamics
    from .tree import generalized_forces as generalized_forces
    from .tree import gravity_torques as gravity_torques
    from .tree import inverse_dynamics as inverse_dynamics
    from .tree import joint_wrenches as joint_wrenches
    from .tree import kinetic_energy as kinetic_energy
    from .tree import mass_matrix as mass_matrix
    from .tree import mechanical_energy as mechanical_energy
    from .tree import potential_energy as potential_energy

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
