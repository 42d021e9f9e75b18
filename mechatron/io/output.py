"""Writing output files whole or not at all, and all of a command's outputs together or none of them.

Every file mechatron writes (CSV tables, JSON, charts, HTML reports, URDF, SRDF and mechanism files) is first
written to a temporary file beside its target and then renamed over it, so a failed run never leaves a
half-written file and never destroys the previous one (:func:`write_atomically`).

Inside a :func:`transaction` the renames wait: each writer leaves its complete temporary file, and
:meth:`Transaction.commit` renames them all at once, when every output of the command is ready; an error before
that removes the temporary files and leaves every file as it was. The command line runs each command in one
(:func:`mechatron.cli.common.outputs`), so ``size --csv out.csv --plots DIR`` writes both or neither.

A target that exists and is not a regular file (``/dev/null``, ``/dev/stdout``, a pipe) is written directly, at
the commit, before the renames, so that a failed write there (``/dev/full``: no space left) is an error before
any other file is replaced. :func:`check_output` checks a path before any work (a directory, a folder that does
not exist or cannot be written, an unsupported format) so that the command line refuses it at once.

No command writes over a file it reads. The command line tells its transaction the files it will write before any
work (:meth:`Transaction.writes`); from then on every file opened for reading inside the transaction — by the readers
of :mod:`mechatron.io` (TOML, CSV), the URDF and SRDF loaders, the study's hashing of its files, or anything else
that opens a file in Python — goes through :func:`check_input` (an audit hook on Python's ``open`` event), which
refuses, in one line naming the output option and the file, a file that one of the outputs would replace: the same
file (device and inode), however it was named (an option, a path in a spec, a symbolic link). A refused command has
written nothing, as its transaction rolls back.
"""

from __future__ import annotations

import contextlib
import io
import os
import stat
import struct
import sys
from collections.abc import Callable, Iterator, Mapping
from contextvars import ContextVar
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO, TYPE_CHECKING

from ..errors import InputError

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
    from matplotlib.figure import Figure

#: The suffixes each kind of output file may have (figures: what matplotlib draws, :func:`figure_formats`).
FILE_SUFFIXES = {"table": (".csv", ".txt"), "html": (".html", ".htm"), "urdf": (".urdf", ".xml"),
                 "toml": (".toml",), "json": (".json",)}

#: The key of the PNG text chunk that marks a chart as written by mechatron into a chart folder (its owner).
PNG_OWNER_KEY = "Source"


