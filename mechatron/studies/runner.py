"""Running a study: every design through every analysis, serially or on Dask, chunk by chunk to disk, resumable.

:func:`evaluate` turns a chunk of designs into rows: the mechanism rebuilt with the design's parameters
(``with_parameters``), each analysis' ``outputs`` with its options and the design's seed; a design that cannot be
built or analysed is a row with ``status = "failed"`` and its ``reason``, never a crash of the study.

:func:`run_study` sends the chunks that have no part file yet to one process (``workers = 1``), to an embedded
``dask.distributed.LocalCluster`` of ``workers`` processes, or to a running scheduler (``scheduler``); the client
writes each chunk's rows to ``OUT/parts/part-NNNNN.parquet`` (whole or not at all) as it arrives. ``OUT/study.json``
holds the digests of the spec and the designs and the chunk size: run again, the study skips the chunks done and
ends with the same table; a different spec in the same folder is refused. The table of all designs, sorted, is
``OUT/designs.parquet`` and ``OUT/designs.csv``.
"""

from __future__ import annotations

import contextvars
import hashlib
import json
import math
import warnings
from collections.abc import Callable
from functools import lru_cache
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..errors import InputError, MechatronWarning
from ..io.values import number
from .cluster import connect, disconnect

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd

    from .result import StudyResult
    from .spec import Spec

@lru_cache(maxsize=4)
def base_mechanism(mechanism: str):
    """The study's mechanism as loaded from its name or file (once per process)."""
    from ..library import load

    return load(mechanism)


def _one(spec: Spec, design: dict[str, Any]) -> dict[str, Any]:
    """The outputs of one design, or its failure and the reason."""
    from .analyses import analysis

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", MechatronWarning)
            mech = base_mechanism(spec.mechanism)
            geometry = spec.geometry(design)
            mech = mech.with_parameters(geometry) if geometry else mech
            out: dict[str, Any] = {}
            for name in spec.analyses:
                out.update(analysis(name).outputs(mech, spec.options(name, design), int(design["seed"])))
        bad = [k for k, v in out.items() if not isinstance(v, (bool, str)) and not math.isfinite(float(v))]
        if bad:
            return {"status": "failed", "reason": f"{bad[0]} is not a finite number"}
        return {"status": "ok", "reason": "", **out}
    except Exception as exc:  # noqa: BLE001 - a design that fails is a row with its reason, never a crashed study
        text = str(exc).splitlines()[0] if str(exc) else ""
        return {"status": "failed", "reason": text or type(exc).__name__}


def evaluate(spec: Spec, designs: pd.DataFrame) -> pd.DataFrame:
    """The rows of a chunk of designs: the designs' columns, ``status``, ``reason`` and the analyses' outputs."""
    import pandas as pd

    rows = []
    for design in designs.to_dict(orient="records"):
        rows.append({**design, **_one(spec, design)})
    return pd.DataFrame(rows)


def _digest(frame: pd.DataFrame) -> str:
    return hashlib.sha256(frame.to_csv(index=False).encode()).hexdigest()


def _isolated(write: Callable[[], Any]) -> Any:
    """Run ``write`` outside the command's output transaction: the study's own files go to disk at once."""
    return contextvars.Context().run(write)


def _write_parquet(frame: pd.DataFrame, path: Path) -> None:
    from ..io.output import write_atomically

    _isolated(lambda: write_atomically(path, lambda fh: frame.to_parquet(fh, index=False), binary=True))


