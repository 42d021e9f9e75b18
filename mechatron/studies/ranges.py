"""One varied quantity of a study or a design file: :class:`Range`, a range or a list of values (a leaf, so that
the evaluation, the designs and the study file all import it from below; :mod:`~mechatron.studies.spec`
re-exports it)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class Range:
    """One varied quantity: a range ``low``–``high`` (SI) or a list of ``values`` (numbers or names); ``target``
    ``"ANALYSIS.OPTION"`` sends its value to an analysis' options instead of the mechanism's geometry."""

    name: str
    low: float | None = None
    high: float | None = None
    values: tuple[Any, ...] | None = None
    target: str | None = None

    @property
    def bounds(self) -> tuple[float, float]:
        """(``low``, ``high``) of a range (SI).

        Raises:
            TypeError: for a list of values.
        """
        if self.low is None or self.high is None:
            raise TypeError(f"{self.name} is a list of values, not a range")
        return self.low, self.high

    def pick(self, u: float) -> Any:
        """The value at the fraction ``u`` ∈ [0, 1): ``low + u (high − low)`` on a range, ``values[⌊u k⌋]`` of k
        values (so that every value has the same share of a uniform sample)."""
        if self.values is None:
            return self.low + u * (self.high - self.low)
        return self.values[min(int(u * len(self.values)), len(self.values) - 1)]
