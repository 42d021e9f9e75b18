"""Where a study's designs run: in this process, on an embedded Dask ``LocalCluster``, or on a running scheduler
(:func:`connect`, :func:`disconnect`)."""

from __future__ import annotations

import logging

from ..errors import InputError

#: Seconds to wait for a running Dask scheduler.
CONNECT_SECONDS = 3.0
#: The Dask settings of the embedded LocalCluster's workers. Dask's default environment of a new worker sets
#: ``MALLOC_TRIM_THRESHOLD_``, which turns off glibc's adaptive mmap threshold: every array above 128 KB is then
#: mapped and unmapped anew, and a PUMA sizing took 0.41–0.60 s per design in a worker against 0.32 s in a plain
#: process (two at once, on this project's two-core machine). The workers keep Dask's one-thread BLAS and OpenMP
#: settings and do without the statistical profiler (a stack sample every 10 ms), which nobody reads here.
#: Workers of a running scheduler are the user's: the same settings belong in their Dask configuration
#: (docs/study_file.md).
WORKER_CONFIG = {"distributed.nanny.pre-spawn-environ": {"OMP_NUM_THREADS": 1, "MKL_NUM_THREADS": 1,
                                                          "OPENBLAS_NUM_THREADS": 1},
                 "distributed.worker.profile.enabled": False}


def connect(workers: int, scheduler: str | None):
    """A Dask client of a running scheduler (refused in a few seconds when it cannot be reached) or of a new
    LocalCluster of ``workers`` processes with one thread each; None for a serial run."""
    if scheduler is None and workers == 1:
        return None
    from distributed import Client, LocalCluster

    quiet = logging.getLogger("distributed")
    level = quiet.level
    quiet.setLevel(logging.CRITICAL)
    try:
        if scheduler is not None:
            try:
                return Client(scheduler, timeout=f"{CONNECT_SECONDS}s")
            except (OSError, TimeoutError, ValueError) as exc:
                detail = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
                raise InputError(f"--scheduler {scheduler}: cannot reach the Dask scheduler within "
                                 f"{CONNECT_SECONDS:g} s ({detail[:120]})") from None
        import dask

        with dask.config.set(WORKER_CONFIG):
            cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None)
        return Client(cluster)
    finally:
        quiet.setLevel(level)


def disconnect(client, scheduler: str | None) -> None:
    """Close the client, and the LocalCluster it started (a running scheduler stays)."""
    cluster = client.cluster if scheduler is None else None
    client.close()
    if cluster is not None:
        cluster.close()
