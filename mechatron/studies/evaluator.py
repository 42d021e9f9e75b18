"""One design through the analyses: the evaluation a study's runner and the optimal-design wing share.

:class:`Evaluator` holds what decides a row — the mechanism (its name or file), the analyses with their options and
the varied quantities (:class:`~mechatron.studies.ranges.Range`) — and turns rows of design values into rows of
outputs: the mechanism rebuilt with a design's geometry (``with_parameters``), each analysis' ``outputs`` with its
options (the file's, with the values of the quantities that target it) and the design's ``seed``. A design that
cannot be built or analysed is a row with ``status = "failed"`` and its ``reason``, never an exception.

An analysis is declared by the :class:`~mechatron.studies.analyses.Analysis` protocol (the modules of
:mod:`mechatron.studies.analyses`); one with exact first derivatives also follows
:class:`~mechatron.studies.analyses.GradientAnalysis`.
"""

from __future__ import annotations

import hashlib
import math
import time
import warnings
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..errors import MechatronWarning
from .analyses import Analysis as Analysis  # re-exported: the protocols live with the analyses
from .analyses import GradientAnalysis as GradientAnalysis

if TYPE_CHECKING:  # pragma: no cover
    from .ranges import Range

#: One row: the design's values (a variable's name → its value, ``seed``, ``design``) and, evaluated, ``status``,
#: ``reason`` and the outputs (SI units, finite numbers, flags, names).
Row = dict[str, Any]


# ------------------------------------------------------------------------------------ the mechanism
@lru_cache(maxsize=4)
def base_mechanism(mechanism: str, content: tuple[str | None, ...] = ()):
    """The study's mechanism as loaded from its name or file (once per process and ``content``: the SHA-256 of its
    files, so that an edited file is loaded anew)."""
    from ..library import load

    return load(mechanism)


def file_hash(path: str | Path) -> str | None:
    """SHA-256 of a file's bytes, None if it cannot be read."""
    try:
        with open(path, "rb") as fh:
            return hashlib.file_digest(fh, "sha256").hexdigest()
    except OSError:
        return None


def mechanism_content(mechanism: str) -> tuple[str | None, ...]:
    """The SHA-256 of each file the mechanism is read from (:func:`mechanism_files`)."""
    return tuple(file_hash(path) for path in mechanism_files(mechanism))


def study_mechanism(mechanism: str):
    """The mechanism of a study (its name or file), loaded once per process and content of its files: the spec's
    checks and every design of the study in this process (or on a worker) share it."""
    return base_mechanism(mechanism, mechanism_content(mechanism))


def mechanism_files(mechanism: str) -> list[Path]:
    """The files the mechanism is read from: its file (a name's: the file :func:`mechatron.library.load` reads)
    and, beside a URDF, the SRDF of its rotor parameters (if there is one)."""
    from ..library import robot_origins

    path = Path(mechanism) if Path(mechanism).is_file() else robot_origins().get(mechanism, (None, None))[1]
    if path is None:
        return []
    srdf = path.with_suffix(".srdf")
    return [path, srdf] if path.suffix.lower() == ".urdf" and srdf.is_file() else [path]


# ------------------------------------------------------------------------------------ a design's options
def analysis_options(analyses: Mapping[str, Mapping[str, Any]], parameters: Iterable[Range], name: str,
                     design: Mapping[str, Any]) -> dict[str, Any]:
    """The options of analysis ``name`` for one design: the file's, with the values of the quantities that target
    it (``target = "NAME.OPTION"``)."""
    out = dict(analyses[name])
    for p in parameters:
        if p.target and p.target.split(".", 1)[0] == name:
            out[p.target.split(".", 1)[1]] = design[p.name]
    return out


def design_geometry(parameters: Iterable[Range], design: Mapping[str, Any]) -> dict[str, float]:
    """The mechanism's parameters a design overrides (m, rad): its values of the quantities that target none."""
    return {p.name: float(design[p.name]) for p in parameters if p.target is None}


@dataclass(frozen=True)
class Evaluator:
    """Rows of designs → rows of outputs (see the module docstring); plain, picklable data (a Dask worker evaluates
    with a copy)."""

    mechanism: str
    analyses: Mapping[str, Mapping[str, Any]]
    parameters: tuple[Range, ...]

    def options(self, name: str, design: Mapping[str, Any]) -> dict[str, Any]:
        """:func:`analysis_options` of this evaluator's analyses."""
        return analysis_options(self.analyses, self.parameters, name, design)

    def evaluate(self, rows: Iterable[Row]) -> list[Row]:
        """Each row with ``status``, ``reason`` and the analyses' outputs added (each row needs ``seed``)."""
        return self.timed(rows)[0]

    def timed(self, rows: Iterable[Row]) -> tuple[list[Row], list[float]]:
        """:meth:`evaluate` and each design's time (s, wall)."""
        content = mechanism_content(self.mechanism)
        out, seconds = [], []
        for row in rows:
            start = time.perf_counter()
            out.append({**row, **self._one(row, content)})
            seconds.append(time.perf_counter() - start)
        return out, seconds

    def _one(self, design: Row, content: tuple[str | None, ...]) -> Row:
        """The outputs of one design, or its failure and the reason."""
        from .analyses import analysis

        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", MechatronWarning)
                mech = base_mechanism(self.mechanism, content)
                geometry = design_geometry(self.parameters, design)
                mech = mech.with_parameters(geometry) if geometry else mech
                out: Row = {}
                for name in self.analyses:
                    out.update(analysis(name).outputs(mech, self.options(name, design), int(design["seed"])))
            bad = [k for k, v in out.items() if not isinstance(v, (bool, str)) and not math.isfinite(float(v))]
            if bad:
                return {"status": "failed", "reason": f"{bad[0]} is not a finite number"}
            return {"status": "ok", "reason": "", **out}
        except Exception as exc:  # noqa: BLE001 - a design that fails is a row with its reason, never a crash
            text = str(exc).splitlines()[0] if str(exc) else ""
            return {"status": "failed", "reason": text or type(exc).__name__}
