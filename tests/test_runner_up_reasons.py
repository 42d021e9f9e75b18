"""The runners-up of a sizing say why they lost in words, never ``×inf`` (issue 22, item 9).

An infinite load factor is a value where the limit is 0 — the speed–torque curve at a speed above the motor's
maximum, where it gives no torque — and no multiple of the limit would do: the reason says what it means.
"""

from __future__ import annotations

import json
import math

from mechatron.cli import main
from mechatron.drives.checks import ALL_CHECKS, NO_LIMIT, failure, failures
from mechatron.drives.cylinders import CYLINDER_CHECKS


def test_the_fastest_puma_names_the_curve_it_leaves_in_words(capsys):
    assert main(["size", "puma560", "--single-pass", "--objective", "time", "--json"]) == 0
    joints = json.loads(capsys.readouterr().out)["joints"]
    reasons = [r["reason"] for j in joints for r in j["runner_up"]]
    assert reasons and not any("inf" in reason for reason in reasons)
    assert any("speed-torque curve: outside it (torque asked above the motor's maximum speed); " in reason
               and ("RMS torque ×" in reason or "winding temperature rise ×" in reason)
               for reason in reasons)  # the shipped motors' heat: their thermal model


def test_a_finite_load_factor_is_the_factor_and_an_infinite_one_words():
    assert failure("peak torque", 1.1749) == "peak torque ×1.17"
    assert failure("RMS torque", math.inf) == ("RMS torque: no continuous torque at the mean speed (above the motor's "
                                               "maximum speed)")
    assert failure("rod buckling", math.inf) == f"rod buckling: {NO_LIMIT}"
    factors = [0.5, math.inf, 1.0] + [0.0] * (len(ALL_CHECKS) - 3)
    assert failures(ALL_CHECKS, factors) == "speed-torque curve: outside it (torque asked above the motor's maximum " \
                                            "speed)"
    assert failures(CYLINDER_CHECKS, [1.0 + 1e-12, 0.2, 2.0, 0.0, 0.0]) == "pull pressure ×2.00"
    assert failures(CYLINDER_CHECKS, [0.0] * 5) == "none"
