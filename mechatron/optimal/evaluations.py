"""The designs of a design problem evaluated through the study's analyses (:class:`~mechatron.studies.evaluator.
Evaluator`), each once, a batch at a time, in this process or on a Dask client's workers; each row judged: its
objectives as minimised, its requirements and their margins, whether it is feasible."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from ..quantities import unit_of
from .problem import Problem
from .requirement import Requirement

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd

#: The value standing for a requirement's margin where a design fails (cannot be assembled, an analysis refuses).
FAILED_MARGIN = -1e12


class Evaluations:
    """Designs evaluated through the study's analyses, each once (kept by its variables' values), a batch at a time:
    in this process, or on a Dask client's workers (warmed once: the mechanism and the analyses' files loaded)."""

    def __init__(self, spec: Problem, client: Any = None, progress: Any = None):
        from ..studies.pace import Pace

        self.spec, self.client, self.progress = spec, client, progress
        self.names = [p.name for p in spec.variables]
        self.rows: dict[tuple, dict[str, Any]] = {}
        self.pace = Pace(spec.evaluations, progress)
        self._warm = False

    def design(self, u: np.ndarray) -> dict[str, Any]:
        """The design at the point ``u`` of the unit cube (:meth:`~mechatron.studies.spec.Range.pick`)."""
        return {p.name: p.pick(float(min(max(x, 0.0), 1.0))) for p, x in zip(self.spec.variables, u)}

    def unit(self, design: dict[str, Any]) -> np.ndarray:
        """The point of the unit cube of a design (a value's index k → (k + ½)/n)."""
        out = []
        for p in self.spec.variables:
            value = design[p.name]
            if p.values is None:
                low, high = p.bounds
                out.append((value - low) / (high - low))
            else:
                out.append((p.values.index(value) + 0.5) / len(p.values))
        return np.array(out)

    def __call__(self, designs: list[dict[str, Any]]) -> list[dict[str, Any]]:
        """The rows (``status``, ``reason``, the outputs) of the designs, evaluating those not seen before."""
        keys = [tuple(d[n] for n in self.names) for d in designs]
        missing = list(dict.fromkeys(k for k in keys if k not in self.rows))
        if missing:
            rows, seconds = self._evaluate(missing)
            for key, row in zip(missing, rows):
                self.rows[key] = row
            self.pace.add([r["design"] for r in rows], seconds, [r["status"] for r in rows],
                          [r["reason"] for r in rows])
        return [self.rows[k] for k in keys]

    def _evaluate(self, keys: list[tuple]) -> tuple[list[dict[str, Any]], list[float]]:
        """The rows of the designs ``keys`` (their variables' values) and their times (s)."""
        from ..studies.designs import design_seed

        first = len(self.rows)
        designs = [{"design": first + i, **dict(zip(self.names, k)), "seed": design_seed(self.spec.seed, first + i)}
                   for i, k in enumerate(keys)]
        evaluator = self.spec.evaluator
        if self.client is None:
            return evaluator.timed(designs)
        from ..studies.cluster import slots
        from ..studies.runner import _warm_worker

        if not self._warm:
            self.client.run(_warm_worker, evaluator, wait=False)
            self._warm = True
        size = max(1, math.ceil(len(designs) / (2 * slots(self.client))))
        chunks = [designs[k:k + size] for k in range(0, len(designs), size)]
        parts = self.client.gather(self.client.map(evaluator.timed, chunks, pure=False))
        return [r for rows, _ in parts for r in rows], [s for _, seconds in parts for s in seconds]

    # ---------------------------------------------------------------------------------------- judging a row
    def objectives(self, row: dict[str, Any]) -> np.ndarray:
        """The objectives of a row as minimised (a maximised one negated); inf where the design failed."""
        if row["status"] != "ok":
            return np.full(len(self.spec.objectives), math.inf)
        return np.array([float(row[n]) * (1.0 if goal == "minimize" else -1.0) for n, goal in self.spec.objectives])

    def requirements(self, row: dict[str, Any]) -> list[Requirement]:
        """The requirements at a row: one per bound (``min``, ``max``), with its value and margin."""
        out = []
        for b in self.spec.requirements:
            value = float(row[b.name]) if row["status"] == "ok" else math.nan
            for kind, limit in (("min", b.low), ("max", b.high)):
                if limit is not None:
                    out.append(Requirement(b.name, value, float(limit), kind, unit_of(b.name)))
        return out

    def margins(self, row: dict[str, Any]) -> np.ndarray:
        """The requirements' margins (≥ 0 when met), :data:`FAILED_MARGIN` where the design failed."""
        return np.array([r.margin if math.isfinite(r.margin) else FAILED_MARGIN for r in self.requirements(row)])

    def feasible(self, row: dict[str, Any]) -> bool:
        """The design was evaluated and meets every requirement (within
        :data:`~mechatron.optimal.requirement.REQUIREMENT_SLACK`: :meth:`Requirement.met`)."""
        return row["status"] == "ok" and all(r.met() for r in self.requirements(row))

    def table(self) -> pd.DataFrame:
        """Every design evaluated, in order: the variables, ``feasible`` and the rows' columns."""
        import pandas as pd

        rows = [{**row, "feasible": self.feasible(row)} for row in self.rows.values()]
        return pd.DataFrame(rows)
