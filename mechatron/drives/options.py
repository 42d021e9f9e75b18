r"""The options of a drive sizing as one value: :class:`SizingOptions`, every default written once here and every
option checked once, when the value is made.

:func:`mechatron.drives.sizing.size` and :func:`mechatron.drives.system.size_mechanism` take it as ``options``, or
its fields as keywords (the keywords' defaults are the constants below); ``mechatron size`` and a study's
``[analyses.sizing]`` build one from their options. The defaults are ours (the project's), not a standard's.
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields
from typing import Any

from ..errors import InputError
from ..io.values import number
from ..units import UNITS
from .derating import check_altitude
from .limits import DriveLimits
from .screws import SCREW_LIFE
from .thermal import AMBIENT_DEGC as AMBIENT_DEGC  # re-exported: the default of --ambient
from .thermal import ZERO_CELSIUS

#: The objectives a sizing ranks the feasible drives by (:mod:`mechatron.drives.sizing`).
OBJECTIVES = ("mass", "cost", "margin", "time")
#: The default objective.
OBJECTIVE = "mass"
#: The default largest load-to-motor inertia ratio (J_L/u² + J_c)/J_m (our default, a common rule of thumb).
INERTIA_RATIO_MAX = 10.0
#: The default relief pressure of the hydraulic system (Pa): 32 MPa (our default).
PRESSURE = 32e6
#: Pa per MPa: the pressure of ``mechatron size --pressure-mpa`` and of a study's ``pressure_MPa``.
MPA = UNITS["pressure"]["MPa"]
#: The most pressure a sizing accepts (Pa).
PRESSURE_MAX = 1e10
#: The default efficiency of the rest of the chain (couplings, bearings, belts): none lost.
CHAIN_EFFICIENCY = 1.0
#: The lowest efficiency of the rest of the chain (``chain_efficiency``): below it the drives' currents overflow.
MIN_EFFICIENCY = 0.01
#: The most sizing passes of the fixed point before it reports that it did not converge (the default).
MAX_ITERATIONS = 10
#: The fewest passes a sizing may be allowed (``max_iterations``): one weightless pass and one to confirm it.
MIN_PASSES = 2
#: The most passes a sizing may be allowed (``max_iterations``).
MAX_PASSES = 1000


def check_objective(objective: Any) -> str:
    """``objective``, one of :data:`OBJECTIVES`, else an :class:`~mechatron.errors.InputError` naming it."""
    if not isinstance(objective, str) or objective not in OBJECTIVES:
        raise InputError(f"unknown objective {objective!r}; expected one of: {', '.join(OBJECTIVES)}")
    return objective


def check_inertia_ratio(value: Any) -> float:
    """``value``, the largest load-to-motor inertia ratio: a finite number > 0."""
    return number("inertia_ratio_max (the largest load-to-motor inertia ratio)", value, positive=True)


@dataclass(frozen=True)
class SizingOptions:
    """How a mechanism's drives are sized (:func:`mechatron.drives.sizing.size`), checked when made: a bad field
    is one :class:`~mechatron.errors.InputError` naming it.

    Attributes:
        objective: ``"mass"``, ``"cost"``, ``"margin"`` or ``"time"`` (:data:`OBJECTIVES`): what ranks the
            feasible drives.
        limits: The emergency-stop torque or current limit, the required screw life, the supply voltage and the
            ambient temperature (:class:`~mechatron.drives.limits.DriveLimits`; default: the motors' peak torque,
            20 000 h, the catalog's voltage, 40 °C).
        inertia_ratio_max: The largest load-to-motor inertia ratio (J_L/u² + J_c)/J_m allowed (> 0; default
            :data:`INERTIA_RATIO_MAX`).
        pressure: The hydraulic system's relief pressure (Pa; > 0; default :data:`PRESSURE`, 32 MPa).
        chain_efficiency: The efficiency of the rest of the chain, η = Π η_i [Egorov, 7.53]; it multiplies every
            converter's (:data:`MIN_EFFICIENCY` … 1; default 1).
        direct: Whether gearless (direct-drive) motors are tried on revolute joints.
        single_pass: Size each coordinate once with weightless drives instead of to the fixed point.
        max_iterations: The most passes of the fixed point (a whole number :data:`MIN_PASSES` …
            :data:`MAX_PASSES`; default :data:`MAX_ITERATIONS`).
    """

    objective: str = OBJECTIVE
    limits: DriveLimits = field(default_factory=DriveLimits)
    inertia_ratio_max: float = INERTIA_RATIO_MAX
    pressure: float = PRESSURE
    chain_efficiency: float = CHAIN_EFFICIENCY
    direct: bool = True
    single_pass: bool = False
    max_iterations: int = MAX_ITERATIONS
    #: The site's altitude (m; :data:`~mechatron.drives.derating.ALTITUDE_RANGE`): the S1 derating
    #: (:mod:`~mechatron.drives.derating`) with the ambient of ``limits``.
    altitude: float = 0.0

    def __post_init__(self) -> None:
        if isinstance(self.max_iterations, float):  # a count, not a measure: 3.0 is refused as 2.5 is
            raise InputError(f"max_iterations must be a whole number >= {MIN_PASSES} and <= {MAX_PASSES}, got "
                             f"{self.max_iterations!r}")
        checked = {
            "max_iterations": number("max_iterations", self.max_iterations, integer=True, minimum=MIN_PASSES,
                                     maximum=MAX_PASSES),
            "inertia_ratio_max": check_inertia_ratio(self.inertia_ratio_max),
            "pressure": number("pressure", self.pressure, positive=True, maximum=PRESSURE_MAX, unit="Pa"),
            "chain_efficiency": number("chain_efficiency", self.chain_efficiency, minimum=MIN_EFFICIENCY,
                                       maximum=1.0),
            "objective": check_objective(self.objective), "altitude": check_altitude(self.altitude)}
        for name in ("direct", "single_pass"):
            if not isinstance(getattr(self, name), bool):
                raise InputError(f"{name} must be true or false, got {getattr(self, name)!r}")
        if not isinstance(self.limits, DriveLimits):
            raise InputError(f"limits must be a DriveLimits, got {self.limits!r}")
        for name, value in checked.items():
            if type(value) is not type(getattr(self, name)):  # a NumPy number or a numeric text: as a Python one
                object.__setattr__(self, name, value)

    def keywords(self) -> dict[str, Any]:
        """The options as the keywords of :func:`~mechatron.drives.sizing.size` (field → value)."""
        return {f.name: getattr(self, f.name) for f in fields(self)}

    @classmethod
    def in_user_units(cls, *, stop_torque: float | None = None, stop_current: float | None = None,
                      voltage: float | None = None, screw_life_h: float | None = None, ambient_degC: float,
                      pressure_MPa: float = PRESSURE / MPA, brake_factor: float | None = None,
                      brake_stops_per_h: float | None = None, **fields: Any) -> SizingOptions:
        """The options as ``mechatron size`` and a study's ``[analyses.sizing]`` give them: the pressure in MPa,
        the limits (:class:`~mechatron.drives.limits.DriveLimits`) as the stop torque (N·m) or current (A), the
        supply voltage (V), the screw life in hours (``None``: the default 20 000 h) and the ambient in °C
        (T = θ + 273.15 K), the holding brakes' factor and emergency stops per hour (``None``: the defaults of
        :mod:`~mechatron.drives.brakes`); ``fields``: the other fields, in SI."""
        limits = DriveLimits(stop_torque, stop_current, SCREW_LIFE if screw_life_h is None else
                             screw_life_h * UNITS["time"]["h"], voltage, ambient_degC + ZERO_CELSIUS)
        brakes = {k: v for k, v in (("brake_factor", brake_factor), ("brake_stops_per_hour", brake_stops_per_h))
                  if v is not None}
        if brakes:
            from dataclasses import replace

            limits = replace(limits, **brakes)
        return cls(limits=limits, pressure=pressure_MPa * MPA, **fields)

    @classmethod
    def of(cls, options: SizingOptions | None = None, **keywords: Any) -> SizingOptions:
        """``options``, or (``None``) the options of ``keywords`` — fields of this class, ``limits=None`` for the
        default limits. Given ``options``, every keyword must be left at its default (that of
        :func:`~mechatron.drives.sizing.size`), else an :class:`~mechatron.errors.InputError` naming it: the
        options are given one way, not both."""
        unknown = sorted(set(keywords) - {f.name for f in fields(cls)})
        if unknown:
            raise TypeError(f"SizingOptions has no field {unknown[0]!r}")
        if options is None:
            if keywords.get("limits", 0) is None:
                keywords.pop("limits")
            return cls(**keywords)
        if not isinstance(options, SizingOptions):
            raise InputError(f"options must be a SizingOptions, got {options!r}")
        for name, value in keywords.items():
            if not _is_default(name, value):
                raise InputError(f"give the sizing options as options=SizingOptions(...) or as keywords, not both: "
                                 f"{name}={value!r} was given with options")
        return options


def _is_default(name: str, value: Any) -> bool:
    """Whether ``value`` is the keyword ``name``'s default (``limits``: ``None``)."""
    if name == "limits":
        return value is None
    default = next(f.default for f in fields(SizingOptions) if f.name == name)
    return value is default or (type(value) is type(default) and value == default)
