"""Global sensitivity of a study's outputs: first-order and total Sobol indices of every numeric output to every
parameter, with SALib, each with its 95 % confidence interval and the warnings a reader needs before ranking them.

The designs of ``[designs] method = "sobol"`` are Saltelli's scheme (:mod:`mechatron.studies.designs`): for N base
points and D parameters, N *blocks* of D + 2 designs, block j being the rows j (D + 2) … j (D + 2) + D + 1: A_j,
then the D rows A_B^(i)_j (A_j with column i from B_j), then B_j. SALib's estimators ([Saltelli] for S₁, [Jansen]
for S_T, both in ``SALib.analyze.sobol``) take the outputs in that order: S₁,i = E[f(B)(f(A_B^(i)) − f(A))] / V(Y),
S_T,i = E[(f(A) − f(A_B^(i)))²] / (2 V(Y)), the means over the blocks, each with a bootstrap confidence interval
(95 %, 100 resamples of the blocks, seeded by the study's seed). The indices are of the parameters in the unit
cube, which a range maps linearly and a list of values by ⌊u k⌋ (each value an equal share): valid for both.

Every term of the estimators lies within one block, so a block is the unit that can be left out: a design without
a value of an output (failed) removes its block from that output's indices, and the others give the same
estimators over fewer blocks (wider intervals, as 1/√blocks). The indices table says how many blocks each output
used (``blocks``).

An output gets no indices (``skipped``, with the reason) when fewer than :data:`MIN_BLOCKS` blocks are left, or
when its spread over the designs is at rounding level (the same on every design, :data:`SAME`) or at the level of
the analyses' numerical error (:data:`NOISE`: then a warning too, since such indices would rank noise). An index
whose interval is wider than itself is not resolved by the samples: its output gets a warning
(:func:`unresolved`).
"""

from __future__ import annotations

import warnings
from typing import TYPE_CHECKING

import numpy as np

from ..quantities import unit_of

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd

    from .spec import StudySpec

#: Columns of a designs table that are not outputs.
FIXED = ("design", "seed", "status", "reason")
#: The columns of the indices table.
COLUMNS = ["output", "parameter", "S1", "S1_conf", "ST", "ST_conf", "blocks", "resolved"]
#: An output whose spread (max − min over the designs) is at most this fraction of its scale is the same on every
#: design: the rounding of the sums and products that compute it (~1e-16 each, 1e-13 over a thousand terms).
SAME = 1e-12
#: An output whose spread is at most this fraction of its scale varies only by the analyses' numerical error, not
#: by the parameters. The closed loops are solved by Newton's method until every closure residual is below 1e-10
#: m or rad (:data:`mechatron.kinematics.loops.TOLERANCE`, before a last polishing step), a drive passes its checks
#: to 1e-9 of its limits (:data:`mechatron.drives.checks.PASS_TOLERANCE`) and Pareto fronts tie outputs within
#: 1e-10 of their scale: an output of a study is good to about 1e-10 of a machine's size, and differences below
#: 1e-9 of the scale (10× that) are noise. The scale is the output's largest magnitude, and at least 1 in the
#: output's unit (SI, or as its name says: mm, deg): the closure tolerance is absolute, so an output near zero (the
#: height of a planar point, ±1e-16 m) is noise at its own magnitude too. A real effect of 1e-9 m on a machine is
#: below what any of its analyses resolves.
NOISE = 1e-9
#: Indices and half-widths below this are zero to a reader ranking parameters (1 % of the output's variance):
#: an index of 1e-16 ± 4e-16 (a parameter the output does not depend on) is resolved, not a warning.
RESOLUTION = 0.01
#: The fewest Saltelli blocks that give indices (a bootstrap of one block has no spread).
MIN_BLOCKS = 2


def numeric_outputs(spec: StudySpec, table: pd.DataFrame) -> list[str]:
    """The output columns of ``table`` that hold numbers (not the parameters, flags or text)."""
    import pandas as pd

    parameters = {p.name for p in spec.parameters}
    return [c for c in table.columns if c not in FIXED and c not in parameters
            and pd.api.types.is_numeric_dtype(table[c]) and not pd.api.types.is_bool_dtype(table[c])]


def unresolved(index: float, half_width: float) -> bool:
    """Whether an index is not resolved by its 95 % interval: the interval is wider than the index, or the index
    lies outside 0 … 1 by more than the interval (both beyond :data:`RESOLUTION`)."""
    margin = max(half_width, RESOLUTION)
    return half_width > max(abs(index), RESOLUTION) or index < -margin or index > 1 + margin


def saltelli_blocks(spec: StudySpec, table: pd.DataFrame) -> int:
    """N, the number of Saltelli blocks of the designs table (its rows must be designs 0 … N (D + 2) − 1)."""
    from ..errors import InputError

    size = len(spec.parameters) + 2
    designs = table["design"].to_numpy()
    if len(table) % size or not np.array_equal(designs, np.arange(len(table))):
        raise InputError(f"the Sobol indices need the designs 0 … N·{size} − 1 in order (Saltelli's scheme); the "
                         f"table has {len(table)} rows", file=spec.file, field="output.sensitivity")
    return len(table) // size


