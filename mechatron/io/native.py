"""C source compiled once into a shared library kept in a cache folder, for the kernels that run in machine code.

The library of a source text is compiled with the system's C compiler (``cc``, or the one in ``CC``; :data:`FLAGS`)
into the :func:`cache_folder` under the hash of the text and the options, and reused by every later process that
compiles the same text. Compiling is switched off with ``MECHATRON_COMPILE=0``; without a working compiler the
callers run their NumPy (or CasADi) path, which gives the same numbers to rounding.
"""

from __future__ import annotations

import hashlib
import os
import subprocess
import tempfile
from collections.abc import Callable
from pathlib import Path

#: The C compiler's options (portable code: the cache folder may be shared by machines of one architecture).
FLAGS = ("-O3", "-fno-math-errno", "-ffp-contract=off", "-shared", "-fPIC")
#: Environment variables: the cache folder, and 0 to run the kernels in CasADi's virtual machine or NumPy.
CACHE_VARIABLE, COMPILE_VARIABLE = "MECHATRON_CACHE", "MECHATRON_COMPILE"


def compiling() -> bool:
    """Whether kernels may be compiled (``MECHATRON_COMPILE`` is not ``0``)."""
    return os.environ.get(COMPILE_VARIABLE, "1").strip() != "0"


def settings() -> tuple:
    """What decides which library a source compiles to, as the environment gives it: the compile switch, the
    compiler and what names the cache folder (a process cache of loaded libraries is keyed by them; read in a
    microsecond, for callers that look a kernel up per call)."""
    environ = os.environ
    return tuple(environ.get(v) for v in (COMPILE_VARIABLE, "CC", CACHE_VARIABLE, "XDG_CACHE_HOME", "HOME"))


def cache_folder() -> Path:
    """Where compiled kernels are kept: ``MECHATRON_CACHE``, else ``$XDG_CACHE_HOME/mechatron/kernels`` or
    ``~/.cache/mechatron/kernels``."""
    if os.environ.get(CACHE_VARIABLE):
        return Path(os.environ[CACHE_VARIABLE])
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "mechatron" / "kernels"


def shared_library(name: str, write: Callable[[Path], bytes]) -> Path | None:
    """The shared library ``NAME_<hash>.so`` of the C text that ``write(folder)`` returns (it may write files into
    the temporary ``folder`` it is given, the text among them): compiled into the :func:`cache_folder`, or the one
    compiled there before from the same text; None when compiling is switched off or fails."""
    if not compiling():
        return None
    try:
        folder = cache_folder()
        folder.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryDirectory(dir=folder) as work:
            text = write(Path(work))
            source = Path(work) / f"{name}.c"
            source.write_bytes(text)
            digest = hashlib.sha256(text + " ".join(FLAGS).encode()).hexdigest()[:20]
            path = folder / f"{name}_{digest}.so"
            if not path.exists():
                partial = Path(work) / path.name
                compiler = os.environ.get("CC", "cc")
                subprocess.run([compiler, *FLAGS, "-o", str(partial), str(source), "-lm"], check=True,
                               capture_output=True, timeout=300)
                os.replace(partial, path)  # whole or not at all: concurrent runs may race, both write the same
        return path
    except (OSError, subprocess.SubprocessError, RuntimeError):
        return None
