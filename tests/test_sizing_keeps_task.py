"""A sizing keeps the task it sized (SizingResult.given): its HTML report shows that task — its payload, its
trajectory, its file's text as read — even when the file changed or went away after the sizing, and refuses a task
of another name."""

from __future__ import annotations

import numpy as np
import pytest

import mechatron
from mechatron.dynamics.task import task_file
from mechatron.errors import InputError
from mechatron.report.html import Code, Table, Text


def sections(report) -> dict:
    return {s.title: s.items for s in report.sections}


@pytest.fixture(scope="module")
def sized(tmp_path_factory):
    puma = mechatron.load("puma560")
    path = tmp_path_factory.mktemp("task") / "pick.toml"
    text = task_file(puma).read_text(encoding="utf-8")
    path.write_text(text, encoding="utf-8")
    result = mechatron.size(puma, path, single_pass=True)
    path.write_text(text.replace("payload = 2.5", "payload = 0.5").replace('name = "pick and place, 2.5 kg"',
                                                                         'name = "changed"'), encoding="utf-8")
    return puma, path, text, result


def test_the_report_shows_the_task_as_sized_after_its_file_changed(sized):
    puma, path, text, result = sized
    assert result.given.payload == 2.5 and result.given.text == text
    task = sections(result.report(mechanism=puma, task=path))["Task"]
    assert "payload 2.5 kg" in task[0].text and not any(isinstance(item, Code) for item in task)
    table = next(item for item in task if isinstance(item, Table)).frame
    np.testing.assert_allclose(table["peak_speed"], np.abs(result.given.trajectory.v).max(axis=0), rtol=1e-12)


def test_without_a_task_the_report_shows_the_text_that_was_read(sized):
    puma, path, text, result = sized
    path.unlink()
    task = sections(result.report(mechanism=puma))["Task"]
    assert isinstance(task[0], Text) and "payload 2.5 kg" in task[0].text
    assert [item.text for item in task if isinstance(item, Code)] == [text]


def test_a_task_of_another_name_is_refused(sized, tmp_path):
    puma, _, text, result = sized
    other = tmp_path / "other.toml"
    other.write_text(text.replace('name = "pick and place, 2.5 kg"', 'name = "other"'), encoding="utf-8")
    with pytest.raises(InputError, match="needs that task"):
        result.report(mechanism=puma, task=other)
