"""Where a study's designs run: in this process, on an embedded Dask ``LocalCluster``, or on a running scheduler
(:func:`connect`, :func:`disconnect`).

A running scheduler is checked before Dask's client is built (:func:`check_scheduler`), because Dask's own
connection bounds only the TCP connect: its handshake reads the peer's first message without a timeout (a port that
accepts and never answers hangs the client for good; see the comment in ``distributed.comm.tcp``), and it reads the
first 8 bytes as a frame length (an HTTP server's ``HTTP/1.1`` asks for 3.07 EiB: ``MemoryError``). The check talks
Dask's TCP protocol itself, every step under one deadline of :data:`HANDSHAKE_SECONDS`:

1. the TCP connection (refused, unknown host, unreachable or no answer → "cannot reach");
2. the greeting: a Dask server writes its handshake (a small msgpack dict) as soon as it accepts, before reading
   anything; nothing within the deadline, a frame length above :data:`MAX_MESSAGE` or bytes that are not Dask's
   frames → "not a Dask scheduler" (a silent port is asked ``GET /`` to tell an HTTP server such as the dashboard);
3. this side's handshake (without compression: the check reads msgpack only), then the ``identity`` operation:
   a Dask worker or nanny greets too, but only a scheduler says ``type = "Scheduler"``; then ``close``, so that the
   scheduler logs nothing.

Addresses of other schemes (``tls://``, ``inproc://``, ``ucx://``) go to Dask directly, with its timeout.
"""

from __future__ import annotations

import logging
import multiprocessing
import os
import socket
import struct
import sys
import time
from collections.abc import Iterable

from ..errors import InputError
from ..io.budget import available_cores

#: Seconds for the whole check of a running scheduler: connection, greeting (or ``GET /`` to a silent port) and
#: identity; Dask's client then gets as long again to connect. A scheduler greets within milliseconds, a busy one
#: within a second or two; with Python's start, the spec and the designs (~2 s) a refusal comes within 10 s.
HANDSHAKE_SECONDS = 5.0
#: Seconds of :data:`HANDSHAKE_SECONDS` kept for an HTTP server to answer ``GET /`` once a port has stayed silent.
HTTP_SECONDS = 1.0
#: The largest message the check reads (bytes): a handshake is ~100 bytes, a scheduler's identity ~1 kB a worker.
MAX_MESSAGE = 64 * 2**20
#: Dask's port of a scheduler (that of its dashboard: 8787).
SCHEDULER_PORT = 8786
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
#: The modules every process of Dask's workers needs, beside the study's (:func:`start_forkserver`).
DASK_MODULES = ("distributed", "numpy", "pandas", "pyarrow.parquet")


def check_workers(workers: int) -> None:
    """Refuse an embedded cluster of more worker processes than the usable cores: each runs one design at a time,
    so more only share the cores and multiply the memory."""
    cores = available_cores()
    if workers > cores:
        raise InputError(f"--workers {workers}: this machine has {cores} usable core{'s' * (cores != 1)}; give "
                         f"at most {cores}, or --scheduler ADDR for a cluster of other machines")


def start_forkserver(modules: Iterable[str]) -> str:
    """Start this process' multiprocessing fork server, importing ``modules`` (after :data:`DASK_MODULES`), with
    the thread settings of :data:`WORKER_CONFIG` in its environment; return the start method of the embedded
    cluster's workers: ``forkserver``, or ``spawn`` where there is no fork server (Windows).

    Spawned, every worker process imports Dask, pandas, Pinocchio and mechatron anew (~1–2 s of CPU each, all at
    once) before its first chunk, and takes ~0.3 s more to close; forked from a server that imported them once, a
    worker starts in milliseconds with them imported (their pages shared) and exits at once. The server is started
    once per process (a second cluster in the same process forks from it again) and ends with the process."""
    if "forkserver" not in multiprocessing.get_all_start_methods():
        return "spawn"
    from multiprocessing import forkserver

    os.environ.update({k: str(v) for k, v in WORKER_CONFIG["distributed.nanny.pre-spawn-environ"].items()})
    multiprocessing.get_context("forkserver").set_forkserver_preload(list(dict.fromkeys([*DASK_MODULES, *modules])))
    forkserver.ensure_running()
    return "forkserver"


