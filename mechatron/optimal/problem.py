"""The one problem type of :mod:`mechatron.optimal` (:class:`Problem`): variables, objectives, requirements and a
pluggable model that evaluates a design — a design file's study analyses (:class:`Analyses`, read by
:mod:`~mechatron.optimal.design_file`) or a named problem's exact CasADi model
(:class:`~mechatron.optimal.problems.base.CasadiModel`, read by :mod:`~mechatron.optimal.problems.named`)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from ..studies.evaluator import Evaluator
from ..studies.ranges import Range

if TYPE_CHECKING:  # pragma: no cover
    from .problems.base import CasadiModel


@dataclass(frozen=True)
class Bound:
    """A requirement on an output: ``low`` ≤ value ≤ ``high`` (either may be None)."""

    name: str
    low: float | None = None
    high: float | None = None


@dataclass(frozen=True)
class Analyses:
    """The model of a design file: the study analyses with their options (``[analyses.NAME]``,
    docs/study_analyses.md), evaluated on the mechanism rebuilt with each design's parameters
    (:class:`~mechatron.studies.evaluator.Evaluator`); their outputs and every file the evaluations read."""

    analyses: dict[str, dict[str, Any]]
    outputs: tuple[str, ...] = ()
    files: tuple[str, ...] = ()


@dataclass(frozen=True)
class Problem:
    """An optimal-design problem, checked, of either form of its file: the mechanism (its name or absolute file), the
    variables (:class:`~mechatron.studies.ranges.Range`: a mechanism parameter's range, a list of values, or an
    analysis option's), the objectives (output, goal), the requirements (:class:`Bound` s on outputs), the start
    (SI), the solver's settings and the ``model`` that evaluates a design:

    - a design file's, :class:`Analyses` (the study analyses, any mechanism; solved by
      :func:`~mechatron.optimal.solve.optimize_design`: ``method`` auto, ipopt, global or nsga2 within
      ``evaluations`` designs, ``population`` a generation);
    - a named problem's, an exact CasADi model of its loop equations
      (:class:`~mechatron.optimal.problems.base.CasadiModel`, whose ``judge`` states its requirements;
      solved by :func:`~mechatron.optimal.problems.named.optimize_named`: ``method`` ipopt or sqpmethod, compared
      with a DOE of ``doe_points`` ``doe_method`` points)."""

    file: str
    name: str
    mechanism: str
    variables: tuple[Range, ...]
    objectives: tuple[tuple[str, str], ...]
    model: Analyses | CasadiModel
    requirements: tuple[Bound, ...] = ()
    start: dict[str, float] = field(default_factory=dict)
    method: str = "auto"
    evaluations: int = 400
    population: int = 16
    seed: int = 0
    max_iterations: int = 100
    tolerance: float = 1e-8
    doe_points: int = 256
    doe_method: str = "sobol"

    @property
    def exact_model(self) -> CasadiModel | None:
        """The exact CasADi model of a named problem (None for a design file's analyses)."""
        return None if isinstance(self.model, Analyses) else self.model

    @property
    def analyses(self) -> dict[str, dict[str, Any]]:
        """The study analyses with their options (none for an exact model)."""
        return self.model.analyses if isinstance(self.model, Analyses) else {}

    @property
    def outputs(self) -> tuple[str, ...]:
        """The outputs of the analyses (of an exact model: its quantities)."""
        return self.model.outputs if isinstance(self.model, Analyses) else tuple(self.model.quantity_names)

    @property
    def files(self) -> tuple[str, ...]:
        """Every file the analyses read (none for an exact model: its reader read them)."""
        return self.model.files if isinstance(self.model, Analyses) else ()

    @property
    def evaluator(self) -> Evaluator:
        """The evaluation of a design through the analyses (:class:`~mechatron.studies.evaluator.Evaluator`: the
        study's own)."""
        return Evaluator(self.mechanism, self.analyses, self.variables)

    def options(self, name: str, design: dict[str, Any]) -> dict[str, Any]:
        """The options of analysis ``name`` for one design (:meth:`Evaluator.options`)."""
        return self.evaluator.options(name, design)
