"""The data folders shipped with mechatron (``robots``, ``catalogs``)."""

from __future__ import annotations

from pathlib import Path

from ..errors import InputError

_PACKAGE_DIR = Path(__file__).resolve().parent.parent


def data_dir(name: str) -> Path:
    """A data folder shipped with mechatron (``robots`` or ``catalogs``): inside the installed package, or at the top
    of the source tree for a development checkout."""
    for candidate in (_PACKAGE_DIR / name, _PACKAGE_DIR.parent / name):
        if candidate.is_dir():
            return candidate
    raise InputError(f"mechatron's {name}/ folder is missing from the installation ({_PACKAGE_DIR})")
