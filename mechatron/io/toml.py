"""Reading TOML files with errors that name the file."""

from __future__ import annotations

import copy
import hashlib
import sys
from pathlib import Path

from ..errors import InputError

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib


#: The files parsed last, by the SHA-1 of their bytes, newest last: a study reads the same task and mechanism files
#: for every design.
_PARSED: dict[bytes, dict] = {}
_KEPT = 64


def read_toml(path: str | Path) -> dict:
    """Parse a TOML file; a missing or malformed file raises :class:`InputError` naming it. A text parsed before
    (the same bytes) is not parsed again: the caller gets its own copy of the data."""
    path = Path(path)
    try:
        text = path.read_bytes()
        key = hashlib.sha1(text).digest()
        if key in _PARSED:
            _PARSED[key] = _PARSED.pop(key)
            return copy.deepcopy(_PARSED[key])
        data = tomllib.loads(text.decode("utf-8"))
        _PARSED[key] = copy.deepcopy(data)
        while len(_PARSED) > _KEPT:
            del _PARSED[next(iter(_PARSED))]
        return data
    except FileNotFoundError:
        raise InputError("no such file", file=path) from None
    except IsADirectoryError:
        raise InputError("is a directory, not a file", file=path) from None
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"not valid TOML: {exc}", file=path) from None
    except UnicodeDecodeError as exc:
        raise InputError(f"not a UTF-8 text file: {exc}", file=path) from None
