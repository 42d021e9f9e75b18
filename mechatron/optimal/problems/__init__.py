"""The named problems of ``mechatron optimize`` (docs/optimize_file.md), each a
:class:`~mechatron.optimal.problem.Problem` whose model is a :class:`~mechatron.optimal.problems.base.CasadiModel` —
CasADi SX expressions of the loop equations, solved by :mod:`~mechatron.optimal.problems.nlp` and checked on the
Pinocchio model: :mod:`.bucket`, :mod:`.shovel`, :mod:`.mass`, :mod:`.accuracy`; read and solved by :mod:`.named`,
reported as an :class:`~mechatron.optimal.result.OptimalResult`."""