def prestart(workers: int, scheduler: str | None, modules: Iterable[str]) -> None:
    """Start the fork server of an embedded cluster of ``workers`` (:func:`start_forkserver`) ahead of
    :func:`connect`, so that its imports (~1 s) run while this process reads the spec and draws the designs; nothing
    for a serial run, a running scheduler, or more workers than cores (:func:`connect` refuses them)."""
    if scheduler is None and 1 < workers <= available_cores():
        start_forkserver(modules)


def connect(workers: int, scheduler: str | None, modules: Iterable[str] = ()):
    """A Dask client of a running scheduler (checked first, :func:`check_scheduler`) or of a new LocalCluster of
    ``workers`` processes with one thread each (at most :func:`~mechatron.io.budget.available_cores`), forked from a
    server that imported ``modules`` (:func:`start_forkserver`); None for a serial run."""
    if scheduler is None:
        check_workers(workers)
        if workers == 1:
            return None
    from distributed import Client, LocalCluster

    quiet = logging.getLogger("distributed")
    level = quiet.level
    quiet.setLevel(logging.CRITICAL)
    try:
        if scheduler is not None:
            return _client(scheduler)
        import dask

        method = start_forkserver(modules)
        with dask.config.set({**WORKER_CONFIG, "distributed.worker.multiprocessing-method": method}):
            cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None)
        return Client(cluster)
    finally:
        quiet.setLevel(level)


def slots(client) -> int:
    """The designs that run at once on the client's cluster: its workers' threads (1 for a serial run, and for a
    scheduler without workers yet)."""
    return 1 if client is None else max(1, sum(client.nthreads().values()))


def _client(scheduler: str):
    """Dask's client of the running scheduler at ``scheduler``, checked first where the scheme is ``tcp``."""
    from distributed import Client

    scheme, host, port = scheduler_address(scheduler)
    if scheme == "tcp":
        check_scheduler(scheduler, host, port)
    try:
        return Client(scheduler, timeout=f"{HANDSHAKE_SECONDS}s")
    except Exception as exc:  # noqa: BLE001 - whatever Dask says, one line naming the address
        detail = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise InputError(f"--scheduler {scheduler}: cannot connect to a Dask scheduler within "
                         f"{HANDSHAKE_SECONDS:g} s ({detail[:160]})") from None


def scheduler_address(scheduler: str) -> tuple[str, str, int]:
    """(scheme, host, port) of a scheduler's address (``tcp://HOST:PORT``, ``HOST:PORT``); the host and port only
    of a ``tcp`` address (else ``""`` and 0). Refused: a scheme Dask does not know (``http://`` of a dashboard) and
    a ``tcp`` address without its port or with one that is not a number in 1 … 65535."""
    from distributed.comm import registry
    from distributed.comm.addressing import parse_address, parse_host_port

    where = f"--scheduler {scheduler}"
    try:
        scheme, location = parse_address(scheduler)
        registry.get_backend(scheme)
    except (ValueError, TypeError):
        scheme = scheduler.partition("://")[0]
        raise InputError(f"{where}: not a Dask address: the scheme {scheme!r} is not Dask's (a scheduler's address "
                         f"is tcp://HOST:{SCHEDULER_PORT})") from None
    if scheme != "tcp":
        return scheme, "", 0
    try:
        host, port = parse_host_port(location)
    except ValueError:
        raise InputError(f"{where}: not a Dask address: expected tcp://HOST:PORT with the port a number (a "
                         f"scheduler's is {SCHEDULER_PORT} unless it was started with another)") from None
    if not 0 < port < 65536:
        raise InputError(f"{where}: not a Dask address: port {port} is not in 1 … 65535")
    return scheme, host, port


