"""URDF export: the written file, loaded back by Pinocchio's own parser, gives the same frame placements, mass matrix
and RNEA torques. Drives travel in an SRDF <rotor_params> file that pinocchio.loadRotorParameters reads."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from conftest import DH_ROBOTS, random_state

import mechatron
from mechatron.cli import main
from mechatron.model.dh import DHLink, DHTable, Inertial, dh_mechanism
from mechatron.model.urdf import export_urdf


def reload_with_pinocchio(files):
    model = pin.buildModelFromUrdf(str(files[0]))
    if len(files) > 1:
        pin.loadRotorParameters(model, str(files[1]), False)
    return model


def assert_same_mechanics(mech, model, rng, samples=20):
    data = model.createData()
    names = [f.name for f in mech.model.frames if f.type in (pin.FrameType.OP_FRAME, pin.FrameType.BODY)]
    assert "tool" in names
    for _ in range(samples):
        q, v, a = random_state(mech, rng)
        pin.framesForwardKinematics(mech.model, mech.data, q)
        pin.framesForwardKinematics(model, data, q)
        for name in names:
            other = next(i for i, f in enumerate(model.frames) if f.name == name and f.type == pin.FrameType.BODY)
            np.testing.assert_allclose(data.oMf[other].homogeneous, mech.data.oMf[mech.frame_id(name)].homogeneous,
                                       atol=1e-12, err_msg=name)
        M_ours = pin.crba(mech.model, mech.data, q)
        M_back = pin.crba(model, data, q)
        np.testing.assert_allclose(np.triu(M_back), np.triu(M_ours), atol=1e-12)
        np.testing.assert_allclose(pin.rnea(model, data, q, v, a), pin.rnea(mech.model, mech.data, q, v, a),
                                   atol=1e-10)


@pytest.mark.parametrize("name", DH_ROBOTS + ["ur5"])
def test_round_trip(tmp_path, rng, name):
    mech = mechatron.load(name)
    files = export_urdf(mech, tmp_path / f"{name}.urdf")
    model = reload_with_pinocchio(files)
    assert model.nq == mech.nq
    assert list(model.names) == list(mech.model.names)
    np.testing.assert_allclose(model.armature, mech.model.armature, rtol=1e-14)
    np.testing.assert_allclose(model.lowerPositionLimit, mech.model.lowerPositionLimit)
    assert_same_mechanics(mech, model, rng)


def test_puma_drives_go_to_srdf(tmp_path):
    files = export_urdf(mechatron.load("puma560"), tmp_path / "puma.urdf")
    assert [f.suffix for f in files] == [".urdf", ".srdf"]
    assert "rotor_params" in files[1].read_text()
    # mechatron's own URDF loader picks the SRDF up: the armature survives a second round
    again = mechatron.load(files[0])
    np.testing.assert_allclose(again.model.armature, mechatron.load("puma560").model.armature, rtol=1e-14)


def test_modified_dh_with_random_geometry_round_trips(tmp_path, rng):
    links = tuple(DHLink("prismatic" if i == 1 else "revolute", a=rng.uniform(-0.4, 0.4),
                         alpha=rng.uniform(-3, 3), d=rng.uniform(-0.3, 0.3), theta=rng.uniform(-3, 3),
                         lower=-1.0, upper=1.0,
                         inertial=Inertial(rng.uniform(0.5, 2), rng.uniform(-0.1, 0.1, 3),
                                           np.diag(rng.uniform(0.02, 0.04, 3))))
                  for i in range(4))
    mech = dh_mechanism(DHTable(links, convention="modified"), "random_mdh")
    assert_same_mechanics(mech, reload_with_pinocchio(export_urdf(mech, tmp_path / "r.urdf")), rng)


def test_command_line_export(tmp_path, capsys):
    out = tmp_path / "scara.urdf"
    assert main(["export-urdf", "scara", "-o", str(out), "--set", "a1=0.35"]) == 0
    assert "wrote" in capsys.readouterr().out
    model = pin.buildModelFromUrdf(str(out))
    data = model.createData()
    pin.framesForwardKinematics(model, data, np.zeros(4))
    tool = next(i for i, f in enumerate(model.frames) if f.name == "tool" and f.type == pin.FrameType.BODY)
    # SCARA at zero: reach a1 + a2 = 0.35 + 0.275 along x, height d1 − d4 = 0.4 − 0.05
    np.testing.assert_allclose(data.oMf[tool].translation, [0.625, 0.0, 0.35], atol=1e-12)