def spread_note(output: str, y: np.ndarray) -> tuple[str | None, bool]:
    """(why ``output`` gets no indices, whether that is a warning) from its values ``y``: the same on every design
    (:data:`SAME`) or only numerical noise (:data:`NOISE`, a warning); (None, False) if it varies."""
    spread, magnitude = float(np.ptp(y)), float(np.abs(y).max())
    scale = max(1.0, magnitude)
    if spread <= SAME * scale:
        return "the same on every design", False
    if spread <= NOISE * scale:
        unit = unit_of(output)
        unit = "" if unit == "-" else f" {unit}"
        return (f"it varies by only {spread:.2g}{unit} over the designs ({spread / scale:.2g} of its scale "
                f"{scale:.3g}{unit}), the level of the analyses' numerical error (below {NOISE:g}): its indices would "
                "rank noise, not the parameters"), True
    return None, False


def _analyse(spec: StudySpec, y: np.ndarray) -> dict[str, np.ndarray]:
    """SALib's first-order and total indices and their 95 % half-widths of the outputs ``y`` of whole blocks."""
    from SALib.analyze import sobol

    d = len(spec.parameters)
    problem = {"num_vars": d, "names": [p.name for p in spec.parameters], "bounds": [[0.0, 1.0]] * d}
    # SALib seeds its bootstrap only with a truthy seed (seed 0 would draw from NumPy's global state): a
    # SeedSequence of the study's seed is truthy and gives default_rng the same stream as the bare number.
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return sobol.analyze(problem, y, calc_second_order=False, print_to_console=False,
                             seed=np.random.SeedSequence(spec.seed))


def _resolution_warning(output: str, rows: list[dict], blocks: int) -> str | None:
    """The warning of an output whose indices ``rows`` include unresolved ones, or None."""
    bad = []
    for r in rows:
        for kind in ("S1", "ST"):
            index, half = r[kind], r[kind + "_conf"]
            if unresolved(index, half):
                why = "its 95 % interval is wider than the index" if half > max(abs(index), RESOLUTION) else \
                    "outside 0 … 1 by more than its 95 % interval"
                bad.append(f"{kind}({r['parameter']}) = {index:.3g} ± {half:.3g} ({why})")
    if not bad:
        return None
    shown = ", ".join(bad[:3]) + (f" and {len(bad) - 3} more" if len(bad) > 3 else "")
    return (f"{output}: not resolved by {blocks} Saltelli blocks: {shown}; do not rank its parameters by these "
            "indices, take more samples (the intervals narrow as 1/√N)")


def output_indices(spec: StudySpec, output: str, y: np.ndarray) -> tuple[list[dict], str | None, str | None]:
    """(rows of the indices table, why there are none, a warning) of one output whose values ``y`` are in blocks of
    D + 2 rows (N, D + 2); blocks with a value missing are left out."""
    whole = np.all(np.isfinite(y), axis=1)
    used, total = int(whole.sum()), len(y)
    if used < MIN_BLOCKS:
        why = f"a design without a value in {total - used} of the {total} Saltelli blocks ({used} left; indices " \
              f"need {MIN_BLOCKS})"
        return [], why, None
    values = y[whole].ravel()
    why, warn = spread_note(output, values)
    if why is not None:
        return [], why, f"no Sobol indices of {output}: {why}" if warn else None
    result = _analyse(spec, values)
    rows = []
    for j, p in enumerate(spec.parameters):
        row = {"output": output, "parameter": p.name, "S1": float(result["S1"][j]),
               "S1_conf": float(result["S1_conf"][j]), "ST": float(result["ST"][j]),
               "ST_conf": float(result["ST_conf"][j]), "blocks": used}
        row["resolved"] = not (unresolved(row["S1"], row["S1_conf"]) or unresolved(row["ST"], row["ST_conf"]))
        rows.append(row)
    return rows, None, _resolution_warning(output, rows, used)


def sobol_indices(spec: StudySpec, table: pd.DataFrame) -> tuple[pd.DataFrame, dict[str, str], list[str]]:
    """(indices, skipped, warnings) of every numeric output (see the module docstring).

    ``indices``: ``output``, ``parameter``, ``S1``, ``S1_conf``, ``ST``, ``ST_conf`` (the half-widths of the 95 %
    confidence intervals), ``blocks`` (the Saltelli blocks used) and ``resolved`` (both intervals no wider than
    their index, :func:`unresolved`); ``skipped``: the outputs without indices → why; ``warnings``: plain
    sentences, one per output whose indices are not resolved or that varies only by numerical noise. ``table`` is
    the study's designs table in design order."""
    import pandas as pd

    n = saltelli_blocks(spec, table)
    size = len(spec.parameters) + 2
    rows, skipped, notes = [], {}, []
    for output in numeric_outputs(spec, table):
        y = table[output].to_numpy(dtype=float).reshape(n, size)
        found, why, warning = output_indices(spec, output, y)
        rows.extend(found)
        if why is not None:
            skipped[output] = why
        if warning is not None:
            notes.append(warning)
    return pd.DataFrame(rows, columns=COLUMNS), skipped, notes
