"""Optimal design: a layer above :mod:`mechatron.studies` (whose evaluation of a design it shares:
:class:`~mechatron.studies.evaluator.Evaluator`) and below the command line.

- :mod:`~mechatron.optimal.problem`: the one problem type, :class:`~mechatron.optimal.problem.Problem` (variables,
  objectives, requirements, start, solver settings and a model: a design file's study analyses or a named problem's
  exact CasADi model);
- :mod:`~mechatron.optimal.reader`: the one reader, :func:`read_problem`, of both forms of ``mechatron optimize``'s
  files — a design file (:mod:`~mechatron.optimal.design_file`, docs/design_file.md) or a named problem's spec
  (:mod:`~mechatron.optimal.problems.named`, docs/optimize_file.md);
- :mod:`~mechatron.optimal.solve`: the one entry point, :func:`optimize`;
- a design file's methods: :mod:`~mechatron.optimal.exact` (ipopt on exact derivatives),
  :mod:`~mechatron.optimal.search` (differential evolution, NSGA-II), ``auto`` choosing between them; its
  evaluations (:mod:`~mechatron.optimal.evaluations`) and written designs (:mod:`~mechatron.optimal.write`);
- :mod:`~mechatron.optimal.problems`: the named problems (the bucket, the front shovel, its catalog cylinders' mass,
  a DH arm's positioning error), each a :class:`~mechatron.optimal.problems.base.CasadiModel`;
- :mod:`~mechatron.optimal.result`: the one result type, :class:`~mechatron.optimal.result.OptimalResult`;
- :mod:`~mechatron.optimal.requirement`: a requirement at a design, shared by both.
"""

from __future__ import annotations

from .problem import Problem
from .reader import read_problem
from .requirement import Requirement
from .result import OptimalResult
from .solve import optimize, optimize_design

__all__ = ["OptimalResult", "Problem", "Requirement", "optimize", "optimize_design", "read_problem"]
