"""``mechatron optimize``: optimal design with CasADi from a spec (docs/optimize_file.md): named parameters chosen to
minimise an objective under requirements, checked with the Pinocchio model and compared with the best of a DOE."""

from __future__ import annotations

import argparse

from .common import add_output_options, emit
from .values import FILE


def cmd_optimize(args: argparse.Namespace) -> int:
    """Solve the spec and emit the optimum; exit 1 when a requirement is not met at the optimum (the Pinocchio
    model's), as ``size`` does without a feasible drive."""
    from ..studies.optimize import optimize, read_spec

    spec = read_spec(args.spec)
    result = optimize(spec)
    emit(result, args)
    return 0 if result.feasible else 1


def register(sub) -> None:
    p = sub.add_parser("optimize", help="optimal design of a mechanism's named parameters with CasADi (ipopt), "
                                        "compared with a DOE over the same box; exit 1 if a requirement is not "
                                        "met at the optimum")
    p.add_argument("spec", type=FILE, metavar="SPEC.toml", help="the optimisation spec (docs/optimize_file.md)")
    add_output_options(p)
    p.set_defaults(func=cmd_optimize)
