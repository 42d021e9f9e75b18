"""Output files are written whole or not at all, with the mode any new file of the user gets."""

from __future__ import annotations

import os
from pathlib import Path

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


def test_a_transaction_writes_every_file_at_its_end_or_none(tmp_path):
    from mechatron.io.output import output_directory, transaction

    first, second = tmp_path / "a.csv", tmp_path / "new" / "b.png"
    write_text(first, "old\n")
    with transaction():
        write_text(first, "new\n")
        output_directory(second.parent)
        write_atomically(second, lambda fh: fh.write(b"png"), binary=True)
        assert first.read_text() == "old\n" and not second.exists()  # staged, not yet in place
    assert first.read_text() == "new\n" and second.read_bytes() == b"png"
    with pytest.raises(InputError, match="stopped"), transaction():
        write_text(first, "newer\n")
        output_directory(tmp_path / "made" / "deeper")
        raise InputError("stopped")
    assert first.read_text() == "new\n"  # kept, and no temporary file or folder left
    assert sorted(p.name for p in tmp_path.rglob("*")) == ["a.csv", "b.png", "new"]


def test_the_same_file_twice_in_one_transaction_is_an_error(tmp_path):
    from mechatron.io.output import transaction

    with pytest.raises(InputError, match="written twice"), transaction():
        write_text(tmp_path / "a.csv", "1\n")
        write_text(tmp_path / "." / "a.csv", "2\n")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="no /dev/full")
def test_a_failed_write_to_a_device_replaces_nothing(tmp_path):
    from mechatron.io.output import transaction

    path = write_text(tmp_path / "a.csv", "old\n")
    with pytest.raises(InputError, match="/dev/full: cannot write: No space left on device"), transaction():
        write_text(path, "new\n")
        write_text("/dev/full", "x")
    assert path.read_text() == "old\n" and [p.name for p in tmp_path.iterdir()] == ["a.csv"]
    assert write_text(os.devnull, "nothing") == Path(os.devnull)


def test_a_link_is_written_through_and_a_mode_kept(tmp_path):
    target = write_text(tmp_path / "target.csv", "old\n")
    target.chmod(0o600)
    link = tmp_path / "link.csv"
    link.symlink_to(target)
    write_text(link, "new\n")
    assert link.is_symlink() and target.read_text() == "new\n"
    assert os.stat(target).st_mode & 0o777 == 0o600


def test_output_paths_are_checked(tmp_path):
    from mechatron.io.output import check_directory, check_output

    (tmp_path / "file").write_text("x")
    with pytest.raises(InputError, match="--plot x.xyz: cannot write a chart as a .xyz file; use .png, .pdf or .svg"):
        check_output(tmp_path / "x.xyz", "figure", where="--plot x.xyz")
    with pytest.raises(InputError, match="is a file, not a folder"):
        check_output(tmp_path / "file" / "x.csv", "table")
    with pytest.raises(InputError, match="is a file, not a folder"):
        check_directory(tmp_path / "file")
    with pytest.raises(InputError, match="does not exist"):
        check_directory(tmp_path / "missing" / "charts")
    assert check_output(os.devnull, "table") == Path(os.devnull)  # a device takes any name
    assert check_directory(tmp_path / "charts") == tmp_path / "charts" and not (tmp_path / "charts").exists()
