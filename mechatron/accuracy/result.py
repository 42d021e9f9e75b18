"""What a tolerance study returns: :class:`ToleranceResult`, with its text report and its charts (the error over the
poses, the Monte Carlo spread at the critical pose and, against a limit, its process capability over the poses, each
error source's contribution).

It follows the result protocol (:class:`~mechatron.report.result.Result`): ``to_frame()`` is the per-pose table,
``as_dict()`` the study as plain data, ``plot()`` the charts in one figure, ``str()`` the report printed by
``mechatron tolerance``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from ..report.result import Result, frame_records, json_ready
from .sensitivity import Sensitivities
from .sources import ErrorSource

if TYPE_CHECKING:  # pragma: no cover
    from pathlib import Path

    import pandas as pd
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..model.mechanism import Mechanism
    from ..report.html import Report

#: Colour classes of the error map.
MAP_CLASSES = 5
#: Poses the text report lists (the critical one is named when there are more).
SHOWN_POSES = 20


@dataclass
class ToleranceResult(Result):
    """A tolerance study over every pose [Egorov, chapter 8].

    Attributes:
        mechanism: The mechanism's name.
        frame: The frame whose position was studied.
        methods: The methods run (of ``given``, ``worst``, ``rss``, ``mc``); the first is the main one.
        k: The coverage factor (σ = t/k for normal errors; results at ±kσ). The ``rss`` results are the k·σ
            estimate |J b| + k·√Σ(∂r/∂e·σ)²: √Σ(∂r/∂e·t)², never above the worst case Σ|∂r/∂e|·t, when every error
            is normal; up to k/√3 times that with uniform errors (one uniform source ±t: √3·t > t for k = 3).
        sources: The error sources.
        poses: The per-pose table: ``label``, the coordinates (rad, m), nominal ``x``, ``y``, ``z`` (m) and, per
            method, ``dx_<method>``, ``dy_<method>``, ``dz_<method>``, ``dr_<method>`` (m); with ``given`` also
            ``dr_nonlinear_given`` (the full model's |Δr| for the same errors, m); with ``mc`` the Monte Carlo's
            ``mean_dr_mc``, ``std_dr_mc``, ``p50_dr_mc``, ``p95_dr_mc``, ``p99_dr_mc``, ``max_dr_mc`` (m),
            ``failed_mc`` (samples whose loops did not close) and, with a limit, ``yield_mc`` (fraction ≤ limit).
        contributions: One row per source at the critical pose: ``source``, ``kind``, ``unit``, ``tolerance``,
            ``distribution``, ``bias`` (SI, in ``unit``), ``sensitivity`` (|∂r/∂e|, m per unit), ``worst_share``,
            ``variance_share`` (%), ``mean_variance_share`` (% averaged over the poses), ``mc_share`` (% of the
            Monte Carlo variance, with ``mc``); largest variance share first.
        sensitivities: ∂r/∂e at every pose.
        critical: Index of the critical pose (the main method's largest |Δr|).
        samples: The Monte Carlo's Δr samples (N, 3) (m) at the critical pose, with ``mc``: the first 10⁶ at most
            (the statistics use every sample).
        limit: The largest acceptable |Δr| (m) of the yield, if given.
        notes: Remarks on the study.
        coordinates: The names of the coordinate columns of ``poses``.
        capability: With ``mc`` and a limit, the process capability (:mod:`~mechatron.accuracy.capability`): one
            row per pose and quantity — ``label``, ``quantity`` (``dx``, ``dy``, ``dz`` against ±L; ``dr``, |Δr|,
            against L), ``spec``, ``mean``, ``std`` (m), ``pp``, ``pp_low``, ``pp_high`` (NaN for ``dr``), ``ppk``,
            ``ppk_low``, ``ppk_high``, ``ppm``, ``ppm_low``, ``ppm_high`` (parts per million out; the bounds of 95 %
            intervals), ``samples`` (the pose's samples), ``sigma_error`` and ``ppm_error`` (the relative standard
            errors of σ and of the PPM of |Δr|; inf while none is out).
        target_error, target: The relative standard error the Monte Carlo's sample count was chosen for (with it the
            poses table has ``samples_mc``, the samples drawn, and ``reached_error_mc``, the error reached) and of
            what (``sigma`` or ``ppm``); ``None`` for a fixed count.
    """

    mechanism: str
    frame: str
    methods: tuple[str, ...]
    k: float
    sources: list[ErrorSource]
    poses: pd.DataFrame
    contributions: pd.DataFrame
    sensitivities: Sensitivities
    critical: int
    samples: NDArray[np.float64] | None = None
    limit: float | None = None
    notes: list[str] = field(default_factory=list)
    coordinates: tuple[str, ...] = ()
    capability: pd.DataFrame | None = None
    target_error: float | None = None
    target: str | None = None

    @property
    def main_method(self) -> str:
        return self.methods[0]

    @property
    def critical_label(self) -> str:
        return str(self.poses["label"].iloc[self.critical])

    # ---------------------------------------------------------------------------------------------- protocol
    def to_frame(self) -> pd.DataFrame:
        """The per-pose table (see :attr:`poses`; SI units)."""
        return self.poses.copy()

    def records(self) -> list[dict]:
        """One object per pose: label, coordinates, x, y, z, dx, dy, dz, dr of the main method (m) and every
        method's numbers under ``methods``."""
        out = []
        for row in self.poses.to_dict(orient="records"):
            record = {"label": str(row["label"]), "coordinates": {n: float(row[n]) for n in self.coordinates},
                      "x": float(row["x"]), "y": float(row["y"]), "z": float(row["z"])}
            for axis in ("dx", "dy", "dz", "dr"):
                record[axis] = float(row[f"{axis}_{self.main_method}"])
            record["methods"] = {m: {c[: -len(m) - 1]: row[c] for c in self.poses.columns if c.endswith("_" + m)}
                                 for m in self.methods}
            if self.capability is not None:
                record["capability"] = self._capability_record(str(row["label"]))
            out.append(record)
        return json_ready(out)

    def _capability_record(self, label: str) -> dict:
        """A pose's capability as plain data: ``samples``, ``sigma_error``, ``ppm_error`` and, per quantity (``dx``,
        ``dy``, ``dz``, ``dr``), ``spec``, ``mean``, ``std`` (m), ``pp``, ``ppk``, ``ppm`` and their ``_low`` and
        ``_high`` bounds (None where undefined or infinite)."""
        table = self._capability_table()
        rows = table[table["label"] == label].to_dict(orient="records")
        shared = ("samples", "sigma_error", "ppm_error")
        out: dict = {name: rows[0][name] for name in shared} if rows else {}
        for row in rows:
            out[row["quantity"]] = {key: value for key, value in row.items()
                                    if key not in ("label", "quantity", *shared)}
        return out

    def as_dict(self) -> dict:
        """The study as plain data: ``mechanism``, ``frame``, ``methods``, ``k``, ``limit`` (m or None),
        ``critical_pose`` (its label), ``poses`` (:meth:`records`; with a capability, each pose's under
        ``capability``), ``contributions`` (the rows of :attr:`contributions`) and ``notes``; with a target error
        also ``target_error`` and ``target``."""
        return json_ready({"mechanism": self.mechanism, "frame": self.frame, "methods": list(self.methods),
                           "k": self.k, "limit": self.limit, "critical_pose": self.critical_label,
                           "poses": self.records(), "contributions": frame_records(self.contributions),
                           "notes": list(self.notes),
                           **({"target_error": self.target_error, "target": self.target}
                              if self.target_error is not None else {})})

    def __str__(self) -> str:
        methods, count = self.methods, len(self.poses)
        lines = [f"{self.mechanism}: positioning error of {self.frame} ({', '.join(methods)}; k = {self.k:g}; "
                 f"{len(self.sources)} error sources, {count} pose{'s' if count > 1 else ''})"]
        shown = self.poses[["label", *[f"dr_{m}" for m in methods]]].copy()
        shown.iloc[:, 1:] *= 1e3
        shown.columns = ["pose", *[f"|Δr| {m} (mm)" for m in methods]]
        lines.append(shown.head(SHOWN_POSES).to_string(index=False, float_format=lambda x: f"{x:.5g}"))
        if count > SHOWN_POSES:
            lines.append(f"… {count - SHOWN_POSES} more poses; the largest at pose {self.critical_label}")
        lines.append("\ncontributions at the critical pose (% of the variance):")
        c = self.contributions
        columns = ["source", "unit", "tolerance", "sensitivity", "worst_share", "variance_share"]
        lines.append(c[columns + (["mc_share"] if "mc_share" in c else [])].to_string(
            index=False, float_format=lambda x: f"{x:.4g}"))
        if self.capability is not None:
            lines += self._capability_lines()
        lines += [f"note: {note}" for note in self.notes]
        return "\n".join(lines)

    def _capability_lines(self) -> list[str]:
        """The capability table of the text report: per pose and quantity Pp, Ppk and the PPM with their 95 %
        intervals, the samples and the relative standard errors of σ and of the PPM (%)."""
        import pandas as pd

        c = self.capability
        assert c is not None and self.limit is not None

        def span(low: float, high: float) -> str:
            return "" if math.isnan(low) else f"{low:.4g}…{high:.4g}"

        shown = pd.DataFrame({
            "pose": c["label"], "quantity": c["quantity"].map({"dx": "Δx", "dy": "Δy", "dz": "Δz", "dr": "|Δr|"}),
            "spec": c["spec"], "Pp": c["pp"].map(lambda x: "" if math.isnan(x) else f"{x:.4g}"),
            "Pp 95 %": [span(a, b) for a, b in zip(c["pp_low"], c["pp_high"])], "Ppk": c["ppk"].map("{:.4g}".format),
            "Ppk 95 %": [span(a, b) for a, b in zip(c["ppk_low"], c["ppk_high"])],
            "PPM": c["ppm"].map("{:.4g}".format), "PPM 95 %": [span(a, b) for a, b in zip(c["ppm_low"], c["ppm_high"])],
            "samples": c["samples"], "σ error (%)": (100 * c["sigma_error"]).map("{:.3g}".format),
            "PPM error (%)": (100 * c["ppm_error"]).map("{:.3g}".format)})
        poses = list(dict.fromkeys(c["label"]))
        lines = [f"\nprocess capability against L = {self.limit * 1e3:g} mm (per axis ±L, |Δr| ≤ L; Pp, Ppk "
                 f"[ISO 22514-2] with 95 % intervals [Bissell, 1990], PPM out with its exact interval "
                 f"[Clopper, 1934]; Ppk of |Δr| is a normal-theory index of a non-normal quantity):"]
        lines.append(shown[c["label"].isin(poses[:SHOWN_POSES])].to_string(index=False))
        if len(poses) > SHOWN_POSES:
            lines.append(f"… {len(poses) - SHOWN_POSES} more poses")
        if self.target_error is not None:
            reached = self.poses["reached_error_mc"]
            what = "σ" if self.target == "sigma" else "the PPM of |Δr|"
            lines.append(f"samples chosen for a relative standard error of {what} ≤ {self.target_error:g}: "
                         f"{int(self.poses['samples_mc'].min()):,}–{int(self.poses['samples_mc'].max()):,} per pose, "
                         f"largest error reached {np.nanmax(reached):.3g}")
        return lines

    # ---------------------------------------------------------------------------------------------- charts
    def plot(self, ax: Axes | None = None) -> Figure:
        """The error map (:meth:`draw_error_map`); without ``ax`` beside it the Monte Carlo histogram at the
        critical pose (with ``mc``) and each source's share of the variance."""
        from ..report.figures import figure_axes, new_figure

        if ax is not None:
            figure, ax = figure_axes(ax)
            self.draw_error_map(ax)
            return figure
        panels = [self.draw_error_map] + ([self.draw_histogram] if self.samples is not None else []) \
            + [self.draw_contributions]
        figure = new_figure(6.0 * len(panels), 5.5)
        for panel, axes in zip(panels, np.atleast_1d(figure.subplots(1, len(panels)))):
            panel(axes)
        return figure

    def draw_error_map(self, ax: Axes, method: str | None = None, axes: tuple[str, str] = ("x", "y")) -> Axes:
        """The nominal positions of the point (m) over the poses, in :data:`MAP_CLASSES` classes of |Δr| of
        ``method`` (default the main one, mm), the critical pose starred."""
        from ..report.figures import style_axes

        method = method or self.main_method
        table = self.poses
        dr = table[f"dr_{method}"].to_numpy() * 1e3
        a, b = axes
        finite = np.isfinite(dr)
        low, high = (dr[finite].min(), dr[finite].max()) if finite.any() else (0.0, 0.0)
        edges = np.linspace(low, high, MAP_CLASSES + 1) if high > low else np.array([low, high])
        classes = np.clip(np.searchsorted(edges, dr, side="right") - 1, 0, len(edges) - 2)
        colours = _colours(len(edges) - 1)
        for n in range(len(edges) - 1):
            chosen = (classes == n) & finite
            if chosen.any():
                ax.scatter(table[a][chosen], table[b][chosen], s=18, color=colours[n],
                           label=f"|Δr| {edges[n]:.4g}–{edges[n + 1]:.4g} mm")
        ax.plot(table[a].iloc[self.critical], table[b].iloc[self.critical], "r*", ms=14,
                label=f"critical pose {self.critical_label}")
        ax.set_aspect("equal", adjustable="datalim")
        return style_axes(ax, f"{a} (m)", f"{b} (m)", f"{self.mechanism}: |Δr| {method} of {self.frame} over "
                          f"{len(table)} pose{'s' if len(table) > 1 else ''}", legend=True)

    def draw_histogram(self, ax: Axes) -> Axes:
        """Histogram of the Monte Carlo |Δr| (mm) at the critical pose with the coverage, RSS, worst-case and limit
        lines."""
        from ..report.figures import style_axes

        d = self._monte_carlo_samples() * 1e3
        row = self.poses.iloc[self.critical]
        ax.hist(np.linalg.norm(d, axis=1), bins=80, histtype="stepfilled", color="tab:blue", alpha=0.8,
                label="Monte Carlo samples")
        ax.axvline(row["dr_mc"] * 1e3, color="tab:red", label=f"±{self.k:g}σ coverage: {row['dr_mc'] * 1e3:.4g} mm")
        if "dr_rss" in row:
            ax.axvline(row["dr_rss"] * 1e3, color="tab:green", ls="--", label=f"RSS: {row['dr_rss'] * 1e3:.4g} mm")
        if "dr_worst" in row:
            ax.axvline(row["dr_worst"] * 1e3, color="k", ls=":", label=f"worst case: {row['dr_worst'] * 1e3:.4g} mm")
        if self.limit is not None:
            ax.axvline(self.limit * 1e3, color="tab:orange", label=f"limit {self.limit * 1e3:g} mm")
        return style_axes(ax, "|Δr| (mm)", "samples (count)",
                          f"Monte Carlo: {len(d)} samples at pose {row['label']}", legend=True)

    def draw_spread(self, ax: Axes) -> Axes:
        """The Monte Carlo Δr samples (mm) at the critical pose in the plane of the two axes with the largest
        spread."""
        from ..report.figures import style_axes

        d = self._monte_carlo_samples() * 1e3
        shown = d[:: max(1, len(d) // 5000)]
        a, b = sorted(np.argsort(-d.std(axis=0))[:2])
        ax.scatter(shown[:, a], shown[:, b], s=2, alpha=0.3)
        ax.set_aspect("equal", adjustable="datalim")
        return style_axes(ax, f"Δ{'xyz'[a]} (mm)", f"Δ{'xyz'[b]} (mm)",
                          f"Monte Carlo spread at pose {self.critical_label}")

    def draw_contributions(self, ax: Axes) -> Axes:
        """Each source's share (%) of the variance of Δr (RSS) at the critical pose, and of the Monte Carlo."""
        from ..report.figures import style_axes

        c = self.contributions.iloc[::-1]
        y = np.arange(len(c))
        both = "mc_share" in c
        ax.barh(y, c["variance_share"], height=0.4 if both else 0.7, label="linear (RSS)")
        if both:
            ax.barh(y - 0.4, c["mc_share"], height=0.4, label="Monte Carlo")
        ax.set_yticks(y - (0.2 if both else 0), c["source"])
        return style_axes(ax, "share of the variance of Δr (%)", "error source (parameter or coordinate)",
                          f"contributions at pose {self.critical_label}", legend=True)

    def draw_capability(self, ax: Axes) -> Axes:
        """Ppk (dimensionless) per pose with its 95 % interval: of each axis with a spread against ±L and of |Δr|
        against L, and the line Ppk = 1 (the mean 3σ inside the limit)."""
        from ..report.figures import style_axes

        c = self._capability_table()
        poses = list(dict.fromkeys(c["label"]))
        x = np.arange(len(poses))
        names = {"dx": "Δx (±L)", "dy": "Δy (±L)", "dz": "Δz (±L)", "dr": "|Δr| (≤ L)"}
        for n, quantity in enumerate(names):
            rows = c[c["quantity"] == quantity].set_index("label").reindex(poses)
            finite = np.isfinite(rows["ppk"].to_numpy(dtype=float))
            if not finite.any():
                continue  # no spread (Δz of a planar arm): Ppk infinite
            y = rows["ppk"].to_numpy(dtype=float)[finite]
            low, high = rows["ppk_low"].to_numpy(dtype=float)[finite], rows["ppk_high"].to_numpy(dtype=float)[finite]
            ax.errorbar(x[finite] + 0.1 * (n - 1.5), y, yerr=[y - low, high - y], fmt="o", capsize=3,
                        label=names[quantity])
        ax.axhline(1.0, color="k", ls=":", label="Ppk = 1")
        long = max(len(label) for label in poses) > 6
        ax.set_xticks(x, poses, rotation=30 if long else 0, ha="right" if long else "center")
        limit = float(self.limit or 0.0)
        return style_axes(ax, "pose (label)", "Ppk (-)", f"process capability against L = {limit * 1e3:g} mm, "
                          "95 % intervals", legend=True)

    def _capability_table(self) -> pd.DataFrame:
        if self.capability is None:
            raise InputError("no process capability: run the study with method mc and a limit")
        return self.capability

    def _monte_carlo_samples(self) -> NDArray[np.float64]:
        if self.samples is None:
            raise InputError("no Monte Carlo samples: run the study with method mc")
        return self.samples

    def error_map(self, method: str | None = None) -> Figure:
        """The error map as a figure: x–y, and x–z beside it when the point leaves the plane z = const."""
        from ..report.figures import new_figure

        planar = np.ptp(self.poses["z"]) < 1e-9
        figure = new_figure(7.0 if planar else 12.0, 5.5)
        for ax, axes in zip(np.atleast_1d(figure.subplots(1, 1 if planar else 2)), (("x", "y"), ("x", "z"))):
            self.draw_error_map(ax, method, axes)
        return figure

    def monte_carlo_chart(self) -> Figure:
        """The Monte Carlo histogram of |Δr| and the Δr spread at the critical pose and, against a limit, Ppk per
        pose (:meth:`draw_capability`)."""
        from ..report.figures import new_figure

        self._monte_carlo_samples()
        panels = [self.draw_histogram, self.draw_spread] + ([self.draw_capability] if self.capability is not None
                                                            else [])
        figure = new_figure(6.0 * len(panels), 5.0)
        for panel, axes in zip(panels, figure.subplots(1, len(panels))):
            panel(axes)
        return figure

    def contribution_chart(self) -> Figure:
        """Each source's share of the variance at the critical pose."""
        from ..report.figures import new_figure

        figure = new_figure(8.0, 0.3 * len(self.contributions) + 1.8)
        self.draw_contributions(figure.add_subplot())
        return figure

    def charts(self) -> dict[str, Figure]:
        """The charts that apply, by name: ``error_map`` (several poses), ``monte_carlo`` (with ``mc``),
        ``contributions``."""
        out = {}
        if len(self.poses) > 1:
            out["error_map"] = self.error_map()
        if self.samples is not None:
            out["monte_carlo"] = self.monte_carlo_chart()
        out["contributions"] = self.contribution_chart()
        return out

    def save_charts(self, directory: str | Path) -> list[Path]:
        """Every chart of :meth:`charts` as ``<directory>/<mechanism>_<name>.png`` (the directory created if
        needed), whole and all together (:func:`mechatron.io.output.write_folder`); the charts an earlier call for
        the same mechanism wrote there and this one does not draw are removed. Returns the files written."""
        from ..io.output import write_folder

        return write_folder(directory, {f"{self.mechanism}_{name}.png": (lambda f=figure: f)
                                        for name, figure in self.charts().items()},
                            owner=f"mechatron tolerance {self.mechanism}")

    # ---------------------------------------------------------------------------------------- the HTML report
    def report(self, mechanism: Mechanism | None = None, **context) -> Report:
        """The HTML report (:mod:`mechatron.report.html`): the tolerances, the method, every pose with its |Δr| by
        every method (mm; against the limit when one is given), the contributions at the critical pose, the notes,
        the charts and, given ``mechanism``, the mechanism drawn at the critical pose."""
        import sys

        import pandas as pd

        from ..kinematics.drawing import configuration_figure
        from ..report.html import Chart, Method, Report, Section, Table, Text
        from . import sensitivity, sources

        tolerances = pd.DataFrame([vars(source) for source in self.sources])
        poses = self.poses[["label", *self.coordinates, "x", "y", "z"]].copy()
        for method in self.methods:
            poses[f"|Δr| {method} (mm)"] = self.poses[f"dr_{method}"] * 1e3
        if self.limit is not None:
            poses["pass"] = self.poses[f"dr_{self.main_method}"] <= self.limit
        study = sys.modules.get("mechatron.accuracy.study")  # the module that ran the study (it imports this one)
        dr = self.poses[f"dr_{self.main_method}"].iloc[self.critical]
        summary = f"critical pose {self.critical_label}: |Δr| {self.main_method} = {dr * 1e3:.4g} mm" + \
            ("" if self.limit is None else f" (limit {self.limit * 1e3:g} mm)")
        sections = [
            Section("Tolerances", [Table(tolerances, f"error sources (SI; k = {self.k:g})", "tolerances")]),
            Section("Method", [Method(text) for text in (getattr(study, "__doc__", None), sensitivity.__doc__,
                                                         sources.ErrorSource.sigma.__doc__) if text]),
            Section("Poses", [Table(poses, f"every pose: coordinates (rad, m), nominal position of {self.frame} (m), "
                                           "|Δr| (mm)" + (", PASS when |Δr| ≤ the limit" if self.limit else ""),
                                    "poses")]),
            Section("Contributions", [Table(self.contributions, f"at the critical pose {self.critical_label} (%)",
                                            "contributions")] + [Text(note) for note in self.notes]),
            *([Section("Capability", [Table(self.capability, f"process capability against L = {self.limit * 1e3:g} "
                                            "mm: Pp, Ppk [ISO 22514-2] with 95 % intervals [Bissell, 1990], parts "
                                            "per million out with the exact interval [Clopper, 1934]; mean, std in m",
                                            "capability")])]
              if self.capability is not None and self.limit is not None else []),
            Section("Charts", [Chart(figure, name.replace("_", " ")) for name, figure in self.charts().items()])]
        if mechanism is not None:
            frame = self.frame if self.frame in mechanism.frame_names else None
            sections.append(Section("Critical pose", [Text(summary), Chart(configuration_figure(
                mechanism, self.sensitivities.q[self.critical], frame=frame,
                title=f"{self.mechanism} at pose {self.critical_label}"))]))
        return Report(str(self).splitlines()[0], sections, summary)


def _colours(count: int) -> list:
    from matplotlib import colormaps

    return [colormaps["viridis"](x) for x in (np.linspace(0, 1, count) if count > 1 else [0.5])]

