"""Comparing a file mechatron writes with the shipped one by what it says, not by the text of its numbers.

The last digit of a float's shortest text (``repr``) can differ between machines (their libm's sin, cos and sqrt
round the last bit differently: ``…0462415573`` on one, ``…04624155733`` on another), so a written file is compared
with its reference in two parts: the text with every float literal masked is equal (keys, order, comments, layout,
strings, integers), and the parsed values are equal, floats to a relative 1e-12 (TOML: :func:`assert_same_toml`).
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from pathlib import Path

from mechatron.io.toml import tomllib

#: A float literal (TOML and Python's repr): a decimal point or an exponent, or inf and nan.
FLOAT = re.compile(r"(?<![\w.])[-+]?(?:\d[\d_]*\.\d[\d_]*(?:[eE][-+]?\d+)?|\d[\d_]*[eE][-+]?\d+|inf|nan)(?![\w.])")

#: The tolerance of a float: relative, and absolute near zero (a coordinate that rounds to 1e-17 on one machine).
RELATIVE, ABSOLUTE = 1e-12, 1e-15


def masked(text: str) -> str:
    """``text`` with every float literal replaced by ``<float>``."""
    return FLOAT.sub("<float>", text)


def assert_same_values(a, b, where: str = "file") -> None:
    """Two parsed documents equal: the same keys in the same order, lists of the same length, the same strings,
    booleans and integers, floats within :data:`RELATIVE` (or :data:`ABSOLUTE` near zero)."""
    if isinstance(a, Mapping) and isinstance(b, Mapping):
        assert list(a) == list(b), f"{where}: keys {list(a)} != {list(b)}"
        for key in a:
            assert_same_values(a[key], b[key], f"{where}.{key}")
    elif isinstance(a, list) and isinstance(b, list):
        assert len(a) == len(b), f"{where}: {len(a)} items != {len(b)}"
        for k, (x, y) in enumerate(zip(a, b)):
            assert_same_values(x, y, f"{where}[{k}]")
    elif isinstance(a, float) and isinstance(b, float):
        assert math.isclose(a, b, rel_tol=RELATIVE, abs_tol=ABSOLUTE), f"{where}: {a!r} != {b!r}"
    else:
        assert type(a) is type(b) and a == b, f"{where}: {a!r} != {b!r}"


def assert_same_toml(written: Path, expected: Path) -> None:
    """``written`` says what ``expected`` says: its text equal with the floats masked, its floats within
    :data:`RELATIVE`."""
    text, reference = written.read_text(encoding="utf-8"), expected.read_text(encoding="utf-8")
    assert masked(text) == masked(reference), f"{written} and {expected} differ beyond their numbers"
    assert_same_values(tomllib.loads(text), tomllib.loads(reference), written.name)
