"""Running a study: every design through every analysis, serially or on Dask, chunk by chunk to disk, resumable.

:func:`evaluate` turns a chunk of designs into rows (:class:`~mechatron.studies.evaluator.Evaluator`: the
mechanism rebuilt with the design's parameters, each analysis' ``outputs`` with its options and the design's seed); a
design that cannot be built or analysed is a row with ``status = "failed"`` and its ``reason``, never a crash of the
study.

:func:`run_study` sends the chunks that have no part file yet to one process (``workers = 1``), to an embedded
``dask.distributed.LocalCluster`` of ``workers`` processes, or to a running scheduler (``scheduler``); the client
writes each chunk's rows to ``OUT/parts/part-NNNNN.parquet`` (whole or not at all) as it arrives, with the
designs it holds in the file's metadata: the study's identity, their numbers and the digest of their values.
``OUT/study.json`` holds the study's identity — the digests of the spec's row-deciding fields and of the designs,
and the SHA-256 of every file the study reads (``StudySpec.files``) — and the chunk size: run again, the study checks
every part against its chunk (a part that does not read or holds other designs is computed again, with one note)
and skips the chunks done, ending with the same table; a folder of another spec, or one whose files changed since
it started, is refused naming what differs (``restart`` discards it instead). The table of all designs, sorted, is
``OUT/designs.parquet`` and ``OUT/designs.csv``.
"""

from __future__ import annotations

import contextvars
import hashlib
import json
import math
import threading
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..errors import InputError, MechatronWarning
from ..io.values import number
from .cluster import connect, disconnect, prestart, slots
from .evaluator import base_mechanism, file_hash, mechanism_content, study_mechanism
from .pace import Pace

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd

    from .evaluator import Evaluator
    from .result import StudyResult
    from .spec import StudySpec

__all__ = ["base_mechanism", "default_chunk", "evaluate", "mechanism_content", "run_study", "warm_up"]

#: The chunks per worker that the default chunk size aims at. As the last chunks end one after the other, each
#: worker waits on average half a chunk for the others: 1/32 of a study cut into 16 chunks a worker. A chunk's own
#: cost (its round trip through the scheduler, its part file: a few ms) stays far below its designs'.
CHUNKS_PER_WORKER = 16
#: The fewest chunks of the default (the part files a stopped study resumes from) and the most designs of one.
MIN_CHUNKS, MAX_CHUNK = 32, 64


def default_chunk(count: int, workers: int = 1) -> int:
    """The default designs per chunk of ``count`` designs on ``workers`` (the designs that run at once): ``count``
    over 32 chunks, or :data:`CHUNKS_PER_WORKER` per worker where that is more, between 1 and :data:`MAX_CHUNK`."""
    return max(1, min(MAX_CHUNK, math.ceil(count / max(MIN_CHUNKS, CHUNKS_PER_WORKER * workers))))


def warm_up(spec: StudySpec | Evaluator) -> None:
    """Load what the designs of ``spec`` read before the first of them runs in this process: the mechanism (once per
    process, :func:`~mechatron.studies.spec.study_mechanism`) and each analysis' inputs through its ``check``, for
    every set of options of the study (the catalogs, parsed once per process; the task). Every worker of a study
    runs it before its first chunk; what fails here fails again in that design's row, with its reason."""
    from .analyses import analysis
    from .spec import variants

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            mech = study_mechanism(spec.mechanism)
            for name, options, _ in variants(spec):
                analysis(name).check(mech, options)
    except Exception:  # noqa: BLE001, S110 - a warm-up that fails leaves the work to the designs
        pass


async def _warm_worker(spec: StudySpec | Evaluator) -> None:
    """:func:`warm_up` on a Dask worker, in a thread of its event loop (the worker keeps answering meanwhile)."""
    import asyncio

    await asyncio.get_running_loop().run_in_executor(None, warm_up, spec)


#: Designs are evaluated one at a time per process: the models, their compiled kernels and caches are not shared
#: between threads safely (two designs at once in one Dask worker of two threads crashed Pinocchio), and the GIL
#: gives threads no speed here; processes (``--workers``) do.
_ONE_AT_A_TIME = threading.Lock()


def evaluate(spec: StudySpec | Evaluator, designs: pd.DataFrame) -> pd.DataFrame:
    """The rows of a chunk of designs (:class:`~mechatron.studies.evaluator.Evaluator`, the study's or one given):
    the designs' columns, ``status``, ``reason`` and the analyses' outputs; each design's time (s, wall) in the
    frame's ``attrs["seconds"]`` (:class:`~mechatron.studies.pace.Pace`)."""
    import pandas as pd

    from .evaluator import Evaluator

    evaluator = spec if isinstance(spec, Evaluator) else spec.evaluator
    with _ONE_AT_A_TIME:  # a worker of several threads (a scheduler started elsewhere): designs in turn
        rows, seconds = evaluator.timed(designs.to_dict(orient="records"))
    frame = pd.DataFrame(rows)
    frame.attrs["seconds"] = seconds
    return frame


