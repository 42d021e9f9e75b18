"""mechatron: sizing and analysis of mechatronic modules and mechanisms on top of Pinocchio.

Quick start::

    import mechatron
    puma = mechatron.load("puma560")                  # a Mechanism: puma.model is a pinocchio.Model
    q = puma.neutral()
    print(mechatron.frame_placement(puma, q, "tool"))  # metres

The top level holds the calls most work starts from; everything else is in the layers, each a folder:
:mod:`mechatron.model` (the :class:`Mechanism`, DH, URDF, planar linkages, closures, loads),
:mod:`mechatron.kinematics`, :mod:`mechatron.dynamics`, :mod:`mechatron.drives`, :mod:`mechatron.accuracy`,
:mod:`mechatron.structure`, :mod:`mechatron.mechanics`, :mod:`mechatron.machines`, with :mod:`mechatron.io` and
:mod:`mechatron.report` underneath and :mod:`mechatron.cli` on top. Names are imported on first use, so
``import mechatron`` stays light.
"""

from ._exports import lazy_exports
from .errors import InputError, LimitWarning, MechatronError, MechatronWarning, SingularityError, UnreachableError

__version__ = "0.1.0"

_EXPORTS = {
    "load": ".library", "available_robots": ".library",
    "Mechanism": ".model", "Parameter": ".model", "Load": ".model",
    "frame_placement": ".kinematics.frames", "frame_jacobian": ".kinematics.frames",
    "assemble": ".kinematics.loops", "sweep": ".kinematics.sweeps",
    "inverse_dynamics": ".dynamics.tree", "forward_dynamics": ".dynamics.tree",
    "simulate": ".dynamics.constrained", "move": ".dynamics.motion",
    "size": ".drives.sizing", "tolerance_study": ".accuracy.study", "analyse_structure": ".structure.analysis",
}
__getattr__, __dir__ = lazy_exports(globals(), _EXPORTS)

__all__ = ["InputError", "LimitWarning", "MechatronError", "MechatronWarning", "SingularityError", "UnreachableError",
           "__version__", *_EXPORTS]