# --------------------------------------------------------------------------------------------- path checks
def figure_formats() -> tuple[str, ...]:
    """The suffixes a chart may have (``.png``, ``.pdf``, ``.svg``, …: what matplotlib's Agg canvas writes)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    return tuple(sorted("." + k for k in FigureCanvasAgg.get_supported_filetypes()))


def _special(path: Path) -> bool:
    """Whether ``path`` exists and is neither a regular file nor a directory (a device, a pipe, a socket)."""
    try:
        mode = path.stat().st_mode
    except OSError:
        return False
    return not (stat.S_ISREG(mode) or stat.S_ISDIR(mode))


def _check_folder(folder: Path, path: Path, where: str) -> None:
    if not folder.exists():
        raise InputError(f"the folder {folder} does not exist", file=where)
    if not folder.is_dir():
        raise InputError(f"{folder} is a file, not a folder", file=where)
    if not os.access(folder, os.W_OK | os.X_OK):
        raise InputError(f"the folder {folder} is not writable", file=where)


def check_output(path: str | Path, kind: str | None = None, *, where: str | None = None) -> Path:
    """Check that ``path`` can take an output file of ``kind`` (a key of :data:`FILE_SUFFIXES`, ``"figure"`` or None:
    any suffix) before any work: not a directory, its folder exists and is writable, its suffix is one of the kind's.
    A device or pipe (``/dev/null``) is accepted as it is. Returns ``path``; raises :class:`InputError` naming
    ``where`` (default: the path)."""
    path = Path(path)
    where = str(path) if where is None else where
    try:
        return _check_output(path, kind, where)
    except OSError as exc:  # e.g. a name too long for the file system
        raise InputError(f"cannot write: {exc.strerror}", file=where) from None


def _check_output(path: Path, kind: str | None, where: str) -> Path:
    if path.is_dir():
        raise InputError("is a directory, not a file", file=where)
    if _special(path):
        return path
    target = Path(os.path.realpath(path)) if path.is_symlink() else path
    folder = target.parent if str(target.parent) else Path(".")
    _check_folder(folder, path, where)
    try:
        longest = os.pathconf(folder, "PC_NAME_MAX")
    except (OSError, ValueError):
        longest = 255
    if len(os.fsencode(target.name)) > longest:
        raise InputError(f"the file name is longer than {longest} bytes", file=where)
    allowed = figure_formats() if kind == "figure" else FILE_SUFFIXES.get(kind or "", ())
    if allowed and path.suffix.lower() not in allowed:
        what = {"figure": "a chart", "table": "a CSV table", "html": "an HTML report", "urdf": "a URDF",
                "toml": "a mechanism file", "json": "JSON"}.get(kind or "", "this file")
        given = f"a {path.suffix} file" if path.suffix else "a file without a suffix"
        use = ".png, .pdf or .svg (or another format matplotlib writes)" if kind == "figure" else ", ".join(allowed)
        raise InputError(f"cannot write {what} as {given}; use {use}", file=where)
    return path


def check_directory(path: str | Path, *, where: str | None = None) -> Path:
    """Check that ``path`` can be a folder of outputs: an existing folder (writable), or a new one in an existing,
    writable folder. Returns ``path``; raises :class:`InputError` naming ``where`` (default: the path)."""
    path = Path(path)
    where = str(path) if where is None else where
    try:
        return _check_directory(path, where)
    except OSError as exc:  # e.g. a name too long for the file system
        raise InputError(f"cannot write: {exc.strerror}", file=where) from None


def _check_directory(path: Path, where: str) -> Path:
    if path.exists() or path.is_symlink():
        if not path.is_dir():
            raise InputError("is a file, not a folder", file=where)
        if not os.access(path, os.W_OK | os.X_OK):
            raise InputError("the folder is not writable", file=where)
        return path
    _check_folder(path.parent if str(path.parent) else Path("."), path, where)
    return path


# --------------------------------------------------------------------------------------------- transactions
@dataclass
class _Staged:
    target: Path  # where the file goes (a symbolic link resolved)
    given: Path  # the path as given
    temporary: str | None  # the complete temporary file beside the target, or None for a special target
    data: bytes = b""  # the bytes of a special target


@dataclass
class Transaction:
    """The outputs of one command: staged (complete, under temporary names) until :meth:`commit` renames them
    together, or :meth:`rollback` removes them.

    Attributes:
        labels: Where a path came from (its resolved path, or the folder it is in → the option, e.g. ``--csv``),
            for the error messages.
        written: The existing files this command will replace, by identity (device, inode) → (their option, the
            path as given): reading one of them is refused (:func:`check_input`).
    """

    labels: dict[Path, str] = field(default_factory=dict)
    written: dict[tuple[int, int], tuple[str, str]] = field(default_factory=dict)
    _staged: list[_Staged] = field(default_factory=list)
    _stale: list[Path] = field(default_factory=list)
    _created: list[Path] = field(default_factory=list)

    def where(self, path: str | Path) -> str:
        """``path`` as the errors name it: after its option (``--plot out.png``) when known."""
        resolved = Path(os.path.realpath(path))
        label = self.labels.get(resolved) or self.labels.get(resolved.parent)
        return f"{label} {path}" if label else str(path)

    def stage(self, path: Path, write: Callable[[IO], None], binary: bool) -> Path:
        """Write ``write(file)`` whole to a temporary file beside ``path`` (to memory for a device or pipe)."""
        target = Path(os.path.realpath(path)) if path.is_symlink() else path
        key = Path(os.path.abspath(target))
        if any(Path(os.path.abspath(s.target)) == key for s in self._staged):
            resolved = Path(os.path.realpath(path))
            options = sorted({self.labels.get(resolved), self.labels.get(resolved.parent)} - {None})
            by = f" ({' and '.join(options)})" if options else ""
            raise InputError(f"is written twice by this command{by}; give each output its own file", file=path)
        if _special(target):
            buffer = io.BytesIO()
            _render(buffer, write, binary)
            self._staged.append(_Staged(target, path, None, buffer.getvalue()))
        else:
            self._staged.append(_Staged(target, path, _temporary(target, write, binary, self.where(path))))
        return path

    def writes(self, path: str | Path, option: str) -> None:
        """``path``, named by ``option`` (``--csv``), is a file this command will write: from now on a read of it
        inside the transaction is refused (:func:`check_input`). Only an existing regular file is recorded (a new
        file replaces nothing; a device or pipe such as ``/dev/stdout`` is written, not replaced)."""
        try:
            info = os.stat(path)
        except (OSError, ValueError):
            return
        if stat.S_ISREG(info.st_mode):
            self.written[(info.st_dev, info.st_ino)] = (option, str(path))
            _watch_reads()

    def remove(self, path: str | Path) -> None:
        """Remove ``path`` (a stale companion of an earlier run) at the commit, unless this command writes it."""
        self._stale.append(Path(path))

    def created(self, directory: Path) -> None:
        """``directory`` was created for these outputs: removed again (if empty) by :meth:`rollback`."""
        self._created.append(directory)

    def commit(self) -> list[Path]:
        """Write the devices and pipes, then rename every staged file to its target, then remove the stale
        companions; returns the paths written (as given). A failed write removes every temporary file and raises
        :class:`InputError` naming the path (and its option) before any target is replaced."""
        staged, self._staged = self._staged, []
        stale, self._stale = self._stale, []
        try:
            for s in staged:
                if s.temporary is None:
                    try:
                        with open(s.target, "wb") as fh:
                            fh.write(s.data)
                    except OSError as exc:
                        raise InputError(f"cannot write: {exc.strerror}", file=self.where(s.given)) from None
            for s in staged:
                if s.temporary is not None:
                    try:
                        os.replace(s.temporary, s.target)
                    except OSError as exc:
                        raise InputError(f"cannot write: {exc.strerror}", file=self.where(s.given)) from None
                    s.temporary = None
        except BaseException:
            self._staged = staged
            self.rollback()
            raise
        self._created = []
        self.written = {}  # replaced: their inodes are free to be reused by files read from now on
        written = {Path(os.path.abspath(s.target)) for s in staged}
        for path in stale:
            if Path(os.path.abspath(path)) not in written:
                with contextlib.suppress(FileNotFoundError):
                    try:
                        path.unlink()
                    except OSError as exc:
                        raise InputError(f"cannot remove the stale file: {exc.strerror}", file=path) from None
        return [s.given for s in staged]

    def rollback(self) -> None:
        """Remove every temporary file and every folder created, leaving the targets as they were."""
        for s in self._staged:
            if s.temporary is not None:
                _remove(s.temporary)
        for directory in reversed(self._created):
            with contextlib.suppress(OSError):
                directory.rmdir()
        self._staged, self._stale, self._created = [], [], []


_CURRENT: ContextVar[Transaction | None] = ContextVar("mechatron_output_transaction", default=None)


@contextlib.contextmanager
def transaction(labels: Mapping[Path, str] | None = None) -> Iterator[Transaction]:
    """Stage every file written inside (by :func:`write_atomically` and all that use it) and rename them together
    at the end, or remove them all if an exception leaves the block. Inside another transaction it joins that one
    (which commits or rolls back); ``labels`` (path → option) name the paths in the errors."""
    current = _CURRENT.get()
    if current is not None:
        current.labels.update({Path(os.path.realpath(k)): v for k, v in (labels or {}).items()})
        yield current
        return
    current = Transaction({Path(os.path.realpath(k)): v for k, v in (labels or {}).items()})
    token = _CURRENT.set(current)
    try:
        yield current
        current.commit()
    except BaseException:
        current.rollback()
        raise
    finally:
        _CURRENT.reset(token)


# ------------------------------------------------------------------------------------------ inputs protected
_UNCHECKED: ContextVar[bool] = ContextVar("mechatron_unchecked_reads", default=False)
_WATCHING = False


def check_input(path: str | Path) -> None:
    """Refuse to read ``path`` if the current command's transaction will replace it (:meth:`Transaction.writes`):
    :class:`InputError` naming the output option and the file as given, e.g. ``--csv designs.csv is an input of
    this command; write the output to another file``. Outside a transaction, or for a path that does not exist,
    nothing happens. Every Python ``open`` for reading inside a transaction calls it (:func:`_watch_reads`); code
    that reads a file by other means (a library in C++) may call it first."""
    current = _CURRENT.get()
    if current is None or not current.written or _UNCHECKED.get():
        return
    try:
        info = os.stat(path)
    except (OSError, ValueError):
        return
    hit = current.written.get((info.st_dev, info.st_ino))
    if hit is None:
        return
    option, given = hit
    read = os.fsdecode(path)
    also = f" (read as {read})" if os.path.abspath(read) != os.path.abspath(given) else ""
    raise InputError(f"{option} {given} is an input of this command{also}; write the output to another file")


@contextlib.contextmanager
def unchecked() -> Iterator[None]:
    """Reads inside are not checked by :func:`check_input`: for the transaction's own look at a file it may
    replace (whose chart is it, :func:`png_owner`), which is no input."""
    token = _UNCHECKED.set(True)
    try:
        yield
    finally:
        _UNCHECKED.reset(token)


def _reading(mode: str | None, flags: int | None) -> bool:
    """Whether an ``open`` event (``open()``: its mode; ``os.open``: None and its flags) opens for reading."""
    if mode is None:
        return (flags or 0) & os.O_ACCMODE != os.O_WRONLY
    return "r" in mode or "+" in mode


def _audit(event: str, args: tuple) -> None:
    """The audit hook: every Python ``open`` for reading inside a transaction that replaces files is checked."""
    if event != "open" or _CURRENT.get() is None:
        return
    path, mode, flags = args
    if isinstance(path, (str, bytes, os.PathLike)) and _reading(mode, flags):
        check_input(path)


def _watch_reads() -> None:
    """Install :func:`_audit` (once per process; it costs a comparison per audited event outside a transaction)."""
    global _WATCHING
    if not _WATCHING:
        sys.addaudithook(_audit)
        _WATCHING = True


def _where(path: str | Path) -> str:
    """``path`` as errors name it: after its option (``--plot out.png``) inside a command's transaction."""
    current = _CURRENT.get()
    return current.where(path) if current is not None else str(path)