def design_times(rows: pd.DataFrame) -> list[float]:
    """The designs' times (s) that :func:`evaluate` recorded with ``rows`` (NaN where it did not)."""
    seconds = rows.attrs.get("seconds")
    return list(seconds) if seconds is not None and len(seconds) == len(rows) else [math.nan] * len(rows)


def _digest(frame: pd.DataFrame) -> str:
    """SHA-256 of a table's CSV text (its values to the last digit)."""
    return hashlib.sha256(frame.to_csv(index=False).encode()).hexdigest()


def _isolated(write: Callable[[], Any]) -> Any:
    """Run ``write`` outside the command's output transaction: the study's own files go to disk at once."""
    return contextvars.Context().run(write)


def _write_parquet(frame: pd.DataFrame, path: Path) -> None:
    from ..io.output import write_atomically

    _isolated(lambda: write_atomically(path, lambda fh: frame.to_parquet(fh, index=False), binary=True))


# ------------------------------------------------------------------------------------ the study's identity
def _stamp(spec: StudySpec, designs: pd.DataFrame) -> dict[str, Any]:
    """What decides the study's rows: the spec's digest, the designs' digest and count, every file read → SHA-256."""
    return {"spec": spec.digest(), "designs": _digest(designs), "count": len(designs),
            "files": {path: file_hash(path) for path in spec.files}}


def _identity(stamp: dict[str, Any]) -> str:
    """One digest of a :func:`_stamp`, recorded in every part file."""
    return hashlib.sha256(json.dumps(stamp, sort_keys=True).encode()).hexdigest()


def _shown(path: str) -> str:
    """A path as shown in a message: relative to the working folder when inside it."""
    try:
        return str(Path(path).relative_to(Path.cwd()))
    except ValueError:
        return path


def _changed_file(old: dict[str, Any], new: dict[str, str | None]) -> str | None:
    """What differs between the files a study read when it started (``old``: path → SHA-256) and now, or None."""
    for path, digest in old.items():
        if path not in new:
            return f"{_shown(path)} is no longer read (the mechanism or a default file is found elsewhere now)"
        if new[path] is None:
            return f"{_shown(path)} is missing or unreadable (the study read it when it started)"
        if new[path] != digest:
            return f"{_shown(path)} changed since this study started (its rows would mix two versions)"
    extra = [path for path in new if path not in old]
    return f"{_shown(extra[0])} is read now but was not when this study started" if extra else None


def _part(out_dir: Path, k: int) -> Path:
    """The part file of chunk ``k``."""
    return out_dir / "parts" / f"part-{k:05d}.parquet"


def _rows_done(out_dir: Path, old: dict[str, Any]) -> int:
    """The rows of the part files of the study recorded in ``old`` (its study.json)."""
    try:
        count, size = int(old["count"]), int(old["chunk_size"])
    except (KeyError, TypeError, ValueError):
        return 0
    return sum(min(size, count - start) for k, start in enumerate(range(0, count, max(size, 1)))
               if _part(out_dir, k).is_file())


def _refuse_other(out_dir: Path, state: Path, old: dict[str, Any], new: dict[str, Any]) -> None:
    """Refuse a folder whose study (``old``) is not this one (``new``), naming what differs and how to start over."""
    if old.get("spec") != new["spec"]:
        problem, where = f"holds a study of another spec or other designs (see {state.name})", out_dir
    else:
        files = old.get("files")
        changed = _changed_file(files if isinstance(files, dict) else {}, new["files"])
        if changed is not None:
            problem, where = changed, state
        elif {k: old.get(k) for k in ("designs", "count")} != {k: new[k] for k in ("designs", "count")}:
            problem, where = f"holds a study of other designs (see {state.name})", out_dir
        else:
            return
    done = _rows_done(out_dir, old)
    raise InputError(f"{problem}; run with --restart to discard the {done:,} row{'' if done == 1 else 's'} done, or "
                     "give another --out", file=where)


def _discard(out_dir: Path) -> None:
    """Remove a study's files from ``out_dir``: study.json, the part files and the designs tables."""
    for path in [out_dir / "study.json", *(out_dir / "parts").glob("part-*.parquet"), out_dir / "designs.parquet",
                 out_dir / "designs.csv"]:
        path.unlink(missing_ok=True)


