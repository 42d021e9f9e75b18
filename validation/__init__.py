"""Validation material: the sources' own formulations and the comparisons with their printed numbers, run by the
test suite and never installed with the package (the package holds no test oracle)."""
