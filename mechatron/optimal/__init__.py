"""Optimal design: a layer above :mod:`mechatron.studies` (whose evaluation of a design it shares:
:class:`~mechatron.studies.evaluator.Evaluator`) and below the command line.

- :mod:`~mechatron.optimal.reader`: the one reader, :func:`read_problem`, of both forms of ``mechatron optimize``'s
  files — a design file (:class:`~mechatron.optimal.problem.DesignProblem`, docs/design_file.md) or a named
  problem's spec (:class:`~mechatron.optimal.problems.named.NamedProblem`, docs/optimize_file.md);
- :mod:`~mechatron.optimal.solve`: the one entry point, :func:`optimize`;
- a design problem's methods: :mod:`~mechatron.optimal.exact` (ipopt on exact derivatives),
  :mod:`~mechatron.optimal.search` (differential evolution, NSGA-II), ``auto`` choosing between them; its
  evaluations (:mod:`~mechatron.optimal.evaluations`), result (:mod:`~mechatron.optimal.result`) and written
  designs (:mod:`~mechatron.optimal.write`);
- :mod:`~mechatron.optimal.problems`: the named problems (the bucket, the front shovel, its catalog cylinders' mass,
  a DH arm's positioning error) on :class:`~mechatron.optimal.problems.base.OptimalDesignProblem`;
- :mod:`~mechatron.optimal.requirement`: a requirement at a design, shared by both.
"""

from __future__ import annotations

from .problem import DesignProblem
from .problems.named import NamedProblem
from .reader import read_problem
from .requirement import Requirement
from .result import OptimalResult
from .solve import optimize, optimize_design

__all__ = ["DesignProblem", "NamedProblem", "OptimalResult", "Requirement", "optimize", "optimize_design",
           "read_problem"]
