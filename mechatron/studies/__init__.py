"""Design studies: designs of experiments over a mechanism's named parameters, catalogs and tasks, the analyses a
designer asks for on every design (:mod:`mechatron.studies.analyses`, evaluated by
:class:`~mechatron.studies.evaluator.Evaluator`), run serially or on Dask. The layer above :mod:`mechatron.library`
(it loads mechanisms by name or file) and below :mod:`mechatron.optimal` (optimal design, which shares the
evaluator) and the CLI."""
