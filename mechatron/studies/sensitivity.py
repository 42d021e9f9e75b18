"""Global sensitivity of a study's outputs: first-order and total Sobol indices of every numeric output to every
parameter, with SALib.

The designs of ``[designs] method = "sobol"`` are Saltelli's scheme (:mod:`mechatron.studies.designs`): for N base
points and D parameters, the rows A, then the D rows A_B^(i) (A with column i from B), then B, of each block of
D + 2 designs. SALib's estimators ([Saltelli] for S₁, [Jansen] for S_T, both in ``SALib.analyze.sobol``)
take the outputs in that order: S₁,i = E[f(B)(f(A_B^(i)) − f(A))] / V(Y), S_T,i = E[(f(A) − f(A_B^(i)))²] / (2 V(Y)),
each with a bootstrap confidence interval (95 %). The indices are of the parameters in the unit cube, which a
range maps linearly and a list of values by ⌊u k⌋ (each value an equal share): valid for both.

An output with a failed design among its rows (no value there) or with the same value on every design has no
indices: it is listed in ``skipped`` with the reason.
"""

from __future__ import annotations

import warnings
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd

    from .spec import Spec

#: Columns of a designs table that are not outputs.
FIXED = ("design", "seed", "status", "reason")


def numeric_outputs(spec: Spec, table: pd.DataFrame) -> list[str]:
    """The output columns of ``table`` that hold numbers (not the parameters, flags or text)."""
    import pandas as pd

    parameters = {p.name for p in spec.parameters}
    return [c for c in table.columns if c not in FIXED and c not in parameters
            and pd.api.types.is_numeric_dtype(table[c]) and not pd.api.types.is_bool_dtype(table[c])]


def sobol_indices(spec: Spec, table: pd.DataFrame) -> tuple[pd.DataFrame, dict[str, str]]:
    """(indices, skipped): a table of ``output``, ``parameter``, ``S1``, ``S1_conf``, ``ST``, ``ST_conf`` (the
    half-widths of the 95 % confidence intervals) for every numeric output, and the outputs without indices → why.
    ``table`` is the study's designs table in design order."""
    import pandas as pd
    from SALib.analyze import sobol

    d = len(spec.parameters)
    problem = {"num_vars": d, "names": [p.name for p in spec.parameters], "bounds": [[0.0, 1.0]] * d}
    rows, skipped = [], {}
    for output in numeric_outputs(spec, table):
        y = table[output].to_numpy(dtype=float)
        if not np.all(np.isfinite(y)):
            skipped[output] = f"{int((~np.isfinite(y)).sum())} designs without a value"
            continue
        if np.ptp(y) <= 1e-12 * max(1.0, float(np.abs(y).max())):
            skipped[output] = "the same on every design"
            continue
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = sobol.analyze(problem, y, calc_second_order=False, print_to_console=False, seed=spec.seed)
        for j, name in enumerate(problem["names"]):
            rows.append({"output": output, "parameter": name, "S1": float(result["S1"][j]),
                         "S1_conf": float(result["S1_conf"][j]), "ST": float(result["ST"][j]),
                         "ST_conf": float(result["ST_conf"][j])})
    columns = ["output", "parameter", "S1", "S1_conf", "ST", "ST_conf"]
    return pd.DataFrame(rows, columns=columns), skipped