# --------------------------------------------------------------------------------------------------- writers
def _render(fh: IO, write: Callable[[IO], None], binary: bool) -> None:
    if binary:
        write(fh)
        return
    text = io.TextIOWrapper(fh, encoding="utf-8", newline="")
    write(text)
    text.flush()
    text.detach()


def _temporary(target: Path, write: Callable[[IO], None], binary: bool, where: str) -> str:
    """``write(file)`` into a new temporary file beside ``target``, complete and synced; returns its name."""
    import tempfile  # imported here: a command that writes no file needs none of it

    folder = target.parent if str(target.parent) else Path(".")
    try:
        handle, temporary = tempfile.mkstemp(prefix=f".{target.name[:100]}.", suffix=".part", dir=folder)
    except OSError as exc:
        raise InputError(f"cannot write: {exc.strerror}", file=where) from None
    try:
        with os.fdopen(handle, "wb") as fh:
            _render(fh, write, binary)
            fh.flush()
            os.fsync(fh.fileno())
        try:  # mkstemp makes the file private; an output gets the mode of the file it replaces, or the usual one
            mode = stat.S_IMODE(target.stat().st_mode)
        except OSError:
            mode = 0o666 & ~_umask()
        os.chmod(temporary, mode)
    except OSError as exc:
        _remove(temporary)
        raise InputError(f"cannot write: {exc.strerror}", file=where) from None
    except BaseException:
        _remove(temporary)
        raise
    return temporary


