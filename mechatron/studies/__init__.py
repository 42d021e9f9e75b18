"""Design studies: designs of experiments over a mechanism's named parameters, catalogs and tasks, the analyses a
designer asks for on every design (:mod:`mechatron.studies.analyses`), run serially or on Dask, and optimal design
with CasADi. The layer above :mod:`mechatron.library` (it loads mechanisms by name or file) and below the CLI."""
