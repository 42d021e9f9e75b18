"""The ranking and the rivals of a joint's choice are found when first asked for (the sizing needs only the chosen
pair): the chosen pair is the ranking's first for every objective, and a pickled result (a study's worker sends
its results to the scheduler) still gives them, the same."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

import mechatron
from mechatron.drives.catalogs import default_catalog
from mechatron.drives.duty import joint_duties
from mechatron.drives.sizing import size_joint
from mechatron.dynamics.task import read_task, task_file


@pytest.fixture(scope="module")
def duties():
    puma = mechatron.load("puma560")
    return joint_duties(puma, read_task(task_file(puma), puma).trajectory)


@pytest.mark.parametrize("objective", ["mass", "cost", "margin"])
def test_the_choice_is_the_first_of_the_ranking(duties, objective):
    motors, gearboxes = default_catalog("motors"), default_catalog("gearboxes")
    for duty in duties:
        joint = size_joint(duty, motors, gearboxes, objective=objective)
        assert joint.feasible
        first = joint.ranking.iloc[0]
        assert (first["motor"], first["converter"]) == (joint.motor, joint.converter)
        assert first["mass"] == pytest.approx(joint.drive_mass(), rel=1e-12)
        assert 1 - max(c.value / c.limit for c in joint.checks if c.limit > 0) == pytest.approx(
            first["smallest_margin"], rel=1e-9, abs=1e-12)


def test_a_pickled_result_gives_the_same_ranking_rivals_and_report():
    result = mechatron.size(mechatron.load("puma560"))
    copy = pickle.loads(pickle.dumps(result))
    for a, b in zip(result.joints, copy.joints):
        assert a.ranking.equals(b.ranking) and a.rivals.equals(b.rivals)
        assert len(a.ranking) >= 5
    assert str(copy) == str(result)
    np.testing.assert_allclose(copy.to_frame()["value"], result.to_frame()["value"], rtol=1e-12)