def check_scheduler(scheduler: str, host: str, port: int, seconds: float = HANDSHAKE_SECONDS) -> None:
    """Refuse, in one line naming ``--scheduler ADDR``, an address where no Dask scheduler answers within
    ``seconds`` (see the module docstring): refused, unknown host, unreachable, silent, another server or another
    Dask server (a worker)."""
    start, wait = time.monotonic(), seconds - HTTP_SECONDS
    where = f"--scheduler {scheduler}"
    try:
        sock = socket.create_connection((host, port), timeout=wait)
    except socket.gaierror as exc:
        raise InputError(f"{where}: cannot reach the Dask scheduler: unknown host {host!r} ({exc.strerror})") \
            from None
    except ConnectionRefusedError:
        raise InputError(f"{where}: cannot reach the Dask scheduler: connection refused (nothing listens on port "
                         f"{port} of {host})") from None
    except TimeoutError:
        raise InputError(f"{where}: cannot reach the Dask scheduler: no answer to the connection within "
                         f"{wait:g} s (a firewall, or a host that is down)") from None
    except OSError as exc:
        raise InputError(f"{where}: cannot reach the Dask scheduler: {exc.strerror or exc}") from None
    with sock:
        _converse(sock, where, start + wait, start + seconds, wait)


def _converse(sock: socket.socket, where: str, greeted: float, deadline: float, wait: float) -> None:
    """The greeting (by the time ``greeted``, ``wait`` seconds from the start), this side's handshake,
    ``identity`` and ``close`` (by ``deadline``) on ``sock``."""
    try:
        greeting = _loads(_read_message(sock, greeted))
    except _Silent:
        raise InputError(f"{where}: not a Dask scheduler: {_silence(sock, deadline, wait)}") from None
    except _NotDask as exc:
        raise InputError(f"{where}: not a Dask scheduler: {_stranger(exc.args[0])}") from None
    except OSError as exc:
        raise InputError(f"{where}: not a Dask scheduler: the connection broke before its greeting "
                         f"({exc.strerror or type(exc).__name__})") from None
    if not isinstance(greeting, dict) or "pickle-protocol" not in greeting:
        raise InputError(f"{where}: not a Dask scheduler: its first message is not Dask's handshake")
    try:
        sock.sendall(_message({"compression": None, "python": tuple(sys.version_info)[:3],
                               "pickle-protocol": greeting["pickle-protocol"]}))
        sock.sendall(_message({"op": "identity", "reply": True}))
        identity = _loads(_read_message(sock, deadline))
        sock.sendall(_message({"op": "close", "reply": False}))
    except _Silent:
        raise InputError(f"{where}: not a Dask scheduler: it greets as Dask does but did not say what it is in "
                         "time") from None
    except (_NotDask, OSError):
        raise InputError(f"{where}: not a Dask scheduler: the connection broke after Dask's greeting") from None
    kind = identity.get("type") if isinstance(identity, dict) else None
    if kind != "Scheduler":
        what = f"a Dask {kind}" if isinstance(kind, str) else "a Dask server that does not say what it is"
        raise InputError(f"{where}: not a Dask scheduler: {what} answers there (give the scheduler's address, "
                         f"printed by `dask scheduler` as 'Scheduler at: tcp://HOST:PORT')")


def _stranger(start: bytes) -> str:
    """What a server that answered ``start`` (its first bytes) is, in words."""
    if start.startswith(b"HTTP/"):
        return _HTTP
    if not start:
        return "it closed the connection without a word"
    return f"it answered {start[:40]!r} instead of Dask's greeting"


class _Silent(Exception):
    """Nothing (or not all of a message) arrived before the deadline."""


