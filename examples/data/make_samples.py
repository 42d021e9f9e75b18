"""Write the three sample trajectories of this folder (run once from the top of the source tree):

    python examples/data/make_samples.py

- ``puma560_move.csv``: the PUMA 560 from its nominal pose to a pose over the table and back, quintic profile
  (smooth: continuous acceleration), 0.3 s rest in between; columns ``t`` and the joints only, so that a reader
  differentiates the positions;
- ``scara_move.csv``: the SCARA from its zero pose to a place position with the quill lowered by 0.15 m and back,
  jerk-limited (double-S) profile [Biagiotti, 3.4]; every column that ``Trajectory.to_csv`` writes (``t``, the
  joints, ``qd_<joint>``, ``qdd_<joint>``);
- ``planar_2r_move.csv``: the textbook's planar 2R arm [Egorov, fig. 4.7] from (0, 0) to (0.5, −1.0) rad in 1 s,
  quintic profile, sampled every 0.1 s: the short complete example of ``docs/trajectory_csv.md``.

All use the joint names of the robot files (``q1`` … ``qn``), radians for revolute joints and metres for the SCARA
quill.
"""

from pathlib import Path

import numpy as np

import mechatron
from mechatron.dynamics.motion import cycle, move

HERE = Path(__file__).resolve().parent


def puma560_move():
    puma = mechatron.load("puma560")
    start = np.radians([0, 45, -180, 0, 45, 0])
    end = np.radians([60, 20, -150, 45, 60, 90])
    return cycle(puma, [start, end, start], profile="quintic", dwell=0.3, dt=0.01,
                 vmax=np.radians([90, 90, 90, 180, 180, 180]), amax=np.radians([180, 180, 180, 360, 360, 360]))


def scara_move():
    scara = mechatron.load("scara")
    start = np.array([0.0, 0.0, 0.0, 0.0])
    end = np.array([np.radians(60), np.radians(-90), 0.15, np.radians(90)])
    return cycle(scara, [start, end, start], profile="scurve", dwell=0.2, dt=0.01,
                 vmax=[3.0, 4.0, 0.8, 8.0], amax=[15.0, 20.0, 5.0, 40.0], jmax=[150.0, 200.0, 50.0, 400.0])


def planar_2r_move():
    arm = mechatron.load("planar_2r")
    return move(arm, [0.0, 0.0], [0.5, -1.0], profile="quintic", duration=1.0, dt=0.1, vmax=100.0, amax=1000.0)


def write(trajectory, name: str, columns=None, digits: int = 10) -> None:
    frame = trajectory.to_frame()
    frame = frame[columns] if columns else frame
    (frame + 0.0).to_csv(HERE / name, index=False, float_format=f"%.{digits}g")  # + 0.0: no "-0" in the file


def main() -> None:
    puma = puma560_move()
    write(puma, "puma560_move.csv", ["t", *puma.names])
    write(scara_move(), "scara_move.csv")
    write(planar_2r_move(), "planar_2r_move.csv", digits=6)


if __name__ == "__main__":
    main()
