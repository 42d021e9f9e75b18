"""Dynamics: the tree's inverse and forward dynamics (RNEA, ABA, CRBA), energies and joint wrenches; closed loops
through their Lagrange multipliers; motions and trajectories; the one-mass (reduced) model; kinetostatics; tasks;
one integrator on the configuration manifold."""

from .._exports import lazy_exports

_EXPORTS = {
    **dict.fromkeys(["inverse_dynamics", "forward_dynamics", "mass_matrix", "bias_forces", "gravity_torques",
                     "kinetic_energy", "potential_energy", "mechanical_energy", "joint_wrenches", "external_forces",
                     "generalized_forces"], ".tree"),
    **dict.fromkeys(["forward", "inverse", "reactions", "simulate", "project", "Simulation", "Reactions"],
                    ".constrained"),
    **dict.fromkeys(["closed_loop_states", "actuator_forces", "holding_forces"], ".trajectory"),
    **dict.fromkeys(["Trajectory", "move", "cycle", "make_profile", "read_trajectory", "PROFILES"], ".motion"),
    **dict.fromkeys(["reduced_inertia", "reduced_inertia_derivative", "reduced_moment", "reduced_table",
                     "differential_form", "energy_form", "motion_regimes"], ".reduced"),
    **dict.fromkeys(["kinetostatics", "inertia_loads", "zhukovsky"], ".kinetostatics"),
    **dict.fromkeys(["Task", "read_task", "default_task", "generic_task"], ".task"),
    "rk4_step": ".integrate",
}
__getattr__, __dir__ = lazy_exports(globals(), _EXPORTS)
__all__ = sorted(_EXPORTS)