def _prepare(out_dir: Path, spec: StudySpec, designs: pd.DataFrame, chunk_size: int | None,
             restart: bool = False, workers: int = 1) -> tuple[int, str]:
    """Create ``out_dir`` (or check the study it holds: the same spec, designs and files; with ``restart``,
    discard it); returns the chunk size (``chunk_size``, a resumed study's own, else :func:`default_chunk` for
    ``workers``) and the study's identity."""
    from ..io.output import output_directory, write_text

    state = out_dir / "study.json"
    stamp = _stamp(spec, designs)
    if state.is_file():
        try:
            old = json.loads(state.read_text())
            if not isinstance(old, dict) or not isinstance(old.get("chunk_size"), int) or old["chunk_size"] < 1:
                raise ValueError
        except (OSError, ValueError):
            raise InputError("not a study's state file; use another output folder", file=state) from None
        if restart:
            _discard(out_dir)
        else:
            _refuse_other(out_dir, state, old, stamp)
            if chunk_size is not None and chunk_size != old.get("chunk_size"):
                raise InputError(f"was started with chunks of {old.get('chunk_size')} designs; resume it with the "
                                 "same chunk size", file=out_dir)
            return int(old["chunk_size"]), _identity(stamp)
    elif restart:
        _discard(out_dir)
    chunk_size = chunk_size or default_chunk(len(designs), workers)
    _isolated(lambda: output_directory(out_dir / "parts"))
    text = json.dumps({**stamp, "chunk_size": chunk_size, "spec_file": spec.file}, indent=2) + "\n"
    _isolated(lambda: write_text(state, text))
    return chunk_size, _identity(stamp)


# -------------------------------------------------------------------------------------------- part files
#: The key of a part file's Parquet metadata that records its designs.
PART_KEY = b"mechatron.study"


def _record(identity: str, chunk: pd.DataFrame) -> dict[str, Any]:
    """What a part file records: the study's identity, its designs' numbers and the digest of their values."""
    return {"study": identity, "designs": [int(d) for d in chunk["design"]], "values": _digest(chunk)}


def _write_part(rows: pd.DataFrame, record: dict[str, Any], path: Path) -> pd.DataFrame:
    """Write a chunk's rows with its :func:`_record` in the file's metadata, whole or not at all; return the rows as
    :func:`_read_part` reads them back (through the same Arrow table: the same dtypes, with no file read)."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    from ..io.output import write_atomically

    table = pa.Table.from_pandas(rows, preserve_index=False)
    table = table.replace_schema_metadata({**(table.schema.metadata or {}), PART_KEY: json.dumps(record).encode()})
    _isolated(lambda: write_atomically(path, lambda fh: pq.write_table(table, fh), binary=True))
    return table.to_pandas()


def _span(designs: Any) -> str:
    """Designs' numbers as ``first–last``."""
    if not isinstance(designs, list) or not designs:
        return "none"
    return f"{designs[0]}" if len(designs) == 1 else f"{designs[0]}–{designs[-1]}"


def _unreadable(exc: Exception) -> str:
    """Why a part file does not read, in words: the system's reason, else not a whole Parquet file."""
    return exc.strerror if isinstance(exc, OSError) and exc.strerror else "not a whole Parquet file"


def _part_problem(path: Path, record: dict[str, Any]) -> str | None:
    """Why the part file ``path`` does not hold the rows of the chunk of ``record``, None if it does: it does not
    read, records other designs or another study, or its rows are not the designs it records."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    try:
        table = pq.read_table(path)
        kept = json.loads((table.schema.metadata or {}).get(PART_KEY, b"null"))
    except (OSError, ValueError, pa.ArrowException) as exc:
        return f"does not read ({_unreadable(exc)})"
    if not isinstance(kept, dict):
        return "records no designs (not written by this study)"
    if kept.get("study") != record["study"]:
        return "is of another study"
    if kept.get("designs") != record["designs"]:
        return f"holds designs {_span(kept.get('designs'))}, not {_span(record['designs'])}"
    if kept.get("values") != record["values"]:
        return f"holds other values of designs {_span(record['designs'])}"
    if "design" not in table.column_names or table.column("design").to_pylist() != record["designs"]:
        return "has rows of other designs than it records"
    return None


def _pending(paths: list[Path], records: list[dict[str, Any]]) -> list[int]:
    """The chunks to run: those without a part file, and those whose part does not hold them (one note for all,
    :class:`~mechatron.errors.MechatronWarning`: they are computed again)."""
    pending, bad = [], []
    for k, (path, record) in enumerate(zip(paths, records)):
        problem = _part_problem(path, record) if path.is_file() else "missing"
        if problem is not None:
            pending.append(k)
            if problem != "missing":
                bad.append(f"{_shown(str(path))} {problem}")
    if bad:
        more = f" (and {len(bad) - 1} more)" if len(bad) > 1 else ""
        warnings.warn(f"{bad[0]}{more}; computed again", MechatronWarning, stacklevel=3)
    return pending


def _read_part(path: Path) -> pd.DataFrame:
    """A part file's rows (an error naming it if it does not read: run the study again to recompute it)."""
    import pandas as pd
    import pyarrow as pa

    try:
        return pd.read_parquet(path)
    except (OSError, ValueError, pa.ArrowException) as exc:
        raise InputError(f"cannot read the part file ({_unreadable(exc)}); run the study again to compute it anew",
                         file=path) from None


