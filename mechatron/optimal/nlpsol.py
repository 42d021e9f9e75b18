r"""The one call of CasADi's NLP solvers that both forms of ``mechatron optimize`` make (:func:`run_nlp`): a design
file's exact route (:mod:`~mechatron.optimal.exact`: ipopt on the analyses' exact first derivatives, a limited-memory
Hessian, a stop once too many trial designs failed) and a named problem's (:mod:`~mechatron.optimal.problems.nlp`:
ipopt or ``sqpmethod`` on SX expressions, exact first and second derivatives).

The problem is  min f(w)  s.t.  lbg ≤ g(w) ≤ ubg,  lbx ≤ w ≤ ubx  (``casadi.nlpsol``), solved from ``x0``; ipopt
silent (``print_level = 0``, no banner), to the relative tolerance ``tol`` in at most ``max_iter`` iterations, the
bounds honoured (``honor_original_bounds``); where ``failures`` counts the trial designs that failed (an output NaN,
from which ipopt's line search steps back), stopped once :data:`MAX_FAILED_TRIALS` have. What comes back
(:class:`NlpRun`): the solution w, the solver's ``success``, its return status (words), its iteration count and the
objective at each iteration.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .requirement import Vector

#: ipopt stops once this many of the designs its line search tries have failed (not assembled, refused by an
#: analysis; each an output NaN, from which the line search steps back): our rule, so that a search pressed
#: against designs that do not assemble ends in seconds, not minutes, with the best design it reached.
MAX_FAILED_TRIALS = 200


@dataclass
class NlpRun:
    """What ``casadi.nlpsol`` returned: the solution ``w``, ``success``, the return ``status``, the ``iterations``
    and the objective f at each iteration (``history``, unscaled: as the NLP states it)."""

    w: Vector
    success: bool
    status: str
    iterations: int
    history: list[float] = field(default_factory=list)


def run_nlp(name: str, terms: dict[str, Any], *, x0: Any, lbx: Any, ubx: Any, lbg: Any, ubg: Any,
            tolerance: float, max_iterations: int, solver: str = "ipopt", ipopt: dict[str, Any] | None = None,
            options: dict[str, Any] | None = None, failures: Callable[[], int] | None = None) -> NlpRun:
    """Solve the NLP ``terms`` (``x``, ``f``, ``g``: CasADi expressions) with ``solver`` (``ipopt`` or
    ``sqpmethod``; the module docstring): ``ipopt``, more of ipopt's options (e.g. its Hessian approximation, the
    constraint tolerance); ``options``, more of CasADi's; ``failures``, the count of failed trial designs so far
    (ipopt stops at :data:`MAX_FAILED_TRIALS`, its status then saying so)."""
    import casadi as ca

    settings: dict[str, Any] = {"print_time": False, **(options or {})}
    stop = None
    if failures is not None:
        stop = _stop_when_failing(failures, terms["x"].numel(), terms["g"].numel())
        settings["iteration_callback"] = stop
    if solver == "ipopt":
        settings["ipopt"] = {"print_level": 0, "sb": "yes", "tol": tolerance, "max_iter": max_iterations,
                             "honor_original_bounds": "yes", **(ipopt or {})}
    else:
        settings.update({"qpsol": "qrqp", "max_iter": max_iterations, "print_header": False,
                         "print_iteration": False, "print_status": False,
                         "qpsol_options": {"print_iter": False, "print_header": False, "error_on_fail": False},
                         "tol_pr": tolerance, "tol_du": tolerance})
    nlp = ca.nlpsol(name, solver, terms, settings)
    result = nlp(x0=x0, lbx=lbx, ubx=ubx, lbg=lbg, ubg=ubg)
    stats = nlp.stats()
    history = [float(v) for v in stats.get("iterations", {}).get("obj", [])]
    status = str(stats.get("return_status", ""))
    if stop is not None and stop.stopped and failures is not None:
        status = f"stopped after {failures()} failed trial designs ({MAX_FAILED_TRIALS} at most)"
    return NlpRun(np.array(result["x"]).ravel(), bool(stats["success"]), status,
                  int(stats.get("iter_count", len(history))), history)


def _stop_when_failing(failures: Callable[[], int], nx: int, ng: int) -> Any:
    """ipopt's iteration callback (CasADi's ``iteration_callback``) for an NLP of ``nx`` variables and ``ng``
    constraints: stop once ``failures()`` reaches :data:`MAX_FAILED_TRIALS` (its ``stopped``)."""
    import casadi as ca

    class Stop(ca.Callback):
        def __init__(self) -> None:
            ca.Callback.__init__(self)
            self.stopped = False
            self.construct("stop_when_failing", {})

        def get_n_in(self) -> int:
            return ca.nlpsol_n_out()

        def get_n_out(self) -> int:
            return 1

        def get_name_in(self, i: int) -> str:
            return ca.nlpsol_out(i)

        def get_sparsity_in(self, i: int) -> Any:
            name = ca.nlpsol_out(i)
            size = {"f": 1, "g": ng, "lam_g": ng, "lam_p": 0, "p": 0}.get(name, nx)
            return ca.Sparsity.dense(size, 1)

        def eval(self, arg: Any) -> Any:
            self.stopped = failures() >= MAX_FAILED_TRIALS
            return [1 if self.stopped else 0]

    return Stop()
