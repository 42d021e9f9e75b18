"""What a tolerance allocation returns: :class:`AllocationResult` — the allocated tolerances with their costs and
shares of the error, the error at every pose against the limit, and the Monte Carlo that verifies it.

It follows the result protocol (:class:`~mechatron.report.result.Result`): ``to_frame()`` is the allocated table,
``as_dict()`` the allocation as plain data, ``plot()`` the costs and shares, ``str()`` the report printed by
``mechatron tolerance --allocate``; :meth:`AllocationResult.write_tolerances` writes the allocated tolerances as a
tolerances CSV.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from ..report.result import Result, frame_records, json_ready, readable
from .costs import ContinuousCost, CostedSource, ProcessTable

if TYPE_CHECKING:  # pragma: no cover
    from pathlib import Path

    import pandas as pd
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..model.mechanism import Mechanism
    from ..report.html import Report
    from .error_model import ErrorModel
    from .result import ToleranceResult

#: Relative distance to the limit within which a pose's constraint counts as active (binding).
ACTIVE = 1e-6
SHOWN_POSES = 20


@dataclass
class AllocationResult(Result):
    """A least-cost tolerance allocation [Chase] (:mod:`~mechatron.accuracy.allocation`).

    Attributes:
        mechanism, frame: The mechanism's name and the frame whose position is bounded.
        method: ``rss`` or ``worst``: the error bounded by the limit; ``k`` the coverage factor.
        limit: The largest |Δr| allowed (m).
        table: One row per error source: ``source``, ``kind``, ``model`` (``continuous``, ``process`` or
            ``fixed``), ``process``, ``option`` (of a process row), ``unit`` (the file unit the tolerance is shown in),
            ``tolerance`` (in ``unit``), ``tolerance_si`` (m or rad), ``tolerance_min``, ``tolerance_max`` (in
            ``unit``; NaN for a fixed row), ``cost``, ``given_tolerance`` (in ``unit``; NaN if the file gave none),
            ``given_cost``, ``distribution``, ``bias_si``, ``share`` (% of the error at the critical pose).
        poses: One row per pose: ``label``, the coordinates (rad, m), ``dr`` (the method's |Δr| of the allocation,
            m), ``margin`` (L − dr, m), ``binding`` (the constraint is active: within 10⁻⁶ L of L), and the
            verifying Monte Carlo of the full nonlinear model: ``dr_mc`` (|Δr| at the coverage of ±kσ, m),
            ``yield_mc`` (fraction of samples within L) and ``meets_mc`` (dr_mc ≤ L).
        total_cost: The allocation's total cost; ``given_cost``: that of the file's own tolerances (None if some
            costed row gave none).
        critical: The label of the pose with the largest |Δr|.
        search: How the optimum was found: ``kind``, rows ``continuous`` and ``process``, ``nodes`` of the branch
            and bound, ipopt ``solves`` and ``iterations``.
        samples, seed: The verifying Monte Carlo's samples per pose and seed.
        verification: The tolerance study of the allocated tolerances (method and ``mc``).
    """

    mechanism: str
    frame: str
    method: str
    k: float
    limit: float
    table: pd.DataFrame
    poses: pd.DataFrame
    total_cost: float
    given_cost: float | None
    critical: str
    search: dict
    samples: int
    seed: int
    costed: list[CostedSource] = field(repr=False, default_factory=list)
    verification: ToleranceResult | None = field(repr=False, default=None)
    notes: list[str] = field(default_factory=list)
    coordinates: tuple[str, ...] = ()

    @classmethod
    def build(cls, mechanism: str, frame: str, method: str, k: float, limit: float, costed: Sequence[CostedSource],
              t: np.ndarray, total: float, model: ErrorModel, achieved: np.ndarray, study: ToleranceResult,
              labels: Sequence[str], coordinates: tuple[str, ...], poses: np.ndarray, search: dict,
              notes: list[str], samples: int, seed: int) -> AllocationResult:
        """The result of :func:`~mechatron.accuracy.allocation.allocate_tolerances` from its pieces."""
        import pandas as pd

        critical = int(np.argmax(achieved))
        shares = model.shares(t, critical)
        rows = []
        for cs, value, share in zip(costed, t, shares):
            f, m = cs.factor, cs.model
            low, high = (m.lower / f, m.upper / f) if isinstance(m, ContinuousCost) else \
                (m.tolerances[-1] / f, m.tolerances[0] / f) if isinstance(m, ProcessTable) else (math.nan, math.nan)
            option = int(np.argmin(np.abs(np.array(m.tolerances) - value))) if isinstance(m, ProcessTable) else None
            unit = m.units[option] if isinstance(m, ProcessTable) and option is not None else cs.unit
            f_shown = _factor(unit)
            rows.append({
                "source": cs.source.name, "kind": cs.source.kind,
                "model": "continuous" if isinstance(m, ContinuousCost) else "process" if m else "fixed",
                "process": m.name if isinstance(m, ProcessTable) else "",
                "option": (m.options[option] or str(option + 1)) if isinstance(m, ProcessTable) and option is not None
                else "",
                "unit": unit or cs.source.unit, "tolerance": value / f_shown, "tolerance_si": value,
                "tolerance_min": low * f / f_shown if not math.isnan(low) else math.nan,
                "tolerance_max": high * f / f_shown if not math.isnan(high) else math.nan,
                "cost": cs.cost(value),
                "given_tolerance": cs.source.tolerance / f_shown if cs.given else math.nan,
                "given_cost": cs.cost(cs.source.tolerance) if cs.given and m is not None else
                (0.0 if m is None else math.nan),
                "distribution": cs.source.distribution, "bias_si": cs.source.bias, "share": share})
        table = pd.DataFrame(rows)
        given = [cs.cost(cs.source.tolerance) for cs in costed if cs.model is not None and cs.given]
        all_given = all(cs.given for cs in costed if cs.model is not None) and not any(map(math.isnan, given))
        at_poses = pd.DataFrame({"label": list(labels)})
        for j, name in enumerate(coordinates):
            at_poses[name] = poses[:, j]
        at_poses["dr"] = achieved
        at_poses["margin"] = limit - achieved
        at_poses["binding"] = achieved >= limit * (1 - ACTIVE)
        at_poses["dr_mc"] = study.poses["dr_mc"].to_numpy()
        at_poses["yield_mc"] = study.poses["yield_mc"].to_numpy()
        at_poses["meets_mc"] = at_poses["dr_mc"] <= limit
        notes = list(notes)
        spread = np.max(np.abs(study.poses[f"dr_{method}"].to_numpy() - achieved))
        if spread > 1e-9 * limit:
            notes.append(f"the study's {method} error differs from the allocation's by {spread:.3g} m")
        notes += study.notes
        return cls(mechanism, frame, method, k, limit, table, at_poses, float(total),
                   float(sum(given)) if all_given else None, str(labels[critical]), search, samples, seed,
                   list(costed), study, notes, coordinates)

    # ---------------------------------------------------------------------------------------------- protocol
    @property
    def binding(self) -> list[str]:
        """The labels of the poses whose constraint is active (|Δr| within 10⁻⁶ L of L)."""
        return [str(label) for label in self.poses.loc[self.poses["binding"], "label"]]

    @property
    def meets(self) -> bool:
        """Whether the Monte Carlo's |Δr| at the coverage is within the limit at every pose."""
        return bool(self.poses["meets_mc"].all())

    def to_frame(self) -> pd.DataFrame:
        """The allocated table (see :attr:`table`)."""
        return self.table.copy()

    def as_dict(self) -> dict:
        """The allocation as plain data: ``mechanism``, ``frame``, ``method``, ``k``, ``limit`` (m), ``total_cost``,
        ``given_cost``, ``critical_pose``, ``binding_poses``, ``meets_limit_mc``, ``search``, ``tolerances`` (rows
        of :attr:`table`), ``poses`` (rows of :attr:`poses`) and ``notes``."""
        return json_ready({"mechanism": self.mechanism, "frame": self.frame, "method": self.method, "k": self.k,
                           "limit": self.limit, "total_cost": self.total_cost, "given_cost": self.given_cost,
                           "critical_pose": self.critical, "binding_poses": self.binding,
                           "meets_limit_mc": self.meets, "search": self.search,
                           "tolerances": frame_records(self.table), "poses": frame_records(self.poses),
                           "notes": list(self.notes)})

    def report(self, mechanism: Mechanism | None = None, **context: object) -> Report:
        """The HTML report (:mod:`mechatron.report.html`): the allocated tolerances with their costs and shares, the
        method, every pose with its error and the verifying Monte Carlo (mm, PASS when within the limit), and the
        charts."""
        import sys

        from ..report.html import Chart, Method, Report, Section, Table, Text

        poses = self.poses.copy()
        for column in ("dr", "margin", "dr_mc"):
            poses[f"{column} (mm)"] = poses.pop(column) * 1e3
        poses["pass"] = poses.pop("meets_mc")
        solver = sys.modules.get("mechatron.accuracy.allocation")  # the module that ran it (it imports this one)
        summary = (f"total cost {self.total_cost:.6g}" + ("" if self.given_cost is None else
                                                         f" (the file's tolerances: {self.given_cost:.6g})")
                   + f"; binding at {', '.join(self.binding) or 'no pose'}; the Monte Carlo "
                   + ("meets" if self.meets else "does not meet") + f" {self.limit * 1e3:g} mm at every pose")
        sections = [
            Section("Allocation", [Text(summary), Table(self.table, "per error source: model, process option, "
                                                        "tolerance (its file unit and SI), cost, share (%)",
                                                        "allocation")]),
            Section("Method", [Method(solver.__doc__)] if solver is not None and solver.__doc__ else []),
            Section("Poses", [Table(poses, f"|Δr| {self.method} of the allocation and of a Monte Carlo of the full "
                                           f"nonlinear model ({self.samples:,} samples per pose, seed {self.seed}) "
                                           "against the limit (mm)", "poses"),
                              *(Text(f"note: {note}") for note in self.notes)]),
            Section("Charts", [Chart(self.plot())]),
        ]
        return Report(str(self).splitlines()[0], sections, summary)

    def __str__(self) -> str:
        n = len(self.poses)
        lines = [f"{self.mechanism}: least-cost tolerances for |Δr| ({self.method}, k = {self.k:g}) of {self.frame} "
                 f"<= {readable(self.limit * 1e3)} mm at {n} pose{'s' if n > 1 else ''} ({self.search['kind']})"]
        t = self.table
        shown = t[["source", "model", "option", "unit", "tolerance", "given_tolerance", "cost", "share"]].copy()
        shown["option"] = [f"{p}: {o}" if p else "" for p, o in zip(t["process"], t["option"])]
        shown.columns = ["source", "model", "process", "unit", "tolerance", "given", "cost", "share (%)"]
        lines.append(shown.to_string(index=False, na_rep="", float_format=lambda x: f"{x:.5g}"))
        cost = f"total cost {readable(self.total_cost)}"
        if self.given_cost is not None:
            cost += f" (the file's tolerances: {readable(self.given_cost)})"
        lines.append(cost)
        binding = self.binding
        lines.append("binding poses (|Δr| = limit): " + (", ".join(binding) if binding else
                     f"none (the largest |Δr| is at pose {self.critical}, below the limit)"))
        p = self.poses
        table = p[["label", "dr", "dr_mc", "yield_mc", "meets_mc"]].copy()
        table["dr"], table["dr_mc"], table["yield_mc"] = p["dr"] * 1e3, p["dr_mc"] * 1e3, 100 * p["yield_mc"]
        coverage = 100 * math.erf(self.k / math.sqrt(2))
        table.columns = ["pose", f"|Δr| {self.method} (mm)", f"MC |Δr| {coverage:.4g} % (mm)", "MC within (%)",
                         "MC <= limit"]
        lines.append(f"\nthe error at every pose, and a Monte Carlo of the full nonlinear model "
                     f"({self.samples:,} samples per pose):")
        lines.append(table.head(SHOWN_POSES).to_string(index=False, float_format=lambda x: f"{x:.5g}"))
        if n > SHOWN_POSES:
            lines.append(f"… {n - SHOWN_POSES} more poses")
        failed = [str(label) for label in p.loc[~p["meets_mc"], "label"]]
        lines.append("verified: the Monte Carlo meets the limit at every pose" if not failed else
                     f"NOT verified: the Monte Carlo exceeds the limit at pose(s) {', '.join(failed)}")
        lines += [f"note: {note}" for note in self.notes]
        return "\n".join(lines)

    def plot(self, ax: Axes | None = None) -> Figure:
        """The cost of every costed row and every row's share of the error at the critical pose (into ``ax``: the
        shares alone)."""
        from ..report.figures import figure_axes, new_figure

        if ax is not None:
            figure, ax = figure_axes(ax)
            self.draw_shares(ax)
            return figure
        figure = new_figure(12.0, 5.5)
        left, right = figure.subplots(1, 2)
        self.draw_costs(left)
        self.draw_shares(right)
        return figure

    def draw_costs(self, ax: Axes) -> Axes:
        """Bars of the allocated cost of every costed row beside its cost at the file's tolerance."""
        from ..report.figures import style_axes

        t = self.table[self.table["model"] != "fixed"]
        x = np.arange(len(t))
        ax.bar(x - 0.2, t["cost"], 0.4, label="allocated")
        ax.bar(x + 0.2, t["given_cost"].fillna(0.0), 0.4, label="file's tolerance")
        ax.set_xticks(x, [f"{s} {v:.3g} {u}" for s, v, u in zip(t["source"], t["tolerance"], t["unit"])],
                      rotation=45, ha="right", fontsize=7)
        return style_axes(ax, "source (allocated tolerance)", "cost (the file's cost unit)",
                          f"total {readable(self.total_cost)}", legend=True)

    def draw_shares(self, ax: Axes) -> Axes:
        """Bars of every row's share of the error (%) at the critical pose."""
        from ..report.figures import style_axes

        t = self.table
        x = np.arange(len(t))
        colours = ["tab:blue" if m != "fixed" else "tab:grey" for m in t["model"]]
        ax.bar(x, t["share"], color=colours)
        ax.set_xticks(x, list(t["source"]), rotation=60, fontsize=7)
        what = "Σ|∂r/∂e|·t" if self.method == "worst" else "the variance Σ(∂r/∂e·kσ)²"
        return style_axes(ax, "source (grey: fixed)", f"share of {what} (%)", f"pose {self.critical}")

    # ---------------------------------------------------------------------------------------------- the CSV
    def tolerances_frame(self) -> pd.DataFrame:
        """The allocated tolerances as a tolerances file's table (:mod:`~mechatron.accuracy.sources`): parameter,
        a ``tolerance_<unit>`` column per unit used (one filled per row), distribution, ``bias_<unit>`` where a row
        has a bias, note."""
        import pandas as pd

        rows: list[dict[str, Any]] = []
        for row in self.table.to_dict(orient="records"):
            unit = row["unit"] if row["unit"] not in ("m", "rad", "-") else ""
            column = f"tolerance_{unit}" if unit else "tolerance"
            out = {"parameter": row["source"], column: repr(float(row["tolerance"]))}
            out["distribution"] = row["distribution"]
            if row["bias_si"]:
                out[f"bias_{unit}" if unit else "bias"] = repr(float(row["bias_si"] / _factor(unit)))
            note = {"continuous": "allocated", "process": f"allocated: process {row['process']} {row['option']}",
                    "fixed": "fixed"}[row["model"]]
            out["note"] = f"{note}, cost {row['cost']:.6g}" if row["model"] != "fixed" else note
            rows.append(out)
        frame = pd.DataFrame(rows).fillna("")
        first = ["parameter"] + sorted(c for c in frame.columns if c.startswith("tolerance"))
        return frame[first + [c for c in frame.columns if c not in first]]

    def write_tolerances(self, path: str | Path) -> Path:
        """Write :meth:`tolerances_frame` as CSV, whole or not at all."""
        from ..io.output import write_table

        return write_table(self.tolerances_frame(), path)


def _factor(unit: str) -> float:
    """The SI value of a length or angle unit suffix (1 for SI, m, rad or a ratio)."""
    from .sources import ANGLE_UNITS, LENGTH_UNITS

    return {**LENGTH_UNITS, **ANGLE_UNITS}.get(unit, 1.0)
