"""The analyses a study runs on every design, by name. Each is a module that follows the
:class:`Analysis` protocol:

- ``OUTPUTS``: the names of the outputs it adds, quantities of the registry (:mod:`mechatron.quantities`: their
  units are the registry's, ``mass_kg`` → kg, ``force_N`` → N), for the docs;
- ``check(mech: Mechanism, options: dict) -> None``: raise :class:`~mechatron.errors.InputError` (one line naming
  the spec's ``[analyses.NAME]`` field) when the options are wrong or the mechanism cannot have this analysis, before
  any design runs;
- ``output_names(mech: Mechanism, options: dict) -> list[str]``: the names of the columns ``outputs`` gives for
  these options, without running (the spec's ``[output.pareto]`` axes are checked against them);
- ``input_files(mech: Mechanism, options: dict) -> list[Path]``: every file ``outputs`` reads for these options
  (those named and the defaults: a task, its trajectory CSV, catalogs, tolerances, poses), whose bytes are part of
  a study's identity;
- ``outputs(mech: Mechanism, options: dict, seed: int) -> dict[str, float | bool]``: the outputs of one design (SI
  units, finite numbers); a design that cannot be analysed (does not assemble, no feasible drive, …) raises a
  :class:`~mechatron.errors.MechatronError` whose message becomes the row's reason. ``seed`` seeds any random draw,
  so that a design gives the same row wherever it runs.

An analysis with exact first derivatives (:data:`EXACT`) also follows
:class:`GradientAnalysis` (``gradient_outputs``, ``gradients``):
:func:`gradient_analysis` gives it, None for the others.
"""

from __future__ import annotations

import importlib
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol, cast

from ...errors import InputError

if TYPE_CHECKING:  # pragma: no cover
    import numpy as np

    from ...model.mechanism import Mechanism

class Analysis(Protocol):
    """An analysis of a study (``[analyses.NAME]``): its ``OUTPUTS`` are names of quantities of the registry
    (:mod:`mechatron.quantities`: the unit is the registry's, ``reach_m`` → m; ``CYLINDER`` and ``ACTUATOR`` stand
    for each item's name)."""

    OUTPUTS: tuple[str, ...]

    def check(self, mech: Mechanism, options: dict[str, Any]) -> None:
        """Raise :class:`~mechatron.errors.InputError` (naming the option) for wrong options, before any design."""

    def output_names(self, mech: Mechanism, options: dict[str, Any]) -> list[str]:
        """The names of the outputs :meth:`outputs` gives for these options, without running."""

    def input_files(self, mech: Mechanism, options: dict[str, Any]) -> Sequence[str | Path]:
        """Every file :meth:`outputs` reads for these options (part of a study's identity)."""

    def outputs(self, mech: Mechanism, options: dict[str, Any], seed: int) -> Mapping[str, Any]:
        """The outputs of one design (SI, finite); a :class:`~mechatron.errors.MechatronError` where it fails."""


class GradientAnalysis(Analysis, Protocol):
    """An analysis that also gives exact first derivatives of its outputs (the exact route of ``optimize``)."""

    def gradient_outputs(self, mech: Mechanism, options: dict[str, Any]) -> list[str]:
        """The outputs :meth:`gradients` differentiates for these options, without running."""

    def gradients(self, mech: Mechanism, options: dict[str, Any], parameters: list[str]
                  ) -> tuple[dict[str, float], dict[str, np.ndarray]]:
        """The outputs of one design and the gradient of each with respect to the named geometric parameters."""


#: Analysis name → module (imported when a study asks for it).
MODULES = {
    "linkage": "mechatron.studies.analyses.linkage",
    "dynamics": "mechatron.studies.analyses.dynamics",
    "sizing": "mechatron.studies.analyses.sizing",
    "accuracy": "mechatron.studies.analyses.accuracy",
}

#: The analyses that give exact first derivatives of their outputs (:class:`GradientAnalysis`).
EXACT = ("linkage",)

#: Analysis name → the modules its ``outputs`` imports on first use: the workers of an embedded cluster start with
#: them imported (:func:`worker_modules`), so that no worker's first chunk pays for them.
IMPORTS = {
    "linkage": ("mechatron.kinematics.sweeps", "mechatron.machines.excavator", "mechatron.dynamics.trajectory"),
    "dynamics": ("mechatron.dynamics.motion", "mechatron.dynamics.task", "mechatron.dynamics.tree"),
    "sizing": ("mechatron.drives.sizing", "mechatron.dynamics.task"),
    "accuracy": ("mechatron.accuracy.study", "mechatron.accuracy.sources"),
}


def worker_modules() -> list[str]:
    """The modules a worker of a study imports: the runner, the library (Pinocchio), every analysis and what its
    ``outputs`` uses (:data:`IMPORTS`)."""
    names = ["mechatron.studies.runner", "mechatron.library"]
    for name, module in MODULES.items():
        names += [module, *IMPORTS[name]]
    return list(dict.fromkeys(names))


def analysis(name: str) -> Analysis:
    """The module of the analysis ``name``.

    Raises:
        InputError: for an unknown name (the known ones listed).
    """
    if name not in MODULES:
        raise InputError(f"unknown analysis {name!r}; known: {', '.join(MODULES)}")
    return cast("Analysis", importlib.import_module(MODULES[name]))


def gradient_analysis(name: str) -> GradientAnalysis | None:
    """The analysis ``name`` where it gives exact first derivatives (:data:`EXACT`), else None."""
    module = analysis(name)
    return cast("GradientAnalysis", module) if name in EXACT else None
