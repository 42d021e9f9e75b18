"""mechatron: sizing and analysis of mechatronic modules and mechanisms on top of Pinocchio.

Quick start::

    import mechatron
    puma = mechatron.load("puma560")                 # a Mechanism: puma.model is a pinocchio.Model
    q = puma.neutral()
    print(mechatron.frame_position(puma, q, "tool"))  # metres
"""

from .dh import DHLink, DHTable, Drive, Inertial, dh_mechanism
from .dynamics import (
    bias_forces,
    forward_dynamics,
    gravity_torques,
    inverse_dynamics,
    joint_wrenches,
    kinetic_energy,
    mass_matrix,
    mechanical_energy,
    motor_loads,
    potential_energy,
)
from .errors import InputError, MechatronError, SingularityError, UnreachableError
from .kinematics import (
    angular_acceleration,
    angular_velocity,
    fk_and_jacobian,
    frame_jacobian,
    frame_placement,
    frame_position,
    frame_rotation,
    link_angular_accelerations,
    link_angular_velocities,
    point_acceleration,
    point_jacobian,
    point_velocity,
)
from .library import available_robots, load
from .model import Mechanism, Parameter
from .reduced import reduced_inertia, reduced_inertia_derivative, reduced_moment
from .urdf import export_urdf, load_urdf

__version__ = "0.1.0"

__all__ = [
    "DHLink", "DHTable", "Drive", "Inertial", "InputError", "Mechanism", "MechatronError", "Parameter",
    "SingularityError", "UnreachableError", "angular_acceleration", "angular_velocity", "available_robots",
    "dh_mechanism", "export_urdf", "fk_and_jacobian", "frame_jacobian", "frame_placement", "frame_position",
    "frame_rotation", "link_angular_accelerations", "link_angular_velocities", "load", "load_urdf",
    "point_acceleration", "point_jacobian", "point_velocity", "bias_forces", "forward_dynamics", "gravity_torques",
    "inverse_dynamics", "joint_wrenches", "kinetic_energy", "mass_matrix", "mechanical_energy", "motor_loads", "potential_energy",
    "reduced_inertia", "reduced_inertia_derivative", "reduced_moment",
]
