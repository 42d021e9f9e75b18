"""The structural report of a mechanism [Egorov, chapter 3]: counts, every formula, the numeric mobility and
redundancy of the model, and the structural groups.

The model's mobility is W = n_v − rank J (the closure Jacobian at a regular position), its redundant closure
equations the rank deficiency of J. For a planar mechanism modelled in the plane, Chebyshev's [Egorov, 3.3] and
[Egorov, 3.17] count the same constraints and must give W unless the geometry is special (then the rank deficiency
says so). Malyshev's [Egorov, 3.2] counts spatial constraints: a planar loop of lower pairs carries 3 redundant ones
(Reshetov's S of [Egorov, 3.12]; the per-loop S_j = 3 of [Egorov, 3.14]), so (3.2) gives W − 3K and [Egorov, 3.16]
gives W again. All counts are dimensionless.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import InputError
from ..model.mechanism import Mechanism
from ..report.result import Result
from . import formulas as F
from .description import StructuralDescription, from_mechanism
from .groups import Decomposition, decompose

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

#: The formulas of the report by key, with their names and equations.
FORMULA_NAMES = {
    "malyshev_3_2": "Malyshev [Egorov, 3.2]",
    "chebyshev_3_3": "Chebyshev [Egorov, 3.3]",
    "planar_with_redundant_links_3_17": "planar, redundant links [Egorov, 3.17]",
    "per_loop_3_16": "per loop [Egorov, 3.16]",
    "reshetov_3_11": "Reshetov [Egorov, 3.11]",
}


@dataclass
class StructureReport(Result):
    """Counts, formula values, the model's numbers when there is a model, groups and explanations.

    ``counts``: pairs by class; ``loops``: K [Egorov, 3.10]; ``loop_redundancies``: S_j [Egorov, 3.14];
    ``formulas``: the mobility by each formula (keys of :data:`FORMULA_NAMES`); ``degrees_of_mobility``: H
    [Egorov, 3.18]; ``mobility`` and ``redundant_equations``: the model's (None without a model).
    """

    description: StructuralDescription
    counts: dict[int, int]
    loops: int
    loop_redundancies: list[int]
    formulas: dict[str, int]
    degrees_of_mobility: int | None
    decomposition: Decomposition | None
    mobility: int | None = None
    redundant_equations: int | None = None
    actuated: list[str] = field(default_factory=list)
    agreement: dict[str, bool] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)

    @property
    def true_mobility(self) -> int:
        """The model's mobility; without a model, that of [Egorov, 3.16] (or of 3.17 for a planar description)."""
        if self.mobility is not None:
            return self.mobility
        return self.formulas.get("per_loop_3_16", self.formulas.get("planar_with_redundant_links_3_17"))

    def to_frame(self) -> pd.DataFrame:
        """The pairs: name, class (constraints), mobilities (6 − class), kind [Egorov, table 3.1], the two links
        it joins (empty when unknown), whether it is actuated, and the loops (1-based) it belongs to."""
        import pandas as pd

        d = self.description
        rows = []
        for p in d.pairs:
            rows.append({"pair": p.name, "class": p.cls, "mobilities": 6 - p.cls, "kind": p.kind or "",
                         "link_a": p.links[0] if p.links else "", "link_b": p.links[1] if p.links else "",
                         "actuated": p.actuated,
                         "loops": " ".join(str(j) for j, loop in enumerate(d.loops, start=1) if p.name in loop.pairs)})
        return pd.DataFrame(rows, columns=["pair", "class", "mobilities", "kind", "link_a", "link_b", "actuated",
                                           "loops"])

    def as_dict(self) -> dict:
        """The description, counts, every formula's mobility, the model's numbers, the groups and the notes."""
        d = self.description
        return {
            "mechanism": d.name, "planar": d.planar, "moving_links": d.n, "links": [d.frame, *d.links],
            "pairs": [{"name": p.name, "class": p.cls, "kind": p.kind, "links": list(p.links) if p.links else None,
                       "actuated": p.actuated} for p in d.pairs],
            "pairs_by_class": {str(k): v for k, v in sorted(self.counts.items(), reverse=True)},
            "loops": self.loops, "loop_pairs": [list(loop.pairs) for loop in d.loops],
            "loop_redundancy": self.loop_redundancies,
            "superfluous_mobilities": [-s for s in self.loop_redundancies if s < 0],
            "formulas": self.formulas, "degrees_of_mobility_H": self.degrees_of_mobility,
            "mobility": self.true_mobility,
            "mobility_source": "model (n_v − rank of the closure Jacobian)" if self.mobility is not None else
            "formula [Egorov, 3.16], no model", "redundant_closure_equations": self.redundant_equations,
            "actuated": self.actuated, "agreement": self.agreement,
            "groups": None if self.decomposition is None else [
                {"links": list(g.links), "pairs": list(g.pairs), "loops": g.loops, "dyad": g.dyad,
                 "driven_pairs": list(g.driven)}
                for g in self.decomposition.groups],
            "driving_links": None if self.decomposition is None else list(self.decomposition.driving_links),
            "notes": self.notes,
        }

    def plot(self, ax: Axes | None = None) -> Figure:
        """The mobility W by every formula (bars) against the model's (or, without a model, that of
        [Egorov, 3.16]) and the degrees of mobility H [Egorov, 3.18]."""
        from ..report.figures import figure_axes, style_axes

        fig, ax = figure_axes(ax, 8.0, 1.5 + 0.5 * len(self.formulas))
        names = [FORMULA_NAMES.get(k, k) for k in self.formulas]
        values = list(self.formulas.values())
        W = self.true_mobility
        positions = list(range(len(values)))
        for agrees, color, label in ((True, "tab:green", "gives W"), (False, "tab:red", "differs from W")):
            rows = [k for k in positions if (values[k] == W) == agrees]
            if rows:
                ax.barh(rows, [values[k] for k in rows], color=color, alpha=0.7, label=label)
        ax.set_yticks(positions, names)
        ax.invert_yaxis()
        source = "model: n_v − rank J" if self.mobility is not None else "[Egorov, 3.16]"
        ax.axvline(W, color="black", lw=1.5, label=f"mobility W = {W} ({source})")
        if self.degrees_of_mobility is not None:
            ax.axvline(self.degrees_of_mobility, color="tab:blue", lw=1.5, ls="--",
                       label=f"degrees of mobility H = {self.degrees_of_mobility} [Egorov, 3.18]")
        ax.axvline(0.0, color="grey", lw=0.8)
        style_axes(ax, "mobility W (-)", "formula (-)", f"{self.description.name}: mobility by formula",
                   legend=True)
        return fig

    def __str__(self) -> str:
        d = self.description
        lines = [f"{d.name}: {d.n} moving links, {len(d.pairs)} pairs, {self.loops} loop(s) [Egorov, 3.10]"
                 + (" — planar" if d.planar else "")]
        for cls in sorted(self.counts, reverse=True):
            members = [p for p in d.pairs if p.cls == cls]
            lines.append(f"  class {cls} ({6 - cls} mobilit{'y' if cls == 5 else 'ies'}): "
                         + ", ".join(p.name + (f" [{p.kind}]" if p.kind else "") + ("*" if p.actuated else "")
                                     for p in members))
        lines.append("  (* actuated)")
        for j, (loop, S) in enumerate(zip(d.loops, self.loop_redundancies), start=1):
            extra = (f", Z = {loop.redundant_links}" if loop.redundant_links else "") + \
                (f", closed by a {loop.closed_by}" if loop.closed_by else "") + (", repeated" if loop.repeated else "")
            lines.append(f"  loop {j}: {' '.join(loop.pairs)} — S_{j} = {S} [Egorov, 3.14]{extra}")
        lines.append("mobility by formula:")
        for name, value in self.formulas.items():
            mark = "" if name not in self.agreement else ("  ✓ = model" if self.agreement[name] else "  ✗ ≠ model")
            lines.append(f"  {FORMULA_NAMES.get(name, name):<40}{value:>4}{mark}")
        if self.mobility is not None:
            lines.append(f"model: mobility {self.mobility} (n_v − rank of the closure Jacobian), "
                         f"{self.redundant_equations} dependent closure equation(s), actuated: "
                         f"{', '.join(self.actuated) or 'none'}")
        if self.degrees_of_mobility is not None:
            lines.append(f"degrees of mobility H [Egorov, 3.18] = {self.degrees_of_mobility}")
        if self.decomposition is not None:
            dec = self.decomposition
            lines.append(f"driving links: {', '.join(dec.driving_links) or 'none'}")
            for g in dec.groups:
                kind = f"dyad {g.dyad}" if g.dyad else f"group of {len(g.links)} link(s)"
                driven = f" (driven pair {', '.join(g.driven)} inside: a link of driven length)" if g.driven else ""
                lines.append(f"  {kind}{driven}: links {', '.join(g.links)}; pairs {', '.join(g.pairs)}; closes "
                             f"{g.loops} loop(s)")
        for note in self.notes:
            lines.append(f"note: {note}")
        return "\n".join(lines)


