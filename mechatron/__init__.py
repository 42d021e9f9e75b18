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

from typing import TYPE_CHECKING

from ._exports import lazy_exports
from .errors import InputError, LimitWarning, MechatronError, MechatronWarning, SingularityError, UnreachableError

if TYPE_CHECKING:  # the lazy names below, for editors and type checkers; at run time each loads on first use
    from .accuracy.allocation import allocate_tolerances as allocate_tolerances
    from .accuracy.calibration import calibrate as calibrate
    from .accuracy.study import tolerance_study as tolerance_study
    from .drives.sizing import size as size
    from .dynamics.constrained import simulate as simulate
    from .dynamics.motion import move as move
    from .dynamics.tree import forward_dynamics as forward_dynamics
    from .dynamics.tree import inverse_dynamics as inverse_dynamics
    from .kinematics.frames import frame_jacobian as frame_jacobian
    from .kinematics.frames import frame_placement as frame_placement
    from .kinematics.loops import assemble as assemble
    from .kinematics.sweeps import sweep as sweep
    from .library import available_robots as available_robots
    from .library import load as load
    from .model import Load as Load
    from .model import Mechanism as Mechanism
    from .model import Parameter as Parameter
    from .structure.analysis import analyse_structure as analyse_structure

__version__ = "0.1.0"

_EXPORTS = {
    "load": ".library", "available_robots": ".library",
    "Mechanism": ".model", "Parameter": ".model", "Load": ".model",
    "frame_placement": ".kinematics.frames", "frame_jacobian": ".kinematics.frames",
    "assemble": ".kinematics.loops", "sweep": ".kinematics.sweeps",
    "inverse_dynamics": ".dynamics.tree", "forward_dynamics": ".dynamics.tree",
    "simulate": ".dynamics.constrained", "move": ".dynamics.motion",
    "size": ".drives.sizing", "tolerance_study": ".accuracy.study", "analyse_structure": ".structure.analysis",
    "allocate_tolerances": ".accuracy.allocation", "calibrate": ".accuracy.calibration",
}
__getattr__, __dir__ = lazy_exports(globals(), _EXPORTS)

__all__ = ["InputError", "LimitWarning", "MechatronError", "MechatronWarning", "SingularityError", "UnreachableError",
           "__version__", *_EXPORTS]
