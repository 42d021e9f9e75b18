"""Write ``measurements_puma560.csv``: a PUMA 560 "as built", measured by a simulated laser tracker with a 6-D probe
(run once from the top of the source tree):

    python examples/data/make_calibration_puma560.py

The machine as built differs from ``robots/puma560.toml`` by the offsets in :data:`BUILT` (a2 +0.4 mm, d3 −0.3 mm,
d4 +0.2 mm, α2 +0.01°, α3 −0.008°) and by encoder zeros off by 0.02° (q2) and −0.015° (q3): the model's joint angle
is the encoder's reading plus the offset. At 50 random poses within the joint limits (seeded) the file holds the
encoder readings (degrees), the tool position (mm) and roll–pitch–yaw (degrees) of the built machine, each with
seeded normal noise: σ = 0.02 mm on every position axis, 0.0005° on every angle. ``mechatron calibrate puma560
--measurements examples/data/measurements_puma560.csv --parameters a2,d3,d4,alpha2,alpha3,q2,q3`` recovers them.
"""

from pathlib import Path

import numpy as np
import pinocchio as pin

import mechatron

HERE = Path(__file__).resolve().parent
#: The built machine's parameters (m, rad): nominal + offset.
BUILT = {"a2": 0.4318 + 0.4e-3, "d3": 0.15005 - 0.3e-3, "d4": 0.4318 + 0.2e-3,
         "alpha2": np.radians(0.01), "alpha3": np.radians(-90 - 0.008)}
#: Encoder offsets (rad): q_model = q_read + offset.
OFFSETS = {"q2": np.radians(0.02), "q3": np.radians(-0.015)}
POSES, SEED = 50, 2026
SIGMA_MM, SIGMA_DEG = 0.02, 0.0005


def measurements(seed: int = SEED, count: int = POSES) -> str:
    """The CSV text of the measurements."""
    puma = mechatron.load("puma560")
    built = puma.with_parameters(BUILT)
    rng = np.random.default_rng(seed)
    read = puma.random_configuration(rng, size=count)
    lines = ["# A PUMA 560 as built, measured by a simulated laser tracker (make_calibration_puma560.py beside it):",
             "# encoder readings (deg), tool position (mm) and roll-pitch-yaw (deg), noise 0.02 mm and 0.0005 deg.",
             "label,q1_deg,q2_deg,q3_deg,q4_deg,q5_deg,q6_deg,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg,sigma_mm,"
             "sigma_rot_deg"]
    for i, q in enumerate(read, start=1):
        true = q.copy()
        for name, offset in OFFSETS.items():
            true[puma.joint_names.index(name)] += offset
        placement = mechatron.frame_placement(built, true, "tool")
        position = placement.translation * 1e3 + rng.normal(0.0, SIGMA_MM, 3)
        rpy = np.degrees(pin.rpy.matrixToRpy(placement.rotation)) + rng.normal(0.0, SIGMA_DEG, 3)
        cells = [f"p{i}", *(f"{v:.6f}" for v in np.degrees(q)), *(f"{v:.5f}" for v in position),
                 *(f"{v:.6f}" for v in rpy), f"{SIGMA_MM:g}", f"{SIGMA_DEG:g}"]
        lines.append(",".join(cells))
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    (HERE / "measurements_puma560.csv").write_text(measurements())
    print(f"wrote {HERE / 'measurements_puma560.csv'}")