def analyse(subject: StructuralDescription | Mechanism) -> StructureReport:
    """The structural report of a description (formulas only) or of a mechanism (formulas and its model)."""
    mech = subject if isinstance(subject, Mechanism) else None
    desc = from_mechanism(mech) if mech is not None else subject
    counts, n = desc.counts(), desc.n
    K = F.gokhman(n, counts)
    by_name = {p.name: p for p in desc.pairs}
    loop_S = [F.loop_redundancy(desc.counts([by_name[name] for name in loop.pairs])) for loop in desc.loops]
    Z = [loop.redundant_links for loop in desc.loops]
    values = {"malyshev_3_2": F.malyshev(n, counts)}
    if desc.planar:
        values["chebyshev_3_3"] = F.chebyshev(n, counts)
        values["planar_with_redundant_links_3_17"] = F.planar_mobility(n, counts, Z)
    if desc.loops or K == 0:
        values["per_loop_3_16"] = F.full_mobility(n, counts, loop_S, Z)
    decomposition = decompose(desc)
    H = _degrees_of_mobility(desc, n, decomposition)
    report = StructureReport(desc, counts, K, loop_S, values, H, decomposition)
    notes = report.notes
    if any(s < 0 for s in loop_S):
        notes.append("loops with superfluous mobilities h_j = −S_j: "
                     + ", ".join(f"loop {j + 1}: {-s}" for j, s in enumerate(loop_S) if s < 0))
    if mech is not None:
        report.mobility = mech.mobility()
        report.redundant_equations = mech.redundant_closure_equations()
        report.actuated = list(mech.actuated)
        values["reshetov_3_11"] = F.reshetov(n, counts, F.reshetov_redundancy(n, counts, report.mobility))
        _compare(report)
    elif decomposition is not None and not decomposition.complete:
        notes.append(f"links {', '.join(decomposition.unplaced)} form no structural group with the others")
    return report


