"""Validation material: the sources' own formulations and the comparisons with their printed numbers, run by the
test suite and never installed with the package (the package holds no test oracle).

- :mod:`validation.grab` — the grab paper's 13-unknown formulation [Mikhailov, 6–25] with its own integration;
- :mod:`validation.bucket` — the bucket paper's closed-form analysis [Bucket, 8, 12–22];
- :mod:`validation.excavator` — the front-shovel report's printed numbers against the design [Shovel];
- :mod:`validation.seven_bar` — the seven-link paper's closed forms and its table 2 [ShiLiang, 3–20, table 2].

``python -m validation.excavator`` prints the report comparison.
"""
