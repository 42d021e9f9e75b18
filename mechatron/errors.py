"""Errors raised by mechatron.

Every problem caused by the user's input (a file, a name, a value) raises :class:`InputError`, whose message names the
file, the row and the field, so that the command line can print it as one line and exit with status 2.
"""

from __future__ import annotations

from pathlib import Path


class MechatronError(Exception):
    """Base class of every error mechatron raises on purpose."""


class InputError(MechatronError, ValueError):
    """Bad input: a malformed file, a missing or wrong field, an unknown name, an impossible value.

    Args:
        message: What is wrong, in words a user understands.
        file: The file the value came from, if any.
        row: The row (CSV) or entry (e.g. ``links[2]``) the value came from, if any.
        field: The field (column or key) that holds the wrong value, if any.
    """

    def __init__(
        self,
        message: str,
        *,
        file: str | Path | None = None,
        row: int | str | None = None,
        field: str | None = None,
    ) -> None:
        self.message = message
        self.file = str(file) if file is not None else None
        self.row = row
        self.field = field
        super().__init__(self._format())

    def _format(self) -> str:
        where = []
        if self.file:
            where.append(self.file)
        if self.row is not None:
            where.append(f"row {self.row}" if isinstance(self.row, int) else str(self.row))
        if self.field:
            where.append(f"field '{self.field}'")
        return f"{': '.join(where)}: {self.message}" if where else self.message


class UnreachableError(MechatronError):
    """A requested position or motion cannot be reached by the mechanism.

    Attributes:
        inputs: The actuated coordinates asked for (name → value, m or rad), if known.
        residual: The largest closure residual left (m or rad), if the loops were solved.
        closure: The closure row with that residual (e.g. ``"pin B = B' [0]"``), if known.
    """

    def __init__(self, message: str, *, inputs: dict[str, float] | None = None, residual: float | None = None,
                 closure: str | None = None) -> None:
        self.message = message
        self.inputs = dict(inputs) if inputs is not None else None
        self.residual = residual
        self.closure = closure
        super().__init__(message)


class SingularityError(MechatronError):
    """The mechanism is at (or too close to) a singular configuration for the requested analysis.

    Attributes:
        inputs: The actuated coordinates at the singular position (name → value, m or rad), if known.
        ratio: The largest velocity ratio |J_d⁻¹| found there (the test is against 1e8), if known.
    """

    def __init__(self, message: str, *, inputs: dict[str, float] | None = None, ratio: float | None = None) -> None:
        self.message = message
        self.inputs = dict(inputs) if inputs is not None else None
        self.ratio = ratio
        super().__init__(message)


class MechatronWarning(UserWarning):
    """A warning about the input that does not stop the analysis; the command line prints it as one line
    ``mechatron: warning: …``."""


class LimitWarning(MechatronWarning):
    """A joint coordinate outside its joint limits (the analysis goes on: limits are often conservative)."""
