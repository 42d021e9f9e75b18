r"""What the sizing of a mechanism returns (:class:`SizingResult`): the drive of every coordinate, the passes of the
fixed point (:class:`Iteration`), the totals, the electrical and hydraulic balances, and the reports — text, JSON,
charts, HTML.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import pandas as pd

from ..errors import InputError
from ..report.result import Result, json_ready, readable
from .duty import DriveMount
from .report import COLUMNS, REPORTED, DriveSizing

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..dynamics.task import Task
    from ..model.mechanism import Mechanism
    from ..report.html import Report
    from .electrical import ElectricalBalance
    from .hydraulics import HydraulicSupply
    from .resistors import BrakingSupply


@dataclass(frozen=True)
class Iteration:
    """One pass of the sizing over every driven coordinate (distal to proximal).

    Attributes:
        number: 1, 2, …
        weighted: whether the chosen drives' masses loaded the mechanism (pass 1 sizes with weightless drives).
        time_scale: the pace of the pass's moves (``time`` objective; 1 otherwise).
        changes: (joint, drive before, drive after) for every coordinate whose drive changed (before ``None`` in
            pass 1).
    """

    number: int
    weighted: bool
    time_scale: float
    changes: tuple[tuple[str, str | None, str], ...]

    def as_dict(self) -> dict:
        return {"iteration": self.number, "drive_masses": self.weighted, "time_scale": self.time_scale,
                "changes": [{"joint": j, "from": a, "to": b} for j, a, b in self.changes]}

    def line(self, included: bool = False) -> str:
        """The pass in one line; ``included``: the link masses include the drives
        (:attr:`SizingResult.masses_included`)."""
        what = "with the drives' masses on their bodies" if self.weighted else \
            "the link masses as given, the drives in them" if included else "drives weightless"
        pace = f", moves ×{self.time_scale:.4g}" if self.time_scale != 1.0 else ""
        changed = "; ".join(f"{j} {b}" if a is None else f"{j} {a} → {b}" for j, a, b in self.changes)
        return f"  pass {self.number} ({what}{pace}): {changed or 'no change'}"



@dataclass
class SizingResult(Result):
    """The sizing of every driven coordinate of a mechanism for a task: ``joints`` holds a
    :class:`JointSizing` per motor-driven joint and a :class:`~mechatron.drives.cylinders.CylinderSizing` per
    hydraulic cylinder; ``time_scale`` < 1 when the ``time`` objective found the task's moves can run faster.

    ``iterations`` are the passes of the sizing (:class:`Iteration`): the first with weightless drives (all of a
    ``single_pass`` sizing), the next ones with the chosen drives' masses on the bodies that carry them
    (``mounts``, :class:`~mechatron.drives.duty.DriveMount`) until the choice repeats (``converged``; ``cycle``
    names the passes whose choice came back when it cycles instead). ``masses_included``: the mechanism's link masses
    include its drives (:attr:`~mechatron.model.Mechanism.link_masses_include_drives`), so no drive's mass was added
    and pass 1 is the fixed point (:attr:`drive_masses`).

    ``to_frame()``: one row per joint and check (joint, motor, converter, ratio, check, value, limit, unit, margin,
    pass; SI units). ``as_dict()``: mechanism, task, objective, method, converged, feasible, time_scale, task_time
    (s), iterations, totals, joints (each joint's ``as_dict`` with its explanation and ``mounted_on``). ``plot()``:
    one panel per joint, its drive's chart. ``str()``: the report of ``mechatron size``.

    ``given``: the :class:`~mechatron.dynamics.task.Task` sized (:func:`~mechatron.drives.sizing.size` keeps it), so
    that the report shows the task as it was sized — its trajectory and file text — whatever the file holds later.
    """

    mechanism: str
    task: str
    objective: str
    joints: list[DriveSizing]
    time_scale: float = 1.0
    iterations: list[Iteration] = field(default_factory=list)
    single_pass: bool = False
    converged: bool = True
    mounts: dict[str, DriveMount] = field(default_factory=dict)
    cycle: tuple[int, ...] = ()
    task_duration: float | None = None
    masses_included: bool = False
    given: Task | None = field(default=None, repr=False, compare=False)
    #: the braking resistor or regenerative supply of the DC bus (:func:`~mechatron.drives.resistors.size_braking`),
    #: where a resistor catalog or a regenerative supply was given; ``None`` otherwise
    braking: BrakingSupply | None = field(default=None, repr=False, compare=False)

    @property
    def feasible(self) -> bool:
        """Whether every joint has a drive that passes every check, for drives that no longer change."""
        return all(j.feasible for j in self.joints) and self.converged

    @property
    def duration(self) -> float:
        """The task's duration as sized (s): the given one, with the moves × ``time_scale`` for the ``time``
        objective."""
        return self.joints[0].duty.duration if self.joints else 0.0

    @property
    def method(self) -> str:
        """``"single pass"`` (each coordinate sized alone, weightless drives) or ``"fixed point"``."""
        return "single pass" if self.single_pass else "fixed point"

    @property
    def drive_masses(self) -> str:
        """How the chosen drives' masses entered the sizing: ``"weightless"`` (single pass: not at all),
        ``"included"`` (the link masses include them: not added) or ``"added"`` (at their mounts, the fixed point)."""
        return "weightless" if self.single_pass else "included" if self.masses_included else "added"

    def _drive_masses_line(self) -> str:
        """The report's line saying which of :attr:`drive_masses` applied; a cylinder's catalog mass is never added
        (the mechanism file's ``barrel_mass`` and ``rod_mass`` are its cylinders' bodies), and the line says so."""
        if self.drive_masses == "weightless":
            return "drive masses: not added (single pass: the drives weightless)"
        total = self.totals()["drive_mass_kg"]
        chosen = "unknown" if total is None else f"{total:.4g} kg"
        if self.drive_masses == "included":
            return (f"drive masses: included in the link masses of {self.mechanism} (link_masses_include_drives) — "
                    f"not added; the chosen drives weigh {chosen} in all, the link masses as given stand for them")
        passes = f"{len(self.iterations)} pass" + ("es" if len(self.iterations) > 1 else "")
        state = f"fixed point after {passes}" if self.converged else f"no fixed point after {passes}"
        cylinders = [j for j in self.joints if j.kind == "cylinder"]
        if not cylinders:
            return f"drive masses: added at their mounts ({chosen} in all), {state}"
        masses = [j.drive_mass() for j in cylinders]
        weigh = "" if None in masses else f" ({sum(masses):.4g} kg in all)"
        barrels = (f"the cylinders' catalog masses{weigh} are not in the model, which carries the barrel_mass and "
                   f"rod_mass of {self.mechanism}'s cylinder joints as given")
        if not self.mounts:
            return f"drive masses: none added — {barrels}"
        moved = sum(m.mass for m in self.mounts.values())
        return f"drive masses: the motors' added at their mounts ({moved:.4g} kg in all), {state}; {barrels}"

    def critical(self) -> DriveSizing:
        """The joint whose drive has the smallest margin (an infeasible one first)."""
        return min(self.joints, key=lambda j: j.smallest_margin())

    def electrical_balance(self) -> ElectricalBalance | None:
        """The electrical power of the chosen motors over the task, per axis and on a common DC bus
        (:func:`mechatron.drives.electrical.electrical`); ``None`` without a motor."""
        from .electrical import electrical

        return electrical(self) if any(j.kind != "cylinder" for j in self.joints) else None

    def hydraulic_supply(self) -> HydraulicSupply | None:
        """The pump flow and hydraulic power of the chosen cylinders over the task at the system pressure
        (:func:`mechatron.drives.hydraulics.hydraulic_supply`); ``None`` without a cylinder."""
        from .hydraulics import hydraulic_supply

        return hydraulic_supply(self) if any(j.kind == "cylinder" for j in self.joints) else None

    def totals(self) -> dict:
        """The sums over the drives (SI units; ``None`` where they do not apply or a catalog lacks the data), named
        as in :mod:`mechatron.quantities`:

        - drive_mass_kg and drive_cost: the chosen drives' catalog masses and prices;
        - energy_per_cycle_J: the energy drawn from the supplies per cycle, ∫ max(P_bus, 0) dt of the common DC
          bus (P_bus = Σ (T_m n + R I²), :mod:`~mechatron.drives.electrical`) plus the pump's ∫ p Q dt, p(t) the
          pressure the loads need (0 where a load drives its cylinder; :mod:`~mechatron.drives.hydraulics`);
        - peak_bus_power_W: max P_bus; regenerated_energy_J: ∫ max(−P_bus, 0) dt, the braking energy per cycle;
          braking_resistor_peak_W and braking_resistor_continuous_W: max(−P_bus) and the regenerated energy over
          the cycle time;
        - peak_pump_power_W and peak_pump_flow_m3_s: max p(t) Q(t) and max Q;
        - cycle_time_s: the task's duration as sized."""
        masses = [j.drive_mass() for j in self.joints]
        prices = [j.drive_price() for j in self.joints]
        balance, supply = self.electrical_balance(), self.hydraulic_supply()
        bus = balance.bus() if balance else None
        pump = supply.rows()[-1] if supply else None
        extra = {} if self.braking is None else {"braking_supply": self.braking.as_dict()}
        return {**extra, "drive_mass_kg": None if None in masses else float(sum(masses)),
                "drive_cost": None if None in prices else float(sum(prices)),
                "energy_per_cycle_J": (bus["energy_drawn"] if bus else 0.0) + (pump["energy"] if pump else 0.0),
                "peak_bus_power_W": bus["peak_power"] if bus else None,
                "regenerated_energy_J": bus["energy_regenerated"] if bus else None,
                "braking_resistor_peak_W": bus["peak_braking_power"] if bus else None,
                "braking_resistor_continuous_W": bus["continuous_braking_power"] if bus else None,
                "peak_pump_power_W": pump["peak_power"] if pump else None,
                "peak_pump_flow_m3_s": pump["peak_flow"] if pump else None,
                "cycle_time_s": self.duration}

    def _totals_lines(self) -> list[str]:
        totals = self.totals()

        def number(key: str, unit: str) -> str:
            return "unknown" if totals[key] is None else f"{readable(totals[key])}{unit}"

        lines = [f"totals: drive mass {number('drive_mass_kg', ' kg')}, cost {number('drive_cost', '')}, energy drawn "
                 f"per cycle {number('energy_per_cycle_J', ' J')}"]
        if totals["peak_bus_power_W"] is not None:
            lines.append(f"  common DC bus: peak {number('peak_bus_power_W', ' W')}; braking resistor peak "
                         f"{number('braking_resistor_peak_W', ' W')}, continuous "
                         f"{number('braking_resistor_continuous_W', ' W')} ({number('regenerated_energy_J', ' J')} "
                         "regenerated per cycle; P = T·n + R·I²)")
        if self.braking is not None:
            lines.append(self.braking.line())
        if totals["peak_pump_power_W"] is not None:
            pump = self.hydraulic_supply().rows()[-1]
            lines.append(f"  pump: peak flow {totals['peak_pump_flow_m3_s'] * 6e4:.4g} l/min, peak power "
                         f"{number('peak_pump_power_W', ' W')}, {readable(pump['energy'])} J per cycle (P = p·Q at "
                         f"the pressure the loads need; {readable(pump['energy_at_relief'])} J at the relief "
                         "pressure)")
        return lines

    def to_frame(self) -> pd.DataFrame:
        """One row per joint and check (:data:`~mechatron.drives.report.COLUMNS`), SI units."""
        return pd.DataFrame([row for j in self.joints for row in j.rows()], columns=list(COLUMNS))

    def _mounted_on(self, joint: str) -> dict | None:
        mount = self.mounts.get(joint)
        return None if mount is None else {"body": mount.carrier, "mass_kg": mount.mass,
                                            "loads_the_mechanism": mount.parent > 0 and not self.masses_included}

    def as_dict(self) -> dict:
        """mechanism, task, objective, method (``fixed point`` or ``single pass``), drive_masses (:attr:`drive_masses`:
        ``added``, ``included`` or ``weightless``), converged, cycle, feasible,
        time_scale, task_time (the task's duration as sized, s), iterations (every pass: iteration, drive_masses,
        time_scale, changes: joint, from, to), totals (:meth:`totals`) and joints (every joint's ``as_dict`` with
        deciding_check, runner_up, drive_mass_kg, drive_price and mounted_on: body, mass_kg, loads_the_mechanism),
        electrical (:meth:`electrical_balance`, per axis and the DC bus) and hydraulics (:meth:`hydraulic_supply`,
        per cylinder and the pump), ``None`` where there is no motor or cylinder; JSON-ready."""
        balance, supply = self.electrical_balance(), self.hydraulic_supply()
        return json_ready({"mechanism": self.mechanism, "task": self.task, "objective": self.objective,
                           "method": self.method, "drive_masses": self.drive_masses, "converged": self.converged,
                           "cycle": list(self.cycle),
                           "feasible": self.feasible, "time_scale": self.time_scale,
                           "task_time": self.duration if self.joints else None,
                           "iterations": [i.as_dict() for i in self.iterations], "totals": self.totals(),
                           "electrical": None if balance is None else balance.as_dict(),
                           "hydraulics": None if supply is None else supply.as_dict(),
                           "joints": [{**j.as_dict(), **j.explanation(), "mounted_on": self._mounted_on(j.joint)}
                                      for j in self.joints]})

    def plot(self, ax: Axes | None = None) -> Figure:
        """The chart of every joint's drive, one panel each (motors: speed–torque zones and operating points;
        cylinders: force over speed with the push and pull limits). Given ``ax``, the chart of the
        :meth:`critical` joint is drawn into it."""
        if ax is not None:
            return self.critical().plot(ax)
        from ..report.figures import new_figure

        columns = min(3, len(self.joints))
        rows = -(-len(self.joints) // columns)
        figure = new_figure(5.5 * columns, 4.2 * rows)
        panels = figure.subplots(rows, columns, squeeze=False).ravel()
        for joint, panel in zip(self.joints, panels):
            joint.plot(panel)
        for panel in panels[len(self.joints):]:
            figure.delaxes(panel)
        figure.suptitle(f"{self.mechanism}: drives for '{self.task}'" + ("" if self.feasible else " — NOT FEASIBLE"))
        return figure

    def save_plots(self, directory: str | Path) -> list[Path]:
        """Every joint's chart (:meth:`DriveSizing.plot`) as ``<directory>/<mechanism>_<joint>.png`` and its data
        (:meth:`DriveSizing.chart_frame`) as ``<directory>/<mechanism>_<joint>.csv``; the directory is created if
        needed. The files are written whole and all together (:func:`mechatron.io.output.write_folder`), and the
        charts (and their data) an earlier call for the same mechanism wrote there for joints no longer sized are
        removed. Returns the files written."""
        from ..io.output import write_folder

        files: dict = {}
        for j in self.joints:
            files[f"{self.mechanism}_{j.joint}.png"] = j.plot
            files[f"{self.mechanism}_{j.joint}.csv"] = j.chart_frame
        return write_folder(directory, files, owner=f"mechatron size {self.mechanism}")

    def _method_lines(self) -> list[str]:
        if self.single_pass:
            return ["method: single pass — each coordinate sized alone, its drive's mass loading no other joint",
                    self._drive_masses_line()]
        if self.masses_included:
            head = ("method: fixed point — the link masses include the drives, so no drive's mass is added and one "
                    "pass, with the link masses as given, is the fixed point (the choice of --single-pass)")
        elif not self.converged:
            what = (f"the choice of pass {self.cycle[-1]} repeats that of pass {self.cycle[0]}: it cycles"
                    if self.cycle else f"the choice still changed after {len(self.iterations)} passes")
            head = f"method: fixed point — NOT CONVERGED: {what}"
        elif not self.mounts:
            head = ("method: fixed point — no motor to place (the cylinders' masses are the mechanism's own), so one "
                    "pass is the fixed point")
        elif len(self.iterations) == 1:
            head = ("method: fixed point — every drive sits on a fixed body, so the drives' masses load no joint "
                    "and one pass is the fixed point")
        else:
            head = (f"method: fixed point — every chosen motor and gearbox is a mass on the body that carries it; "
                    f"sized distal to proximal until the choice repeats: converged in {len(self.iterations)} "
                    "passes")
        return [head, self._drive_masses_line(), *(i.line(self.masses_included) for i in self.iterations)]

    def __str__(self) -> str:
        """The method and its passes, the chosen drive of every joint with every check, margin and PASS/FAIL, why
        it was chosen, where it sits, the totals and the verdict."""
        duration = self.duration
        lines = [f"{self.mechanism}: drive sizing for '{self.task}' ({duration:.3f} s, objective {self.objective})"]
        if self.objective == "time":
            lines.append(f"fastest feasible pace: the moves replayed ×{self.time_scale:.3f} in time, the dwells kept "
                         f"({duration:.3f} s instead of {self.task_duration or duration:.3f} s)")
        schedule = getattr(self.given, "schedule", None)
        if schedule is not None:
            lines.append(f"payload: {schedule.mass:g} kg at {schedule.frame}, {schedule.label}")
        lines += self._method_lines()
        for j in self.joints:
            lines += [""] + j.lines()
            mount = self.mounts.get(j.joint)
            if mount is not None:
                lines.append(f"    on {mount.carrier}: {mount.mass:.3g} kg" + (
                    " (a fixed body: it loads no joint)" if mount.parent == 0 else
                    " (included in the link masses: not added)" if self.masses_included else ""))
        lines += ["", *self._totals_lines()]
        if self.feasible:
            verdict = "every joint has a feasible drive"
        elif not self.converged:
            verdict = "NOT FEASIBLE: the choice of drives did not settle (see the method above)"
        else:
            verdict = "NOT FEASIBLE: no drive passes every check for " + ", ".join(
                j.joint for j in self.joints if not j.feasible)
        return "\n".join(lines + ["", verdict])

    def report(self, mechanism: Mechanism | None = None, task: Task | str | Path | None = None, **context) -> Report:
        """The HTML report (:mod:`mechatron.report.html`): the method, every joint's drive and the check deciding it,
        per joint every check, the best alternatives (the closest drives when none is feasible) and its chart; given
        ``mechanism`` the task and the mechanism at its binding pose: the sample where the :meth:`critical` joint is
        most loaded (:meth:`~mechatron.drives.report.DriveSizing.binding_sample`: a motor's largest |τ|, a
        cylinder's pose where its deciding check binds). The task is the one sized (:attr:`given`), its file's text
        shown as it was read unless ``task`` names that file (the inputs show it then); a sizing without one reads
        ``task`` (a :class:`~mechatron.dynamics.task.Task` or a file; default the mechanism's default task)."""
        from ..kinematics.drawing import configuration_figure
        from ..kinematics.loops import assemble
        from ..report.html import Chart, Code, Method, Report, Section, Table, Text
        from . import checks, cylinders, duty, electrical, hydraulics, joint

        lines = str(self).splitlines()
        kinds = {j.kind for j in self.joints}
        texts = [joint.__doc__, duty.__doc__] + [checks.__doc__] * bool(kinds - {"cylinder"}) \
            + [cylinders.__doc__] * ("cylinder" in kinds)
        def drive_row(j: DriveSizing) -> dict:
            deciding, mount = j.deciding(), self._mounted_on(j.joint)
            return {"joint": j.joint, "drive": j.headline(), "feasible": j.feasible,
                    "smallest margin": j.smallest_margin(), "deciding check": deciding.name if deciding else "",
                    "drive mass (kg)": j.drive_mass(), "price": j.drive_price(),
                    "on body": mount["body"] if mount else "",
                    "runner-up": " | ".join(f"{r['candidate']}: {r['reason']}" for r in j.runner_up())}

        drives = pd.DataFrame([drive_row(j) for j in self.joints])
        servo = [getattr(j, "drive", None) for j in self.joints]
        if any(servo):  # the chosen servo drive next to the motor
            drives.insert(2, "servo drive", [d or "" for d in servo])
        totals = pd.DataFrame([{"quantity": k, "value": v if k != "braking_supply" else self.braking.line().strip()}
                               for k, v in self.totals().items()])
        iterations = pd.DataFrame([{"pass": i.number, "drives' masses": i.weighted, "moves ×": i.time_scale,
                                    "changes": i.line(self.masses_included).split(": ", 1)[1]}
                                   for i in self.iterations])
        sections = [Section("Method", [Method(text) for text in texts]), Section(
            "Drives", [Text(line) for line in lines[1:lines.index("")]] + [
                Table(drives, "the chosen drive of every joint, the check deciding it and the runners-up", "drives"),
                Table(iterations, "the passes of the sizing", "iterations"),
                Table(totals, "totals (kg, the catalogs' currency, J, W, s)", "totals")])]
        for title, supply, module in (("Electrical", self.electrical_balance(), electrical),
                                      ("Hydraulic supply", self.hydraulic_supply(), hydraulics)):
            if supply is not None:
                table = Table(supply.to_frame(), "SI units (J, W, A, V; m³/s, m³)", title.lower())
                sections.append(Section(title, [Method(module.__doc__), table, Chart(supply.plot())]))
        for j in self.joints:
            checks_table = Table(_in_rpm(j.to_frame()[["check", "value", "limit", "unit", "margin", "pass"]]),
                                 "every check (SI, speeds in rpm as in the text report; margin = 1 − value/limit)",
                                 f"checks {j.joint}")
            alternatives = Table(j.ranking.head(REPORTED) if j.feasible else j.closest,
                                 "the best feasible drives" if j.feasible else
                                 "the closest drives and the checks they fail", f"alternatives {j.joint}")
            ahead = "cheaper" if getattr(j, "objective", "") == "cost" else "lighter"
            rejected = [Table(j.rivals, f"the {ahead} catalog rows rejected, nearest first, each with the checks it "
                              "fails (load factor = value/limit); rated pressure and stroke: pass/fail filters (rating "
                              "≥ relief pressure, stroke ≤ the row's longest)", f"rejected {j.joint}")] \
                if j.kind == "cylinder" and len(j.rivals) else []
            sections.append(Section(f"Joint {j.joint}", [
                Text(j.headline()), *(Text(line.strip()) for line in j.explanation_lines()), checks_table,
                alternatives, *rejected, Chart(j.plot())]))
        if mechanism is not None:
            given, task = task, self._task(mechanism, task)
            if task.name != self.task:
                raise InputError(f"the report of a sizing for the task '{self.task}' needs that task, not "
                                 f"'{task.name}'")
            loaded, trajectory = self.critical(), task.trajectory
            k, carried = loaded.binding_sample()
            if len(trajectory.t) != len(loaded.duty.t):  # resampled: the same fraction of the task
                k = int(np.argmin(np.abs((trajectory.t - trajectory.t[0]) / trajectory.duration
                                         - (loaded.duty.t[k] - loaded.duty.t[0]) / loaded.duty.duration)))
            q = assemble(mechanism, dict(zip(trajectory.names, trajectory.q[k]))) if mechanism.closures else \
                trajectory.q[k] if trajectory.q.shape[1] == mechanism.nq else \
                mechanism.configuration(trajectory.coordinates[k])
            where = f"t = {trajectory.t[k]:.4g} s of the task as given, where {loaded.joint} (the smallest margin) " \
                f"{carried}"
            frame = mechanism.tool_frame if mechanism.tool_frame in mechanism.frame_names else None
            loads = [Table(pd.DataFrame([{"frame": load.frame, **dict(zip(("Fx (N)", "Fy (N)", "Fz (N)"), load.force)),
                                          **dict(zip(("Mx (N·m)", "My (N·m)", "Mz (N·m)"), load.moment))}
                                         for load in task.loads]), "the task's constant loads (world axes)", "loads")
                     ] if task.loads else []
            sections += [Section("Task", [Text(f"{task.name} ({task.source}): payload {task.payload:g} kg"
                                              + (f", {task.schedule.label}" if task.schedule else "")), Table(
                pd.DataFrame(trajectory.as_dict()["coordinates"]), f"{trajectory.duration:.4g} s as given (SI)",
                "task"), *loads] + ([Code(task.text)] if given is None and task.text else [])),
                Section("Binding pose", [Text(where), Chart(configuration_figure(
                    mechanism, q, frame=frame, title=f"{mechanism.name} at t = {trajectory.t[k]:.4g} s"))])]
        return Report(lines[0], sections, lines[-1])

    def _task(self, mechanism: Mechanism, task: Task | str | Path | None) -> Task:
        """The task of the report: ``task`` when it is a Task; the one sized when ``task`` is ``None`` or names the
        file it was read from; else ``task`` read for ``mechanism`` (``None``: its default task)."""
        from ..dynamics.task import Task, default_task, read_task

        if isinstance(task, Task):
            return task
        kept = self.given
        if kept is not None and (task is None or (kept.source and Path(task).resolve() == Path(kept.source).resolve())):
            return kept
        return default_task(mechanism) if task is None else read_task(task, mechanism)


def _in_rpm(checks: pd.DataFrame) -> pd.DataFrame:
    """The checks with their speeds (rad/s) in rpm, as the text report gives them (n = 60 ω / 2π)."""
    checks = checks.copy()
    speed = checks["unit"] == "rad/s"
    checks.loc[speed, ["value", "limit"]] = checks.loc[speed, ["value", "limit"]].astype(float) * 30 / math.pi
    checks.loc[speed, "unit"] = "rpm"
    return checks
