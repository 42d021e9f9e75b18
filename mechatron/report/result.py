"""The one result protocol of mechatron.

Every analysis returns a :class:`Result`: ``to_frame()`` (a pandas DataFrame), ``as_dict()`` (plain data, ready for
``json.dumps(..., allow_nan=False)``), ``plot(ax=None)`` (a matplotlib Figure with labelled axes and units) and
``str()`` (the text report the command line prints). The command line's ``--csv``, ``--json``, ``--plot`` and
``--report`` are exactly :meth:`Result.write_csv`, :meth:`Result.to_json`, :meth:`Result.save_plot` and
:meth:`Result.write_html` (whose content is :meth:`Result.report`).
"""

from __future__ import annotations

import dataclasses
import json
import math
from abc import ABC, abstractmethod
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..model.mechanism import Mechanism
    from .html import Report


def json_ready(value: Any) -> Any:
    """``value`` as plain JSON data: numpy scalars and arrays to numbers and lists, NaN and ±inf to ``None``, paths
    to strings, dataclasses and mappings to dicts, tuples and sets to lists."""
    if isinstance(value, Result):
        return json_ready(value.as_dict())
    if isinstance(value, Mapping):
        return {str(k): json_ready(v) for k, v in value.items()}
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {f.name: json_ready(getattr(value, f.name)) for f in dataclasses.fields(value)}
    if isinstance(value, np.ndarray):
        return json_ready(value.tolist())
    if isinstance(value, (list, tuple, set, frozenset)):
        return [json_ready(v) for v in value]
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        x = float(value)
        return x if math.isfinite(x) else None
    if isinstance(value, Path):
        return str(value)
    if value is None or isinstance(value, str):
        return value
    if hasattr(value, "to_dict"):  # pandas objects
        return json_ready(value.to_dict())
    return str(value)


def readable(value: float, digits: int = 4) -> str:
    """A number for people, never in exponent form between 10⁻³ and 10¹⁵: from 10^digits on every integer digit
    with thousands separators (100028.4 → ``100,028``), below it ``digits`` significant digits (1234.56 → ``1235``,
    0.01234 → ``0.01234``); outside that range and for NaN or ±inf, Python's ``g`` format."""
    size = abs(value)
    if not math.isfinite(value) or (size and not 1e-3 <= size < 1e15):
        return f"{value:.{digits}g}"
    if size >= 10**digits:
        return f"{value:,.0f}"
    return f"{value + 0.0:.{digits}g}"  # + 0.0: no "-0"


def frame_records(frame: pd.DataFrame) -> list[dict]:
    """The rows of a DataFrame as JSON-ready dicts."""
    return json_ready(frame.to_dict(orient="records"))


class Result(ABC):
    """Base class of every analysis result (see the module docstring)."""

    @abstractmethod
    def to_frame(self) -> pd.DataFrame:
        """The result as a table (SI units; the columns say what each holds)."""

    @abstractmethod
    def as_dict(self) -> dict:
        """The result as plain data: numbers, strings, lists and dicts, no NaN (JSON-ready)."""

    @abstractmethod
    def plot(self, ax: Axes | None = None) -> Figure:
        """A chart of the result with labelled axes and units, drawn into ``ax`` if given; returns its Figure."""

    @abstractmethod
    def __str__(self) -> str:
        """The text report printed by the command line."""

    # ------------------------------------------------------------------------------------------ file outputs
    def to_json(self, indent: int | None = 2) -> str:
        """:meth:`as_dict` as JSON text (``allow_nan=False``: a NaN would be a bug, not a value)."""
        return json.dumps(json_ready(self.as_dict()), indent=indent, allow_nan=False)

    def write_csv(self, path: str | Path) -> Path:
        """Write :meth:`to_frame` as CSV, whole or not at all."""
        from ..io.output import write_table

        return write_table(self.to_frame(), path)

    def write_json(self, path: str | Path) -> Path:
        """Write :meth:`to_json`, whole or not at all."""
        from ..io.output import write_text

        return write_text(path, self.to_json() + "\n")

    def save_plot(self, path: str | Path) -> Path:
        """Draw :meth:`plot` into a file (.png, .pdf or .svg), whole or not at all."""
        from ..io.output import save_figure

        return save_figure(self.plot(), path)

    # ------------------------------------------------------------------------------------------- the HTML report
    def report(self, mechanism: Mechanism | None = None, **context: Any) -> Report:
        """What the HTML report holds (:mod:`mechatron.report.html`): by default the text report, the table and the
        chart. An analysis overrides it to add its method, its checks and a drawing of the mechanism; ``mechanism``
        (the mechanism analysed) and ``context`` (what else the analysis was given, e.g. ``task``) are for those
        overrides, which ignore what they do not use."""
        from .html import Chart, Code, Report, Section, Table

        text = str(self)
        return Report(text.splitlines()[0] if text else type(self).__name__,
                      [Section("Results", [Code(text), Table(self.to_frame(), "the result's table (SI)", "result")]),
                       Section("Chart", [Chart(self.plot())])])

    def write_html(self, path: str | Path, *, inputs: Mapping[str, Any] | None = None, files: Sequence[str | Path] = (),
                   mechanism: Mechanism | None = None, **context: Any) -> Path:
        """Write the HTML report (:meth:`report` after the ``inputs``, the ``mechanism`` and the input ``files``; the
        references it cites last) as one self-contained file, whole or not at all
        (:func:`mechatron.report.html.write_report`)."""
        from .html import write_report

        return write_report(self, path, inputs=inputs, files=files, mechanism=mechanism, **context)