class _NotDask(Exception):
    """Bytes that are not Dask's frames (the argument: the first of them; empty if the peer closed at once)."""


def _read_exactly(sock: socket.socket, count: int, deadline: float, seen: bytes = b"") -> bytes:
    """``count`` bytes from ``sock`` before ``deadline`` (``seen``: what came before them, for the error)."""
    chunks, got = [], 0
    while got < count:
        left = deadline - time.monotonic()
        if left <= 0:
            raise _Silent
        sock.settimeout(left)
        try:
            chunk = sock.recv(min(count - got, 1 << 20))
        except TimeoutError:
            raise _Silent from None
        if not chunk:
            raise _NotDask(seen + b"".join(chunks))
        chunks.append(chunk)
        got += len(chunk)
    return b"".join(chunks)


def _read_message(sock: socket.socket, deadline: float) -> bytes:
    """One message of Dask's TCP protocol without its 8-byte length: the frames' prelude (their count and sizes)
    and every frame. A length above :data:`MAX_MESSAGE` or a prelude that does not fit is not Dask's."""
    head = _read_exactly(sock, 8, deadline)
    (length,) = struct.unpack("Q", head)
    if not 16 <= length <= MAX_MESSAGE:
        raise _NotDask(head + _peek(sock))
    body = _read_exactly(sock, length, deadline, head)
    (count,) = struct.unpack_from("Q", body)
    if not 0 < count <= (length - 8) // 8:
        raise _NotDask(head + body)
    sizes = struct.unpack_from(f"{count}Q", body, 8)
    rest = 8 * (1 + count) + sum(sizes) - length
    if not 0 <= rest <= MAX_MESSAGE:
        raise _NotDask(head + body)
    return body + _read_exactly(sock, rest, deadline, head + body) if rest else body


def _peek(sock: socket.socket) -> bytes:
    """What else has arrived at once (up to 32 bytes), for an error message."""
    sock.settimeout(0.05)
    try:
        return sock.recv(32)
    except OSError:
        return b""


def _loads(message: bytes):
    """The object of one message of :func:`_read_message`, None if it is not Dask's msgpack (nothing of the
    peer's is unpickled)."""
    from distributed.protocol import loads
    from distributed.protocol.utils import unpack_frames

    try:
        return loads(list(unpack_frames(message)), deserialize=False)
    except Exception:  # noqa: BLE001 - not Dask's message: not a Dask server
        return None


def _message(msg: dict) -> bytes:
    """``msg`` as one message of Dask's TCP protocol (its length, the frames' prelude, the frames)."""
    from distributed.protocol import dumps
    from distributed.protocol.utils import pack_frames_prelude

    frames = [bytes(f) for f in dumps(msg)]
    body = pack_frames_prelude(frames) + b"".join(frames)
    return struct.pack("Q", len(body)) + body


#: An HTTP server where the scheduler should be, in words.
_HTTP = (f"an HTTP server answers there (a Dask dashboard? the scheduler itself listens on port {SCHEDULER_PORT} "
         "unless started with another)")


def _silence(sock: socket.socket, deadline: float, waited: float) -> str:
    """What a port that sent nothing for ``waited`` seconds is: an HTTP server (it answers ``GET /`` before
    ``deadline``) or a silent one."""
    try:
        sock.settimeout(max(deadline - time.monotonic(), 0.05))
        sock.sendall(b"GET / HTTP/1.0\r\nHost: mechatron\r\n\r\n")
        answer = sock.recv(16)
    except OSError:
        answer = b""
    if answer.startswith(b"HTTP/"):
        return _HTTP
    return f"it accepts connections but sent nothing within {waited:g} s (a Dask scheduler greets at once)"


def disconnect(client, scheduler: str | None) -> None:
    """Close the client, and the LocalCluster it started (a running scheduler stays)."""
    cluster = client.cluster if scheduler is None else None
    client.close()
    if cluster is not None:
        cluster.close()
