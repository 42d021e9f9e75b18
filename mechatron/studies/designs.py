"""The designs of a study: a table with ``design`` (0 … n−1), one column per parameter (SI, or the names of a
categorical parameter) and ``seed``, the design's own seed, so that a design's row is the same wherever it runs.

- ``grid``: the full factorial of ``levels`` evenly spaced values from ``low`` to ``high`` of every range and all
  ``values`` of every list, the last parameter varying fastest;
- ``lhs``: ``samples`` points of a scrambled Latin hypercube (:func:`latin_hypercube`: the points of
  ``scipy.stats.qmc.LatinHypercube(d, rng=np.random.default_rng(seed))``, to the last bit, in a few lines of NumPy
  instead of SciPy's statistics package, whose import alone takes over a second);
- ``sobol``: Saltelli's scheme on scrambled Sobol points (``SALib.sample.sobol``, itself on
  ``scipy.stats.qmc.Sobol``, seeded): ``samples`` = N base points (a power of 2) give N (D + 2) designs for D
  parameters — the matrices A, B and the D matrices A_B^(i) whose Sobol indices
  :mod:`mechatron.studies.sensitivity` estimates;
- ``csv``: the rows of a CSV file whose columns are the mechanism's parameters (SI units).

Every point is drawn in the unit cube and mapped by :meth:`~mechatron.studies.ranges.Range.pick`: a range
linearly, a list of k values by ⌊u k⌋. A design's seed is the first word of ``np.random.SeedSequence([study seed,
design])``.
"""

from __future__ import annotations

import warnings
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np

from ..errors import InputError

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd

    from .ranges import Range


class Plan(Protocol):
    """What the designs are drawn from (a :class:`~mechatron.studies.spec.StudySpec`; a protocol, so that this
    module needs no import of the study file, which imports it): the parameters, the method (``grid``, ``lhs``,
    ``sobol``, ``csv``), the samples or levels, the CSV file and the study's seed."""

    @property
    def parameters(self) -> tuple[Range, ...]: ...

    @property
    def method(self) -> str: ...

    @property
    def samples(self) -> int | None: ...

    @property
    def levels(self) -> int | None: ...

    @property
    def csv(self) -> str | None: ...

    @property
    def seed(self) -> int: ...


def design_seed(study_seed: int, design: int) -> int:
    """The seed of one design (a 32-bit integer) from the study's seed and the design's number."""
    return int(np.random.SeedSequence([study_seed, design]).generate_state(1, np.uint32)[0])


def latin_hypercube(n: int, d: int, seed: int) -> np.ndarray:
    """``n`` points of a scrambled Latin hypercube in ``d`` dimensions, (n, d): each axis cut into ``n`` equal strata
    holds one point in each, placed uniformly within it. The same points, to the last bit, as
    ``scipy.stats.qmc.LatinHypercube(d, scramble=True, rng=np.random.default_rng(seed)).random(n)`` (SciPy 1.15+):
    its generator is the first child of the seed's sequence; it draws the offsets within the strata, then shuffles
    the strata of each axis in turn."""
    child = np.random.SeedSequence(seed).spawn(1)[0]
    rng = np.random.Generator(np.random.PCG64(child))
    offsets = rng.uniform(size=(n, d))
    strata = np.tile(np.arange(1, n + 1), (d, 1))
    for axis in range(d):
        rng.shuffle(strata[axis, :])
    return (strata.T - offsets) / n


def sample_box(lower: np.ndarray, upper: np.ndarray, points: int, method: str = "sobol", seed: int = 0
               ) -> np.ndarray:
    """``points`` designs in the box [lower, upper] (rows): scrambled Sobol points (``points`` a power of two: their
    balance needs it; ``scipy.stats.qmc.Sobol`` seeded with ``seed``) or the Latin hypercube of
    :func:`latin_hypercube` — the DOE of the named optimisation problems (docs/optimize_file.md)."""
    d = len(lower)
    if method == "sobol":
        from scipy.stats import qmc

        if points < 1 or points & (points - 1):
            raise InputError(f"Sobol points need a power of 2 of them (their balance needs it), got {points}")
        unit = qmc.Sobol(d, scramble=True, seed=seed).random_base2(points.bit_length() - 1)
    elif method == "lhs":
        unit = latin_hypercube(points, d, seed)
    else:
        raise InputError(f"unknown DOE method {method!r}; known: sobol, lhs")
    return np.asarray(lower, dtype=float) + unit * (np.asarray(upper, dtype=float) - np.asarray(lower, dtype=float))


def unit_points(spec: Plan) -> np.ndarray:
    """The designs of ``spec`` (grid, lhs or sobol) as points of the unit cube, (n, D)."""
    d = len(spec.parameters)
    if spec.method == "lhs":
        return latin_hypercube(spec.samples, d, spec.seed)
    if spec.method == "sobol":
        from SALib.sample import sobol

        problem = {"num_vars": d, "names": [p.name for p in spec.parameters], "bounds": [[0.0, 1.0]] * d}
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return sobol.sample(problem, spec.samples, calc_second_order=False, scramble=True, seed=spec.seed)
    axes = [np.arange(len(p.values)) / len(p.values) if p.values is not None
            else np.linspace(0.0, 1.0, spec.levels) for p in spec.parameters]
    return np.stack([a.ravel() for a in np.meshgrid(*axes, indexing="ij")], axis=1)


def make_designs(spec: Plan) -> pd.DataFrame:
    """The designs table of ``spec`` (see the module docstring)."""
    import pandas as pd

    if spec.method == "csv":
        table = read_designs_csv(spec.csv)
    else:
        points = unit_points(spec)
        table = pd.DataFrame({p.name: [p.pick(u) for u in points[:, j]] for j, p in enumerate(spec.parameters)})
    table.insert(0, "design", np.arange(len(table)))
    table["seed"] = [design_seed(spec.seed, k) for k in range(len(table))]
    return table


def read_designs_csv(path: str | Path, known: dict[str, Any] | None = None) -> pd.DataFrame:
    """A CSV of designs: a header of parameter names (of the mechanism: ``known``, when given) and one design per
    row, every cell a finite number (SI). Errors name the file, the row (its line number) and the column."""
    import pandas as pd

    from ..io.tables import number, read_csv

    cells = read_csv(path)
    for column in cells.columns:
        if known is not None and column not in known:
            raise InputError(f"unknown parameter {column!r} (known: {', '.join(known)})", file=path, row=1,
                             field=column)
    out = {}
    for column in cells.columns:
        values = []
        for line, text in zip(cells.index, cells[column]):
            if not text:
                raise InputError("missing value", file=path, row=int(line), field=column)
            values.append(number(text, file=path, row=int(line), field=column))
        out[column] = values
    return pd.DataFrame(out)