def write_atomically(path: str | Path, write: Callable[[IO], None], *, binary: bool = False) -> Path:
    """Call ``write(file)`` on a temporary file in the folder of ``path``, then rename it to ``path`` (inside a
    :func:`transaction`: when it commits). Returns ``path``.

    Raises:
        InputError: naming ``path`` (and its option, inside a transaction of the command line) if it is a
            directory, its folder does not exist or cannot be written, or the write fails (e.g. a full disk).
    """
    path = Path(path)
    check_output(path, where=_where(path))
    with transaction() as current:
        return current.stage(path, write, binary)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _remove(path: str) -> None:
    try:
        os.unlink(path)
    except OSError:
        pass


def write_text(path: str | Path, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` whole or not at all."""
    return write_atomically(path, lambda fh: fh.write(text))


def write_table(table: pd.DataFrame, path: str | Path) -> Path:
    """Write a DataFrame as CSV (no index, 10 significant digits) whole or not at all."""
    return write_atomically(path, lambda fh: table.to_csv(fh, index=False, float_format="%.10g"))


def save_figure(figure: Figure, path: str | Path, dpi: int = 110, *, owner: str | None = None) -> Path:
    """Save a matplotlib figure (format from the suffix: .png, .pdf, .svg) whole or not at all; ``owner`` (PNG
    only) marks it as a chart of :func:`write_folder`."""
    path = Path(path)
    check_output(path, None if _special(path) else "figure", where=_where(path))
    fmt = path.suffix.lower().lstrip(".") or "png"
    if fmt not in figure.canvas.get_supported_filetypes():
        fmt = "png"  # a device or pipe without a suffix
    metadata = {PNG_OWNER_KEY: owner} if owner and fmt == "png" else None
    return write_atomically(path, lambda fh: figure.savefig(fh, dpi=dpi, format=fmt, metadata=metadata),
                            binary=True)


def output_directory(directory: str | Path) -> Path:
    """``directory``, created if needed (an error naming it if it cannot be); inside a :func:`transaction` the
    folders created are removed again if it rolls back."""
    directory = Path(directory)
    where = _where(directory)
    if directory.exists() and not directory.is_dir():
        raise InputError("is a file, not a folder", file=where)
    missing = [p for p in [directory, *directory.parents] if not p.exists()][::-1]
    try:
        directory.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"cannot create the folder: {exc.strerror}", file=where) from None
    current = _CURRENT.get()
    for created in missing if current is not None else ():
        current.created(created)
    return directory


# ----------------------------------------------------------------------------------------- folders of charts
def png_owner(path: Path) -> str | None:
    """The owner mark (:data:`PNG_OWNER_KEY`) of a PNG written by :func:`save_figure`, or None."""
    try:
        with unchecked(), open(path, "rb") as fh:
            if fh.read(8) != b"\x89PNG\r\n\x1a\n":
                return None
            while True:
                head = fh.read(8)
                if len(head) < 8:
                    return None
                length, kind = struct.unpack(">I4s", head)
                if kind in (b"IDAT", b"IEND") or length > 1 << 20:
                    return None
                data = fh.read(length)
                fh.read(4)
                if kind == b"tEXt":
                    key, _, value = data.partition(b"\0")
                    if key.decode("latin-1") == PNG_OWNER_KEY:
                        return value.decode("latin-1")
    except OSError:
        return None


def write_folder(directory: str | Path, files: Mapping[str, Callable[[], Figure | pd.DataFrame]], *,
                 owner: str) -> list[Path]:
    """Write ``files`` (a name → a function making its content: ``NAME.png`` a Figure, ``NAME.csv`` a DataFrame)
    into ``directory`` (created if needed) as one transaction, each PNG marked as ``owner``'s (e.g. ``mechatron size
    puma560``). The companions of an earlier call for the same ``owner`` that this one does not write — a PNG there
    with that mark, and the CSV of the same name — are removed. Returns the files, in order."""
    with transaction() as current:
        directory = output_directory(directory)
        written: list[Path] = []
        for name, make in files.items():
            content = make()
            if name.endswith(".csv"):
                written.append(write_atomically(directory / name,
                                                lambda fh, f=content: f.to_csv(fh, index=False)))
            else:
                written.append(save_figure(content, directory / name, owner=owner))
        for png in sorted(directory.glob("*.png")):
            if png.name not in files and png_owner(png) == owner:
                current.remove(png)
                if png.with_suffix(".csv").name not in files and png.with_suffix(".csv").is_file():
                    current.remove(png.with_suffix(".csv"))
    return written


output_name = _where


def stage_removal(path: str | Path) -> None:
    """Remove ``path``, a stale companion of an earlier run, when the current transaction commits (at once
    outside one)."""
    with transaction() as current:
        current.remove(path)


def stale_failures(path: str | Path) -> Path | None:
    """The ``<stem>.failures.csv`` beside the table ``path`` if it is one that earlier versions of mechatron wrote
    there (a CSV whose last column is ``reason``), else None."""
    path = Path(path)
    companion = path.with_name(path.stem + ".failures.csv")
    try:
        with unchecked(), open(companion, encoding="utf-8", errors="replace") as fh:
            header = fh.readline(10_000).strip()
    except OSError:
        return None
    return companion if header.split(",")[-1] == "reason" else None


def will_write(path: str | Path, option: str) -> None:
    """Tell the current transaction that ``path`` (named by ``option``, e.g. ``-o DIR``) may be replaced or removed
    by this command (:meth:`Transaction.writes`): from now on a read of it is refused. Outside a transaction nothing
    happens."""
    current = _CURRENT.get()
    if current is not None:
        current.writes(path, option)


def written_so_far() -> list[Path]:
    """Commit the current transaction's outputs now (before a command prints that it wrote them)."""
    current = _CURRENT.get()
    return current.commit() if current is not None else []