def _degrees_of_mobility(desc: StructuralDescription, n: int, decomposition: Decomposition | None) -> int | None:
    """H of [Egorov, 3.18]: from the loops' closed_by when every counted loop states it, else from the groups."""
    counted = [loop for loop in desc.loops if not loop.repeated]
    if counted and all(loop.closed_by for loop in counted):
        return F.degrees_of_mobility(n, [2 if loop.closed_by == "group" else 1 for loop in counted])
    if not desc.loops and F.gokhman(n, desc.counts()) == 0:
        return n  # an open chain: K = 0, H = n ([Egorov, 3.18], the robot of fig. 3.15)
    if decomposition is not None and decomposition.complete:
        return n - sum(g.closing_value * g.loops for g in decomposition.groups)
    return None


def _compare(report: StructureReport) -> None:
    """Which formulas give the model's mobility, and why the others do not."""
    W, desc, values = report.mobility, report.description, report.formulas
    for name, value in values.items():
        report.agreement[name] = value == W
    K, redundant = report.loops, report.redundant_equations
    if desc.planar and values["malyshev_3_2"] != W:
        report.notes.append(f"Malyshev [Egorov, 3.2] counts spatial constraints: the {K} planar loop(s) carry "
                            f"S = {W - values['malyshev_3_2']} redundant constraints [Egorov, 3.12], the per-loop "
                            f"S_j [Egorov, 3.14] = {report.loop_redundancies}; [Egorov, 3.16] adds them back")
    if desc.planar and values["chebyshev_3_3"] != W:
        report.notes.append(f"Chebyshev [Egorov, 3.3] gives {values['chebyshev_3_3']} but the model moves with {W}: "
                            f"{redundant} closure equation(s) are dependent at this geometry (a special geometry the "
                            "formula cannot see)" if redundant else
                            f"Chebyshev [Egorov, 3.3] gives {values['chebyshev_3_3']}, the model {W}")
    if report.degrees_of_mobility is not None and report.degrees_of_mobility != len(report.actuated):
        report.notes.append(f"H [Egorov, 3.18] = {report.degrees_of_mobility} while the model has "
                            f"{len(report.actuated)} actuated coordinate(s)")


def analyse_structure(subject: StructuralDescription | Mechanism | str | Path) -> StructureReport:
    """The structural analysis [Egorov, chapter 3] of a :class:`~mechatron.model.Mechanism`, a
    :class:`~mechatron.structure.description.StructuralDescription`, or a description file given by path or by the
    name of a shipped case (``gripper_3_12a``)."""
    from .description import read_structure, structure_file

    if isinstance(subject, (str, Path)):
        path = structure_file(str(subject))
        if path is None:
            raise InputError(f"{subject}: not a structural description file (a TOML file with [[pairs]]) nor a "
                             "shipped case")
        subject = read_structure(path)
        try:
            return analyse(subject)
        except InputError as exc:  # the bounded group search: name the file
            if exc.file is None:
                raise InputError(exc.message, file=path, row=exc.row, field=exc.field) from None
            raise
    return analyse(subject)
