"""The one reader of ``mechatron optimize``'s files: :func:`read_problem` parses a file once and reads it in the form
it has, each a :class:`~mechatron.optimal.problem.Problem` — a design file (it has ``[analyses.NAME]`` tables,
docs/design_file.md: the study analyses as its model, :mod:`~mechatron.optimal.design_file`) or a named problem's
spec (``[objective] type = ...``, docs/optimize_file.md: an exact CasADi model, :mod:`~mechatron.optimal.problems.
named`)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..io.schema import FieldReader
from .design_file import design_problem
from .problem import Problem
from .problems.named import named_problem


def is_design_file(data: Any) -> bool:
    """Whether a parsed optimisation file is of the general form (it has ``[analyses.NAME]`` tables), not one of
    the named templates (``[objective] type = ...``, docs/optimize_file.md)."""
    return isinstance(data, dict) and "analyses" in data


@dataclass(frozen=True)
class ProblemFile:
    """An optimisation file parsed once: its path and its TOML data."""

    path: Path
    data: dict[str, Any]

    @property
    def is_design(self) -> bool:
        """The design-file form (:func:`is_design_file`)."""
        return is_design_file(self.data)


def parse_problem(path: str | Path) -> ProblemFile:
    """Parse an optimisation file (TOML; an error naming the file where it is not)."""
    from ..io.toml import read_toml

    return ProblemFile(Path(path), read_toml(Path(path)))


def read_problem(source: ProblemFile | str | Path) -> Problem:
    """Read and check an optimisation file of either form (the module docstring), parsed once.

    Raises:
        InputError: naming the file and the field for a bad file.
    """
    parsed = source if isinstance(source, ProblemFile) else parse_problem(source)
    reader = FieldReader(parsed.data, file=parsed.path)
    if parsed.is_design:
        return design_problem(reader, parsed.path)
    return named_problem(reader, parsed.path)
