"""Transmission ratios of the cylindrical robot of [Egorov, fig. 4.8] by the formulas of [Egorov, section 4.4], side
by side with the numerical optimum of the same move model (CasADi), and the move time against the ratio for every
joint.

    python examples/cylindrical_robot_ratios.py [--motor SM60-0.64-30] [--payload 2] [--plot FILE]

Joint q1 turns the column (rotary: u in rad/rad, [Egorov, 4.65]); q2 lifts the carriage and q3 extends the arm
through ball screws (rotary→linear: u = 2π/lead in rad/m, [Egorov, 4.70]). Every joint uses the same motor: Ω_d its
rated speed, J_d = 1.2 J_rotor [Egorov, 4.67], M_i its peak torque (half of it on the vertical q2, the other half
holds the weight); γ = γ_max/2 [Egorov, 4.64]; the load inertia P_h is the largest the joint sees (the mass matrix
over the workspace). The columns (4.63) and (4.66) of the printed table are those equations of [Egorov].
"""

from __future__ import annotations

import argparse
import math

import numpy as np
from matplotlib.figure import Figure

import mechatron
from mechatron.drives.catalogs import default_catalog
from mechatron.drives.ratio import motor_side_inertia, move_time, optimal_ratio, textbook_ratio
from mechatron.dynamics.tree import mass_matrix
from mechatron.io.output import save_figure
from mechatron.model.payload import with_payload


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--motor", default="SM60-0.64-30", help="motor key in catalogs/servo_motors.csv")
    parser.add_argument("--payload", type=float, default=2.0, help="payload at the gripper (kg)")
    parser.add_argument("--plot", default="cylindrical_ratios.png")
    args = parser.parse_args()

    motors = default_catalog("motors").set_index("key")
    if args.motor not in motors.index:
        raise SystemExit(f"unknown motor {args.motor!r}")
    motor = motors.loc[args.motor]
    robot = with_payload(mechatron.load("cylindrical_rpp"), args.payload)
    lower, upper = robot.model.lowerPositionLimit, robot.model.upperPositionLimit
    grid = np.array([[0.0, q2, q3] for q2 in np.linspace(lower[1], upper[1], 5)
                     for q3 in np.linspace(lower[2], upper[2], 7)])
    inertia = np.diagonal(mass_matrix(robot, grid), axis1=1, axis2=2).max(axis=0)
    screws = default_catalog("linear")
    speed, rotor, peak = motor["rated_speed"], motor["rotor_inertia"], motor["peak_torque"]
    drive = motor_side_inertia(rotor)
    print(f"motor {args.motor}: Ω_d = {speed:.1f} rad/s, J_rotor = {rotor:.3g} kg·m² (J_d = {drive:.3g}), "
          f"T_peak = {peak:g} N·m; payload {args.payload:g} kg\n")
    joints = [("q1", "rad", 0.95, peak), ("q2", "m", 0.9, peak / 2), ("q3", "m", 0.9, peak)]
    fig = Figure(figsize=(12, 4), layout="constrained")
    axes = fig.subplots(1, 3)
    header = (f"{'joint':<6}{'P_h':>9}{'γ':>8}{'(4.63)':>10}{'(4.66)':>8}  {'book':<18}{'optimum':>10}"
              f"{'t book':>9}{'t opt':>9}")
    print(header)
    for (name, unit, eta, effort), ax in zip(joints, axes):
        k = robot.joint_names.index(name)
        gamma = (upper[k] - lower[k]) / 2  # [Egorov, 4.64]
        load = inertia[k]
        book = textbook_ratio(speed, load, gamma, effort, rotor, eta)
        best, t_best = optimal_ratio(speed, load, gamma, effort, eta, drive)
        t_book = move_time(book.ratio, speed, load, gamma, effort, eta, drive)
        rule = "min. time" if book.rule.startswith("minimum") else "inertia matching"
        print(f"{name:<6}{load:>9.4g}{gamma:>8.3f}{book.minimum_time:>10.4g}{book.dominance:>8.3f}  "
              f"{rule + f' {book.ratio:.4g}':<18}{best:>10.4g}{t_book:>9.4f}{t_best:>9.4f}")
        if unit == "m":
            lead = 2 * math.pi / best
            screws = screws[screws["type"] == "ball screw"]
            nearest = screws.iloc[int(np.argmin(np.abs(screws["lead"] - lead)))]
            print(f"{'':6}→ screw lead 2π/u = {lead * 1e3:.2f} mm (catalog: {nearest['key']}, "
                  f"{nearest['lead'] * 1e3:g} mm)")
        ratios = np.geomspace(best / 8, best * 8, 400)
        ax.plot(ratios, [move_time(u, speed, load, gamma, effort, eta, drive) for u in ratios])
        ax.axvline(book.ratio, color="tab:red", ls="--", label=f"book: {rule} {book.ratio:.3g}")
        ax.axvline(best, color="tab:green", label=f"optimum {best:.3g}")
        ax.set_xscale("log")
        ax.set_xlabel(f"u ({'rad/rad' if unit == 'rad' else 'rad/m'})")
        ax.set_ylabel(f"move time over γ = {gamma:.3g} {unit} (s)")
        ax.set_title(f"{name}: P_h = {load:.3g} {'kg·m²' if unit == 'rad' else 'kg'}")
        ax.grid(True, alpha=0.3, which="both")
        ax.legend(fontsize=8)
    print("\nThe column (4.66) is J_h/(u² J_d) at the minimum-time ratio [Egorov, 4.66]. The numerical optimum equals "
          "[Egorov, 4.63] while the move reaches the motor's speed limit (J_h/(u² J_d) ≥ η) and √(J_h/(η J_d)) "
          "otherwise; the book switches at 1 and drops η from [Egorov, 4.69].")
    fig.suptitle(f"cylindrical robot, motor {args.motor}: move time against the ratio")
    save_figure(fig, args.plot)  # whole or not at all (110 dpi)
    print(f"wrote {args.plot}")


if __name__ == "__main__":
    main()
