"""Output files are written whole or not at all, with the mode any new file of the user gets."""

from __future__ import annotations

import os

import pytest

from mechatron.errors import InputError
from mechatron.io.output import write_atomically, write_text


def test_a_written_file_has_the_users_usual_mode(tmp_path):
    mask = os.umask(0o022)
    try:
        path = write_text(tmp_path / "out.txt", "x")
        assert os.stat(path).st_mode & 0o777 == 0o644
    finally:
        os.umask(mask)


def test_a_failed_write_keeps_the_previous_file_and_leaves_no_part(tmp_path):
    path = write_text(tmp_path / "out.csv", "old\n")

    def fail(fh):
        fh.write("half")
        raise RuntimeError("stopped")

    with pytest.raises(RuntimeError):
        write_atomically(path, fail)
    assert path.read_text() == "old\n" and sorted(p.name for p in tmp_path.iterdir()) == ["out.csv"]
    with pytest.raises(InputError, match="is a directory"):
        write_text(tmp_path, "x")
    with pytest.raises(InputError, match="does not exist"):
        write_text(tmp_path / "missing" / "out.txt", "x")
