r"""The ``accuracy`` analysis of a study: the positioning error of a point of one design from the tolerances of
its parameters and joints over a set of poses (:func:`mechatron.accuracy.study.analyse_tolerances`, the study of
``mechatron tolerance``) [Egorov, chapter 8], reduced to a row of numbers.

Options (the spec's ``[analyses.accuracy]`` table, see ``docs/study_analyses.md``): ``tolerances`` (a tolerances
CSV, required), ``limit_mm`` (the largest acceptable |Δr| for the yield, mm, required), ``poses`` (a poses CSV) or
``grid`` (N poses per coordinate, or N random ones, :func:`~mechatron.accuracy.sources.workspace_grid` seeded 0 so
that every design has the same poses; default the mechanism's reference pose), ``frame`` (default the tool),
``samples`` (Monte Carlo samples per pose, 2 … 10⁶, default 10 000), ``quantile`` (default 0.95), ``k`` (the
coverage factor: σ = t/k for normal errors, default 3).

Outputs (mm; each at the pose where it is worst):

- ``worst_case_mm``: max over the poses of |Δr| of the worst case, Δ = |J b| + Σ_i |J_i| t_i per axis, the modulus
  of the axes' values [Egorov, 8.4–8.6];
- ``rss_mm``: the same of the statistical estimate Δ = |J b| + k √Σ_i (J_i σ_i)²;
- ``mc_quantile_mm``: max over the poses of the ``quantile`` of |Δr| of the Monte Carlo of the full nonlinear
  model (closed loops re-assembled for every sample, :class:`~mechatron.accuracy.nonlinear.PerturbedLoops`), over
  the samples whose loops close;
- ``yield``: min over the poses of the fraction of the ``samples`` with |Δr| ≤ ``limit_mm`` (a sample whose loops
  do not close counts as out of the limit).

The Monte Carlo draws from the design's ``seed`` (the same samples at every pose): the same seed gives the same
row. A design whose loops do not close at a pose raises :class:`~mechatron.errors.MechatronError` naming the pose.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ...errors import InputError, MechatronError
from .sizing import field_error, field_file, field_names, field_number

if TYPE_CHECKING:  # pragma: no cover
    from pathlib import Path

    from ...accuracy.sources import ErrorSource
    from ...model.mechanism import Mechanism

OUTPUTS = ("worst_case_mm", "rss_mm", "mc_quantile_mm", "yield")
OPTIONS = ("tolerances", "limit_mm", "poses", "grid", "frame", "samples", "quantile", "k")
#: The most Monte Carlo samples per pose: every |Δr| is kept, so that the quantile is exact.
MOST_SAMPLES = 1_000_000


def settings(mech: Mechanism, options: dict) -> dict:
    """The options checked: tolerances and poses files, frame name, samples, quantile, limit (m), k."""
    field_names("accuracy", options, OPTIONS)
    for field in ("tolerances", "limit_mm"):
        if field not in options:
            raise field_error("accuracy", field, "required")
    if "poses" in options and "grid" in options:
        raise field_error("accuracy", "grid", "give poses or grid, not both")
    frame = options.get("frame", mech.tool_frame)
    if not isinstance(frame, str):
        raise field_error("accuracy", "frame", f"must be a frame name, got {frame!r}")
    try:
        mech.frame_id(frame)
    except InputError as exc:
        raise field_error("accuracy", "frame", str(exc)) from None
    quantile = field_number("accuracy", options, "quantile", 0.95, positive=True)
    if not quantile < 1:
        raise field_error("accuracy", "quantile", f"must be a fraction > 0 and < 1, got {quantile:g}")
    return {"tolerances": field_file("accuracy", options, "tolerances"),
            "poses": field_file("accuracy", options, "poses"),
            "grid": field_number("accuracy", options, "grid", integer=True, minimum=1), "frame": frame,
            "samples": field_number("accuracy", options, "samples", 10000, integer=True, minimum=2,
                                    maximum=MOST_SAMPLES),
            "quantile": quantile, "k": field_number("accuracy", options, "k", 3.0, minimum=0.1, maximum=100.0),
            "limit": field_number("accuracy", options, "limit_mm", positive=True, unit="mm") * 1e-3}


def sources_and_poses(mech: Mechanism, values: dict) -> tuple[list[ErrorSource], np.ndarray, list[str]]:
    """The error sources (SI) of the tolerances file and the poses (rad, m) with their labels, read for ``mech``
    (a tolerance by grade depends on the design's nominal size)."""
    from ...accuracy.sources import read_poses, read_tolerances, reference_pose, workspace_grid

    try:
        sources = read_tolerances(values["tolerances"], mech)
    except InputError as exc:
        raise field_error("accuracy", "tolerances", str(exc)) from None
    if values["poses"] is not None:
        try:
            poses, labels = read_poses(values["poses"], mech)
        except InputError as exc:
            raise field_error("accuracy", "poses", str(exc)) from None
    elif values["grid"] is not None:
        poses = workspace_grid(mech, values["grid"], 0)
        labels = [str(i + 1) for i in range(len(poses))]
    else:
        poses, labels = reference_pose(mech), ["reference"]
    return sources, poses, labels


def check(mech: Mechanism, options: dict) -> None:
    """Refuse unknown or missing options, bad values, missing or malformed tolerances and poses files, an unknown
    frame, and a Monte Carlo past the time budget (:class:`~mechatron.errors.InputError` naming
    ``[analyses.accuracy] FIELD``)."""
    from ...accuracy.study import monte_carlo_budget

    values = settings(mech, options)
    sources, poses, _ = sources_and_poses(mech, values)
    try:
        monte_carlo_budget(values["samples"], len(sources), len(poses))
    except InputError as exc:
        raise field_error("accuracy", "samples", exc.message) from None


def output_names(mech: Mechanism, options: dict) -> list[str]:
    """The names of the outputs (the same for every mechanism and options): :data:`OUTPUTS`."""
    return list(OUTPUTS)


def input_files(mech: Mechanism, options: dict) -> list[Path]:
    """The files the analysis of one design reads: the tolerances file and the poses file, if any."""
    values = settings(mech, options)
    return [values[key] for key in ("tolerances", "poses") if values[key] is not None]


def outputs(mech: Mechanism, options: dict, seed: int) -> dict[str, float]:
    """The outputs of one design (see the module), the Monte Carlo drawn from ``seed``.

    Raises:
        MechatronError: when the design's loops do not close at a pose.
    """
    from ...accuracy.study import analyse_tolerances

    values = settings(mech, options)
    sources, poses, labels = sources_and_poses(mech, values)
    common = dict(frame=values["frame"], k=values["k"])
    # the options were checked: an error left is the design's (a pose it cannot reach), the reason of its row
    try:
        linear = analyse_tolerances(mech, sources, poses, labels, methods=("worst", "rss"), **common).poses
    except InputError as exc:
        raise MechatronError(f"accuracy of {mech.name}: {exc}") from None
    quantile, within = 0.0, 1.0
    for pose, label in zip(poses, labels):
        # one pose at a time: the study keeps every Δr sample of its critical pose, so the quantile is exact
        try:
            mc = analyse_tolerances(mech, sources, pose, [label], methods=("mc",), samples=values["samples"], seed=seed,
                                    **common)
        except InputError as exc:  # the loops close at the pose but not for any sampled error
            raise MechatronError(f"accuracy of {mech.name}: pose {label}: "
                                 f"{exc.message.removeprefix('pose 1: ')}") from None
        r = np.linalg.norm(mc.samples, axis=1)
        quantile = max(quantile, float(np.quantile(r, values["quantile"])))
        within = min(within, np.count_nonzero(r <= values["limit"]) / values["samples"])
    return {"worst_case_mm": float(linear["dr_worst"].max()) * 1e3, "rss_mm": float(linear["dr_rss"].max()) * 1e3,
            "mc_quantile_mm": quantile * 1e3, "yield": float(within)}

