"""A named geometric parameter of a mechanism (:class:`Parameter`): a low module of its own, so that the data a
:class:`~mechatron.model.mechanism.Mechanism` holds (:mod:`mechatron.model.dh_table`) needs no import of it."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

ParameterKind = Literal["length", "angle", "ratio"]


@dataclass(frozen=True)
class Parameter:
    """A named geometric parameter of a mechanism.

    Attributes:
        name: Name used in overrides (``load("puma560", a2=0.45)``) and tolerance files.
        value: Nominal value in SI units (m for lengths, rad for angles).
        kind: ``"length"``, ``"angle"`` or ``"ratio"`` (dimensionless).
        description: What the parameter is, e.g. "DH a of link 2 (common normal z1-z2)".
    """

    name: str
    value: float
    kind: ParameterKind
    description: str = ""

    @property
    def unit(self) -> str:
        return {"length": "m", "angle": "rad"}.get(self.kind, "-")