def run_study(spec: StudySpec | str | Path, out_dir: str | Path, workers: int = 1, scheduler: str | None = None,
              chunk_size: int | None = None, progress: Callable[[int, int], None] | None = None,
              max_chunks: int | None = None, restart: bool = False) -> StudyResult | None:
    """Run a study (see the module docstring) and return its :class:`~mechatron.studies.result.StudyResult`.

    Args:
        spec: A checked spec or the path of a study file.
        out_dir: The study's folder (created; a folder of the same study is resumed).
        workers: 1: serially in this process; more: an embedded LocalCluster of that many worker processes.
        scheduler: The address of a running Dask scheduler (``tcp://HOST:PORT``); then ``workers`` is ignored.
        chunk_size: Designs per task and per part file (default: n/32, 1 to 64; a resumed study keeps its own).
        progress: Called as ``progress(done, total)`` with the designs done (those of earlier runs included); a
            callback with a ``status`` attribute (:func:`~mechatron.report.progress.progress_bar`) is given the
            designs done and failed and the rate first (:class:`~mechatron.studies.pace.Pace`), and a design that
            takes over ten times the median is named in a warning.
        max_chunks: Stop after this many chunks (the study is then resumed by running it again); returns None.
        restart: Discard the study in ``out_dir`` (its state, parts and tables) and start again.

    Raises:
        InputError: when ``out_dir`` holds another study, or one whose files (the mechanism's, the designs, the
            analyses') changed since it started, naming what differs.
    """
    import pandas as pd

    from .analyses import worker_modules
    from .designs import make_designs
    from .result import study_result
    from .spec import StudySpec, read_study

    workers = number("workers", workers, integer=True, minimum=1, maximum=1024)
    prestart(workers, scheduler, worker_modules())
    spec = spec if isinstance(spec, StudySpec) else read_study(spec)
    chunk_size = number("chunk", chunk_size, integer=True, minimum=1, allow_none=True)
    designs = make_designs(spec)
    out_dir = Path(out_dir)
    client = connect(workers, scheduler, worker_modules())
    try:
        chunk_size, identity = _prepare(out_dir, spec, designs, chunk_size, restart, slots(client))
        chunks = [designs.iloc[k:k + chunk_size] for k in range(0, len(designs), chunk_size)]
        part = [_part(out_dir, k) for k in range(len(chunks))]
        records = [_record(identity, chunk) for chunk in chunks]
        pending = _pending(part, records)
        pace = Pace(len(designs), progress, len(designs) - sum(len(chunks[k]) for k in pending))
        pending = pending[:max_chunks]
        pace.show()
        rows = {}
        for k, chunk_rows in _results(client, spec, chunks, pending):
            seconds = design_times(chunk_rows)
            chunk_rows.attrs.clear()  # the times are not part of the study's rows
            rows[k] = _write_part(chunk_rows, records[k], part[k])
            pace.add(chunk_rows["design"].tolist(), seconds, chunk_rows["status"].tolist(),
                     chunk_rows["reason"].tolist())
        done = pace.done
    finally:
        if client is not None:
            disconnect(client, scheduler)
    if max_chunks is not None and done < len(designs):
        return None
    table = pd.concat([rows[k] if k in rows else _read_part(p) for k, p in enumerate(part)], ignore_index=True)
    table = table.sort_values("design", kind="stable").reset_index(drop=True)
    _write_parquet(table, out_dir / "designs.parquet")
    from ..io.output import write_table

    _isolated(lambda: write_table(table, out_dir / "designs.csv"))
    return study_result(spec, table, out_dir)


def _results(client, spec: StudySpec, chunks: list, pending: list[int]):
    """(chunk number, rows) of every pending chunk, as each finishes: in this process one after the other, or on the
    client's cluster, whose workers first :func:`warm_up` (not waited for: each starts its first chunk when warm),
    all chunks sent in one message and their rows gathered as they end."""
    if client is None:
        for k in pending:
            yield k, evaluate(spec, chunks[k])
        return
    if not pending:
        return
    from distributed import as_completed

    client.run(_warm_worker, spec, wait=False)
    futures = client.map(evaluate, [spec] * len(pending), [chunks[k] for k in pending], pure=False)
    chunk_of = {future.key: k for future, k in zip(futures, pending)}
    finished = as_completed(futures, with_results=True)
    del futures  # as each chunk's rows are here, its future goes, and the worker forgets them
    for future, rows in finished:
        yield chunk_of.pop(future.key), rows
