"""The result protocol every analysis follows, checked the same way for every result type."""

from __future__ import annotations

import json

import pandas as pd
from matplotlib.figure import Figure

from mechatron.report.result import Result


def check_result(result: Result) -> dict:
    """``result`` follows the protocol: ``to_frame`` is a non-empty DataFrame, ``as_dict`` round-trips through JSON
    without NaN, ``plot`` returns a Figure whose every axes with data has labelled x and y axes (units in
    brackets or parentheses), ``plot(ax=...)`` draws into the given axes, and ``str`` is a non-empty report.
    Returns ``as_dict()`` for further checks."""
    assert isinstance(result, Result)
    frame = result.to_frame()
    assert isinstance(frame, pd.DataFrame) and len(frame.columns) > 0
    data = result.as_dict()
    assert isinstance(data, dict) and data
    assert json.loads(json.dumps(data, allow_nan=False)) == json.loads(result.to_json())
    figure = result.plot()
    assert isinstance(figure, Figure)
    axes = [ax for ax in figure.axes if ax.has_data()]
    assert axes, "the plot draws nothing"
    for ax in axes:
        colour_bar = hasattr(ax, "_colorbar")  # a colour bar labels its one long axis
        for label in [ax.get_ylabel() or ax.get_xlabel()] if colour_bar else (ax.get_xlabel(), ax.get_ylabel()):
            assert label and ("(" in label or "[" in label), f"axis label without a unit: {label!r} " \
                f"(axes {ax.get_title()!r})"
        keyed = [a for a in ax.get_lines() + ax.collections if not a.get_label().startswith("_")]
        if keyed:
            assert ax.get_legend() is not None or figure.legends, \
                f"labelled markers without a key in {ax.get_title()!r}"
    from matplotlib.figure import Figure as NewFigure

    given = NewFigure().add_subplot()
    assert result.plot(ax=given) is given.get_figure()
    text = str(result)
    assert isinstance(text, str) and text.strip()
    return data
