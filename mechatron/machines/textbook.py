"""The textbook's single-loop mechanisms [Egorov, sections 4.1–4.3; figs. 4.2, 4.4–4.6, 4.18, 5.7, 8.3] ship as
mechanism files: ``robots/crank_slider.toml``, ``robots/scotch_yoke.toml`` and ``robots/slotted_link.toml`` are
their source (points, bodies, masses, joints, closures and the named lengths l1, l2, d), read by
:func:`mechatron.load` like any user's file.

The functions below only load those files (for the names listed in :data:`mechatron.machines.BUILTINS`):
``crank_slider(l1=0.2, l2=0.346)`` is ``mechatron.load("crank_slider", l1=0.2, l2=0.346)``.
"""

from __future__ import annotations

from ..model.mechanism import Mechanism


def shipped(name: str, **parameters: float) -> Mechanism:
    """The shipped mechanism file ``robots/{name}.toml``, built, with some named parameters changed (m)."""
    from ..io.data import data_dir
    from ..model.linkage import build_linkage
    from ..model.linkage_file import read_linkage_file

    mechanism = build_linkage(read_linkage_file(data_dir("robots") / f"{name}.toml"))
    return mechanism.with_parameters(parameters) if parameters else mechanism


def crank_slider(**parameters: float) -> Mechanism:
    """Central crank-slider, crank l1 = AB, rod l2 = BC (robots/crank_slider.toml) [Egorov, figs. 4.2, 4.18]."""
    return shipped("crank_slider", **parameters)


def scotch_yoke(**parameters: float) -> Mechanism:
    """Scotch-yoke (sine) mechanism, crank l1 = AB (robots/scotch_yoke.toml) [Egorov, fig. 4.4]."""
    return shipped("scotch_yoke", **parameters)


def slotted_link(**parameters: float) -> Mechanism:
    """Slotted-link (coulisse) mechanism, crank l1 = AB, pivots d = AC (robots/slotted_link.toml) [Egorov, fig. 4.5]."""
    return shipped("slotted_link", **parameters)
