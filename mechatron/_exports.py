"""Lazy re-exports for package ``__init__`` files (PEP 562): a name is imported from its module on first use, so
``import mechatron`` stays light (no pandas, matplotlib or CasADi until an analysis needs them)."""

from __future__ import annotations

import importlib
import importlib.util
from collections.abc import Callable
from typing import Any


def lazy_exports(namespace: dict[str, Any], exports: dict[str, str]) -> tuple[Callable[[str], Any],
                                                                           Callable[[], list[str]]]:
    """(``__getattr__``, ``__dir__``) for a package whose public ``exports`` map a name to the module (relative to
    the package) that defines it."""
    package = namespace["__name__"]

    def __getattr__(name: str) -> Any:
        if name not in exports:  # a subpackage or module, e.g. mechatron.kinematics after ``import mechatron``
            if name.startswith("_") or importlib.util.find_spec(f"{package}.{name}") is None:
                raise AttributeError(f"module {package!r} has no attribute {name!r}")
            return importlib.import_module(f".{name}", package)
        value = getattr(importlib.import_module(exports[name], package), name)
        namespace[name] = value
        return value

    def __dir__() -> list[str]:
        return sorted(set(namespace) | set(exports))

    return __getattr__, __dir__