def _prepare(out_dir: Path, spec: Spec, designs: pd.DataFrame, chunk_size: int | None) -> int:
    """Create ``out_dir`` (or check the study it holds: the same spec and designs); returns the chunk size."""
    from ..io.output import output_directory, write_text

    state = out_dir / "study.json"
    stamp = {"spec": spec.digest(), "designs": _digest(designs), "count": len(designs)}
    if state.is_file():
        try:
            old = json.loads(state.read_text())
        except (OSError, ValueError):
            raise InputError("not a study's state file; use another output folder", file=state) from None
        if {k: old.get(k) for k in stamp} != stamp:
            raise InputError(f"holds a study of another spec or other designs (see {state.name}); use another "
                             "output folder or remove it", file=out_dir)
        if chunk_size is not None and chunk_size != old.get("chunk_size"):
            raise InputError(f"was started with chunks of {old.get('chunk_size')} designs; resume it with the "
                             "same chunk size", file=out_dir)
        return int(old["chunk_size"])
    chunk_size = chunk_size or max(1, min(64, math.ceil(len(designs) / 32)))
    _isolated(lambda: output_directory(out_dir / "parts"))
    text = json.dumps({**stamp, "chunk_size": chunk_size, "spec_file": spec.file}, indent=2) + "\n"
    _isolated(lambda: write_text(state, text))
    return chunk_size


def run_study(spec: Spec | str | Path, out_dir: str | Path, workers: int = 1, scheduler: str | None = None,
              chunk_size: int | None = None, progress: Callable[[int, int], None] | None = None,
              max_chunks: int | None = None) -> StudyResult | None:
    """Run a study (see the module docstring) and return its :class:`~mechatron.studies.result.StudyResult`.

    Args:
        spec: A checked spec or the path of a study file.
        out_dir: The study's folder (created; a folder of the same study is resumed).
        workers: 1: serially in this process; more: an embedded LocalCluster of that many worker processes.
        scheduler: The address of a running Dask scheduler (``tcp://HOST:PORT``); then ``workers`` is ignored.
        chunk_size: Designs per task and per part file (default: n/32, 1 to 64; a resumed study keeps its own).
        progress: Called as ``progress(done, total)`` with the designs done (those of earlier runs included).
        max_chunks: Stop after this many chunks (the study is then resumed by running it again); returns None.
    """
    import pandas as pd

    from .designs import make_designs
    from .result import study_result
    from .spec import read_spec

    spec = read_spec(spec) if not hasattr(spec, "analyses") else spec
    workers = number("workers", workers, integer=True, minimum=1, maximum=1024)
    chunk_size = number("chunk", chunk_size, integer=True, minimum=1, allow_none=True)
    designs = make_designs(spec)
    out_dir = Path(out_dir)
    client = connect(workers, scheduler)
    try:
        chunk_size = _prepare(out_dir, spec, designs, chunk_size)
        chunks = [designs.iloc[k:k + chunk_size] for k in range(0, len(designs), chunk_size)]
        part = [out_dir / "parts" / f"part-{k:05d}.parquet" for k in range(len(chunks))]
        pending = [k for k in range(len(chunks)) if not part[k].is_file()][:max_chunks]
        done = len(designs) - sum(len(chunks[k]) for k in range(len(chunks)) if not part[k].is_file())
        if progress is not None:
            progress(done, len(designs))
        for k, rows in _results(client, spec, chunks, pending):
            _write_parquet(rows, part[k])
            done += len(rows)
            if progress is not None:
                progress(done, len(designs))
    finally:
        if client is not None:
            disconnect(client, scheduler)
    if not all(p.is_file() for p in part):
        return None
    table = pd.concat([pd.read_parquet(p) for p in part], ignore_index=True)
    table = table.sort_values("design", kind="stable").reset_index(drop=True)
    _write_parquet(table, out_dir / "designs.parquet")
    from ..io.output import write_table

    _isolated(lambda: write_table(table, out_dir / "designs.csv"))
    return study_result(spec, table, out_dir)


def _results(client, spec: Spec, chunks: list, pending: list[int]):
    """(chunk number, rows) of every pending chunk, as each finishes."""
    if client is None:
        for k in pending:
            yield k, evaluate(spec, chunks[k])
        return
    from distributed import as_completed

    futures = {client.submit(evaluate, spec, chunks[k], pure=False): k for k in pending}
    for future in as_completed(futures):
        rows = future.result()
        yield futures.pop(future), rows  # released: the worker forgets the chunk's rows once they are here
