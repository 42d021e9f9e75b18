"""Charts of an accuracy study: the error over the poses (a map of the workspace), the Monte Carlo spread at the
critical pose, and each error source's contribution."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from ..errors import InputError
from ..io.output import output_directory
from ..io.output import save_figure as _save
from .study import StudyResult


def error_map(result: StudyResult, path: str | Path, method: str | None = None) -> Path:
    """The nominal point positions (x, y; x, z beside it when the point leaves the plane) coloured by |Δr| (mm)."""
    method = method or result.main_method
    table = result.poses
    dr = table[f"dr_{method}"].to_numpy() * 1e3
    planar = np.ptp(table["z"]) < 1e-9
    fig = Figure(figsize=(7 if planar else 12, 5.5), layout="constrained")
    axes = [fig.subplots()] if planar else list(fig.subplots(1, 2))
    for ax, (a, b) in zip(axes, (("x", "y"), ("x", "z"))):
        points = ax.scatter(table[a], table[b], c=dr, cmap="viridis", s=18)
        ax.plot(table[a].iloc[result.critical], table[b].iloc[result.critical], "r*", ms=14, label="critical pose")
        ax.set_xlabel(f"{a} (m)")
        ax.set_ylabel(f"{b} (m)")
        ax.set_aspect("equal", adjustable="datalim")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    fig.colorbar(points, ax=axes, label=f"|Δr| {method} (mm)")
    axes[0].set_title(f"{result.mechanism}: positioning error of {result.frame} over {len(table)} poses")
    _save(fig, Path(path))
    return Path(path)


def monte_carlo_chart(result: StudyResult, path: str | Path) -> Path:
    """Histogram of |Δr| and the Δx–Δy scatter (mm) of the Monte Carlo samples at the critical pose."""
    if result.samples is None:
        raise InputError("no Monte Carlo samples: run the study with method mc")
    d = result.samples * 1e3
    r = np.linalg.norm(d, axis=1)
    fig = Figure(figsize=(12, 5), layout="constrained")
    left, right = fig.subplots(1, 2)
    left.hist(r, bins=80, color="tab:blue", alpha=0.8)
    row = result.poses.iloc[result.critical]
    left.axvline(row["dr_mc"] * 1e3, color="tab:red", label=f"±{result.k:g}σ coverage: {row['dr_mc'] * 1e3:.4g} mm")
    if "dr_rss" in row:
        left.axvline(row["dr_rss"] * 1e3, color="tab:green", ls="--", label=f"RSS (8.6): {row['dr_rss'] * 1e3:.4g} mm")
    if "dr_worst" in row:
        left.axvline(row["dr_worst"] * 1e3, color="k", ls=":", label=f"worst case: {row['dr_worst'] * 1e3:.4g} mm")
    if result.limit is not None:
        left.axvline(result.limit * 1e3, color="tab:orange", label=f"limit {result.limit * 1e3:g} mm")
    left.set_xlabel("|Δr| (mm)")
    left.set_ylabel("samples")
    left.legend(fontsize=8)
    shown = d[:: max(1, len(d) // 20000)]
    a, b = sorted(np.argsort(-d.std(axis=0))[:2])  # the two axes with the largest spread
    right.scatter(shown[:, a], shown[:, b], s=2, alpha=0.3)
    right.set_xlabel(f"Δ{'xyz'[a]} (mm)")
    right.set_ylabel(f"Δ{'xyz'[b]} (mm)")
    right.set_aspect("equal", adjustable="datalim")
    right.grid(True, alpha=0.3)
    fig.suptitle(f"{result.mechanism}: Monte Carlo of {len(d)} samples at pose {row['label']}")
    _save(fig, Path(path))
    return Path(path)


def contribution_chart(result: StudyResult, path: str | Path) -> Path:
    """Each source's share (%) of the variance (RSS) at the critical pose, and of the Monte Carlo if run."""
    c = result.contributions.iloc[::-1]
    fig = Figure(figsize=(8, 0.3 * len(c) + 1.8), layout="constrained")
    ax = fig.subplots()
    y = np.arange(len(c))
    ax.barh(y, c["variance_share"], height=0.4 if "mc_share" in c else 0.7, label="linear (RSS)")
    if "mc_share" in c:
        ax.barh(y - 0.4, c["mc_share"], height=0.4, label="Monte Carlo")
    ax.set_yticks(y - (0.2 if "mc_share" in c else 0), c["source"])
    ax.set_xlabel("share of the variance of Δr (%)")
    ax.set_title(f"{result.mechanism}: contributions at pose {result.poses['label'].iloc[result.critical]}")
    ax.grid(True, axis="x", alpha=0.3)
    ax.legend(fontsize=8)
    _save(fig, Path(path))
    return Path(path)


def write_charts(result: StudyResult, directory: str | Path) -> list[Path]:
    """The charts that apply, in ``directory``: map (several poses), Monte Carlo, contributions."""
    directory = output_directory(directory)
    out = []
    if len(result.poses) > 1:
        out.append(error_map(result, directory / f"{result.mechanism}_error_map.png"))
    if result.samples is not None:
        out.append(monte_carlo_chart(result, directory / f"{result.mechanism}_monte_carlo.png"))
    out.append(contribution_chart(result, directory / f"{result.mechanism}_contributions.png"))
    return out
