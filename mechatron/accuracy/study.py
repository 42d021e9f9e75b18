r"""Tolerance studies of a point's position over poses [Egorov, chapter 8].

With the sensitivities J = ∂r/∂e of the error sources e (:mod:`~mechatron.accuracy.sensitivity`), tolerances
t_i, biases b_i and standard deviations σ_i (:class:`~mechatron.accuracy.sources.ErrorSource`), per axis:

- ``given`` — one set of signed errors e: Δr = J e [Egorov, 8.4], Δx, Δy, Δz [Egorov, 8.5], |Δr| [Egorov, 8.6];
  also the full nonlinear model's Δr for the same errors [Egorov, 8.2];
- ``worst`` — worst case: Δ = |J b| + Σ_i |J_i| t_i, every error at the end of its tolerance that hurts most;
- ``rss`` — statistical (root sum of squares): Δ = |J b| + k √(Σ_i (J_i σ_i)²), a k·σ estimate with σ_i the
  standard deviation of each source (:meth:`~mechatron.accuracy.sources.ErrorSource.sigma`). With normal errors
  (σ = t/k) it is √Σ(J t)², never above the worst case; with uniform (σ = t/√3) or triangular (σ = t/√6) errors
  it is k/√3 resp. k/√6 times that and can exceed the worst case (one uniform source ±t, k = 3: √3·t > t), as the
  worst case bounds the first-order error and RSS estimates its spread;
- ``mc`` — Monte Carlo of the full nonlinear model: seeded samples of every error from its distribution, the
  point's position computed exactly (:mod:`~mechatron.accuracy.nonlinear`); per axis |mean| + k·std, |Δr| at the
  coverage of ±k σ of a normal (99.73 % for k = 3), mean, standard deviation, percentiles, the yield against a
  limit, and each source's share of the variance (least-squares regression of Δr on the sampled errors). The
  samples are streamed in chunks (:mod:`~mechatron.accuracy.streaming`): moments by Chan's merge, the regression by
  its normal equations, quantiles exact up to 10⁶ samples per pose and within half a histogram bin beyond; memory
  does not grow with the samples. With a limit L also the process capability per pose
  (:mod:`~mechatron.accuracy.capability`): Pp and Ppk of each axis against ±L and of |Δr| against L, the parts per
  million out, each with its 95 % interval [ISO 22514-2; Bissell, 1990; Clopper, 1934]. With a target error the
  sample count of each pose is chosen as it runs, stopping once the relative standard error of σ (or of the PPM)
  is reached, ``samples`` the cap.

The worst case and RSS are the usual tolerance stack-ups built on the first-order error [Egorov, 8.4]; for both the
modulus is [Egorov, 8.6] of the per-axis values (an upper bound of the largest |Δr|). The shares of the linear
methods are Σ_axes |J_i| t_i / Σ (worst) and Σ_axes (J_i σ_i)² / Σ (variance).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError, SingularityError, UnreachableError
from ..io.values import LARGEST, number, numbers
from ..kinematics.loops import assemble
from ..model.mechanism import Mechanism
from .capability import AXES, capability_rows, check_target, next_count, ppm_error, sigma_error
from .nonlinear import PerturbedLoop, perturbed_positions
from .result import ToleranceResult
from .sensitivity import Sensitivities, coordinate_names, sensitivities
from .sources import POSE_BYTES, ErrorSource
from .streaming import BINS, EXACT_SAMPLES, CentralMoments, Moments, Quantiles, variance_shares

__all__ = ["METHODS", "ToleranceResult", "configurations", "draw_errors", "analyse_tolerances", "tolerance_study"]

Floats = NDArray[np.float64]

METHODS = ("given", "worst", "rss", "mc")
#: Samples per chunk of the vectorized Monte Carlo (and of the one-sample-at-a-time one).
CHUNK, SLOW_CHUNK = 32768, 1024
#: The Monte Carlo's Δr samples kept per pose for the charts and :attr:`ToleranceResult.samples` (the statistics use
#: every sample).
KEPT_SAMPLES = EXACT_SAMPLES


def configurations(mech: Mechanism, poses: ArrayLike, labels: Sequence[str] | None = None) -> Floats:
    """Full configurations q (N, nq) for poses given as coordinate values (N, n_c) (rad, m): one per joint of a
    serial mechanism (q = :meth:`~mechatron.model.Mechanism.configuration`, a continuous joint's angle becoming its
    (cos, sin)), the actuated inputs of a closed loop (assembled in order, each from the previous one)."""
    poses = np.atleast_2d(np.asarray(poses, dtype=float))
    names = coordinate_names(mech)
    if poses.shape[1] != len(names):
        raise InputError(f"a pose of {mech.name} gives {len(names)} values ({', '.join(names)})")
    labels = list(labels) if labels is not None else [str(i + 1) for i in range(len(poses))]
    if not mech.closures:
        return np.atleast_2d(mech.configuration(poses))
    out, guess = np.empty((len(poses), mech.nq)), None
    for i, pose in enumerate(poses):
        try:
            out[i] = guess = assemble(mech, dict(zip(names, pose)), guess=guess)
        except (UnreachableError, SingularityError) as exc:
            raise InputError(f"pose {labels[i]}: {exc}") from None
    return out


def _columns(study_sources: Sequence[ErrorSource], sens: Sensitivities) -> Floats:
    index = {name: i for i, name in enumerate(sens.sources)}
    return sens.matrix[:, :, [index[s.name] for s in study_sources]]


def analyse_tolerances(mech: Mechanism, sources: Sequence[ErrorSource], poses: ArrayLike,
                       labels: Sequence[str] | None = None, *, frame: str | None = None,
                       methods: Sequence[str] = ("worst", "rss"), k: float = 3.0, samples: int = 10000, seed: int = 0,
                       limit: float | None = None, progress: Callable[[int, int], None] | None = None,
                       target_error: float | None = None, target: str = "sigma") -> ToleranceResult:
    """Run the ``methods`` (of :data:`METHODS`, see the module) for the error ``sources`` at every pose.

    Args:
        mech: The mechanism.
        sources: The error sources (tolerances, biases and errors in SI: m, rad).
        poses: Coordinate values (N, n_c) or (n_c,) (rad, m): one per joint of a serial mechanism, the actuated
            coordinates of a closed loop (see :func:`configurations`).
        labels: A label per pose (default 1, 2, …).
        frame: The frame whose position is studied (default the tool frame).
        methods: Of ``given`` (Δr of the sources' errors [Egorov, 8.4–8.6]), ``worst``, ``rss``, ``mc``; the first
            is the main one.
        k: The coverage factor: σ = t/k for normal errors, results at ±kσ.
        samples, seed: Monte Carlo samples per pose (with ``target_error``: the most per pose) and the seed of their
            generator.
        limit: The largest acceptable |Δr| (m) for the Monte Carlo yield and capability
            (:mod:`~mechatron.accuracy.capability`).
        progress: Called with (samples done, samples in all) during the Monte Carlo; with a target error its
            ``status(text)``, where it has one, shows the relative error reached.
        target_error: With ``mc``: draw samples at each pose until the relative standard error of ``target`` is at
            most this (0 < E ≤ 0.5), ``samples`` at most.
        target: ``sigma`` (the standard deviation of every axis with a spread and of |Δr|, from the fourth moment)
            or ``ppm`` (the parts per million of |Δr| > ``limit``).
    """
    methods = tuple(methods)
    for m in methods:
        if m not in METHODS:
            raise InputError(f"unknown method {m!r}; expected one of: {', '.join(METHODS)} or all")
    if not sources:
        raise InputError("no error sources")
    k = number("k", k, minimum=0.1, maximum=100.0)
    if "mc" in methods:
        samples = number("samples", samples, integer=True, minimum=2)
    seed = number("seed", seed, integer=True, minimum=0)
    limit = number("limit", limit, positive=True, unit="m", allow_none=True)
    target_error = check_target(target_error, target, limit)
    if target_error is not None and "mc" not in methods:
        from ..io.budget import option

        raise InputError(f"{option('target_error')} needs the Monte Carlo (method mc or all)")
    if "given" in methods and any(s.error is None for s in sources):
        raise InputError("--method given needs an error for every source")
    frame = frame or mech.tool_frame
    poses = np.atleast_2d(numbers("poses", poses, minimum=-LARGEST, unit="rad or m"))
    from ..io.budget import count, require

    require(f"{count(len(poses))} poses", len(poses), POSE_BYTES + 64.0 * len(sources), advice="use fewer poses")
    if "mc" in methods:
        monte_carlo_budget(samples, len(sources), len(poses))
    labels = list(labels) if labels is not None else [str(i + 1) for i in range(len(poses))]
    Q = configurations(mech, poses, labels)
    if not mech.closures:
        mech.warn_limits(Q, "poses", [f"pose {label}" for label in labels])
    parameters = [s.name for s in sources if s.kind == "parameter"]
    coordinates = [s.name for s in sources if s.kind == "coordinate"]
    sens = sensitivities(mech, Q, frame, parameters, coordinates)
    J = _columns(sources, sens)  # (N, 3, n_e)
    t = np.array([s.tolerance for s in sources])
    sigma = np.array([s.sigma(k) for s in sources])
    bias = np.array([s.bias for s in sources])
    import pandas as pd

    table = pd.DataFrame({"label": labels})
    for j, name in enumerate(coordinate_names(mech)):
        table[name] = poses[:, j]
    table["x"], table["y"], table["z"] = sens.positions.T
    shift = np.abs(J @ bias)
    results: dict[str, Floats] = {}
    notes: list[str] = []
    if "given" in methods:
        error = np.array([s.error for s in sources])
        results["given"] = J @ error
        exact = _nonlinear_given(mech, frame, sources, Q, error)
        table["dr_nonlinear_given"] = np.linalg.norm(exact - sens.positions, axis=1)
    if "worst" in methods:
        results["worst"] = shift + np.abs(J) @ t
    if "rss" in methods:
        results["rss"] = shift + k * np.sqrt((J**2) @ sigma**2)
        if any(s.distribution != "normal" for s in sources):
            notes.append(f"rss is the k·σ estimate |J b| + k·√Σ(∂r/∂e·σ)² with σ = t/√3 (uniform), t/√6 (triangular), "
                         f"t/k (normal): with uniform or triangular errors it can exceed the worst case "
                         f"(one uniform ±t: {k:g}/√3·t)")
    variance = (J**2 * sigma**2).sum(axis=1)  # (N, n_e)
    for m, values in results.items():
        table[f"dx_{m}"], table[f"dy_{m}"], table[f"dz_{m}"] = values.T
        table[f"dr_{m}"] = np.linalg.norm(values, axis=1)
    mc_samples, mc_shares, capability = None, None, None
    lead = next((m for m in methods if m in results), None)  # the critical pose: the main method's largest |Δr|
    critical = int(np.argmax(table[f"dr_{lead}"])) if lead else 0
    if "mc" in methods:
        run = _MonteCarlo(samples, seed, k, limit, target_error, target, progress, notes)
        stats, mc_samples, mc_shares, critical, rows = run(mech, frame, sources, Q, sens.positions,
                                                           critical if lead else None, labels)
        for column, values in stats.items():
            table[column] = values
        capability = pd.DataFrame(rows) if rows else None
    shares = {
        "worst_share": 100 * (np.abs(J[critical]) * t).sum(axis=0) / max((np.abs(J[critical]) @ t).sum(), 1e-300),
        "variance_share": 100 * variance[critical] / max(variance[critical].sum(), 1e-300),
        "mean_variance_share": 100 * (variance / np.maximum(variance.sum(axis=1, keepdims=True), 1e-300)).mean(axis=0),
    }
    contributions = pd.DataFrame({
        "source": [s.name for s in sources], "kind": [s.kind for s in sources], "unit": [s.unit for s in sources],
        "tolerance": t, "distribution": [s.distribution for s in sources], "bias": bias,
        "sensitivity": np.linalg.norm(J[critical], axis=0), **shares})
    if mc_shares is not None:
        contributions["mc_share"] = mc_shares
    contributions = contributions.sort_values("variance_share", ascending=False, kind="stable").reset_index(drop=True)
    return ToleranceResult(mech.name, frame, methods, k, list(sources), table, contributions, sens, critical,
                           mc_samples, limit, notes, tuple(coordinate_names(mech)), capability,
                           target_error, target if target_error is not None else None)


def _nonlinear_given(mech: Mechanism, frame: str, sources: Sequence[ErrorSource], Q: Floats, error: Floats) -> Floats:
    """Positions (N, 3) (m) of the full model [Egorov, 8.2] with the given errors at every pose."""
    parameters = [s.name for s in sources if s.kind == "parameter"]
    dl = np.array([e for s, e in zip(sources, error) if s.kind == "parameter"])
    loop = PerturbedLoop(mech, frame, parameters)
    dq = _coordinate_errors(mech, sources, error[None, :])[0]
    out = np.empty((len(Q), 3))
    for i, q in enumerate(Q):
        try:
            out[i] = loop.position(q, dl, dq)
        except UnreachableError:
            out[i] = np.nan
    return out


def _coordinate_errors(mech: Mechanism, sources: Sequence[ErrorSource], errors: Floats) -> Floats:
    """Errors of the error coordinates as the evaluators take them: a joint error vector (N, nv) (velocity order,
    one coordinate per joint) of a serial mechanism, the actuated coordinates (N, n_act) of a closed loop."""
    if mech.closures:
        names = list(mech.actuated)
        columns = {name: n for n, name in enumerate(names)}
        out = np.zeros((len(errors), len(names)))
    else:
        columns = {name: mech.model.joints[mech.joint_id(name)].idx_v for name in mech.joint_names}
        out = np.zeros((len(errors), mech.nv))
    for j, s in enumerate(sources):
        if s.kind == "coordinate":
            out[:, columns[s.name]] = errors[:, j]
    return out


def draw_errors(sources: Sequence[ErrorSource], count: int, rng: np.random.Generator, k: float) -> Floats:
    """``count`` samples (count, n_e) of every source's error (SI): bias + normal(σ = t/k), uniform on ±t or
    triangular on ±t, drawn in double precision (single precision loses tolerances below its range: 1e-50 drew 0)."""
    out = np.empty((count, len(sources)))
    for j, s in enumerate(sources):
        if s.distribution == "normal":
            out[:, j] = rng.standard_normal(count) * s.sigma(k)
        elif s.distribution == "uniform":
            out[:, j] = (2 * rng.random(count) - 1) * s.tolerance
        else:
            out[:, j] = (rng.random(count) + rng.random(count) - 1) * s.tolerance
        out[:, j] += s.bias
    return out


#: Memory of the Monte Carlo (bytes; tracemalloc peaks of the PUMA with a margin): per sample of a chunk
#: (positions and temporaries of the evaluator, the moments' centred copy) plus per source and sample of a chunk
#: (the errors), per kept sample of a pose (at most :data:`KEPT_SAMPLES`: Δr of the pose and of the critical one,
#: |Δr| for the exact quantiles, their sorted copy), the quantiles' histogram past the exact store, and fixed. Time
#: per sample and pose (s: about 4e-6 s for the PUMA's 30 sources on an idle two-core machine, 13–25e-6 s busy).
MC_BYTES_PER_CHUNK_SAMPLE, MC_BYTES_PER_ERROR, MC_BYTES_PER_SAMPLE = 400.0, 48.0, 64.0
MC_FIXED_BYTES, MC_SECONDS = 2 * 2**20, 4e-6


def monte_carlo_budget(samples: float, sources: int, poses: int) -> float:
    """The memory (bytes) of a Monte Carlo of ``samples`` per pose over ``sources`` errors at ``poses`` poses, or
    :class:`~mechatron.io.budget.BudgetError` past the time limit (:mod:`mechatron.io.budget`). The memory stops
    growing at :data:`KEPT_SAMPLES` samples (the statistics are streamed): it is checked too, but no sample count
    exceeds it."""
    from ..io.budget import count, option, require, seconds

    name = option("samples")
    what = f"{name} {count(samples)}: the Monte Carlo"
    advice = f"use fewer {name} (its spread falls only as 1/√samples)"
    chunk = min(samples, CHUNK) * (MC_BYTES_PER_CHUNK_SAMPLE + MC_BYTES_PER_ERROR * sources)
    histogram = 16.0 * (BINS + 1) if samples > EXACT_SAMPLES else 0.0  # the counts and one bincount
    estimate = require(what, min(samples, KEPT_SAMPLES), MC_BYTES_PER_SAMPLE,
                       fixed=MC_FIXED_BYTES + chunk + histogram, advice=advice)
    seconds(f"{what} at {poses} pose(s)", samples * poses, MC_SECONDS, advice=advice + " or fewer poses")
    return estimate


class _MonteCarlo:
    """The Monte Carlo of a study: its options (``samples`` the count per pose, or the cap under a target error),
    called on the poses."""

    def __init__(self, samples: int, seed: int, k: float, limit: float | None, target_error: float | None,
                 target: str, progress: Callable[[int, int], None] | None, notes: list[str]) -> None:
        self.samples, self.seed, self.k, self.limit = samples, seed, k, limit
        self.target_error, self.target = target_error, target
        self.progress, self.notes = progress, notes
        self.status = getattr(progress, "status", None)

    def __call__(self, mech: Mechanism, frame: str, sources: Sequence[ErrorSource], Q: Floats, nominal: Floats,
                 critical: int | None, labels: Sequence[str]
                 ) -> tuple[dict[str, Floats], Floats, Floats, int, list[dict]]:
        """Monte Carlo statistics per pose, the first :data:`KEPT_SAMPLES` Δr samples (m) and the variance shares
        (%) at the critical pose (the given one, else the largest |Δr| at the coverage), that pose, and the
        capability rows (with a limit). The samples are drawn, evaluated and summarized chunk by chunk
        (:mod:`~mechatron.accuracy.streaming`): memory independent of ``samples``."""
        samples, k, limit, notes = self.samples, self.k, self.limit, self.notes
        parameters = [j for j, s in enumerate(sources) if s.kind == "parameter"]
        names = [sources[j].name for j in parameters]
        evaluator = perturbed_positions(mech, frame, names)
        chunk = SLOW_CHUNK if isinstance(evaluator, PerturbedLoop) else CHUNK
        if not evaluator.exact:
            notes.append("some placements are not products of one-parameter exponentials: the Monte Carlo is exact "
                         "in the coordinates and to first order in those parameters")
        coverage = math.erf(k / math.sqrt(2))
        stats = {c: np.empty(len(Q)) for c in ("dx_mc", "dy_mc", "dz_mc", "dr_mc", "mean_dr_mc", "std_dr_mc",
                                               "p50_dr_mc", "p95_dr_mc", "p99_dr_mc", "max_dr_mc", "failed_mc")}
        if limit is not None:
            stats["yield_mc"] = np.empty(len(Q))
        if self.target_error is not None:
            stats["samples_mc"], stats["reached_error_mc"] = np.empty(len(Q)), np.empty(len(Q))
        rows: list[dict] = []
        best = None  # (pose, kept Δr samples, moments) of the critical pose
        bound = 0.0
        m = len(sources)
        for i, q in enumerate(Q):
            rng = np.random.default_rng(self.seed)  # the same samples at every pose (common random numbers)
            summary = _Summary(samples, len(sources), limit)

            def chunk_of(errors: Floats, q: Floats = q, i: int = i) -> Floats:
                dl, dq = errors[:, parameters], _coordinate_errors(mech, sources, errors)
                return evaluator.positions(q, dl, dq) - nominal[i]

            drawn, error = self._run(summary, chunk_of, sources, rng, chunk, i, len(Q), labels[i])
            n = summary.moments.n
            if n < 2:
                raise InputError(f"pose {i + 1}: the loops do not close for the sampled errors")
            mean, std = summary.moments.mean[m:m + 3], np.sqrt(summary.moments.variance()[m:m + 3])
            stats["dx_mc"][i], stats["dy_mc"][i], stats["dz_mc"][i] = np.abs(mean) + k * std
            quantiles = summary.quantiles.quantiles([coverage, 0.5, 0.95, 0.99])
            bound = max(bound, summary.quantiles.bound)
            stats["dr_mc"][i], stats["p50_dr_mc"][i], stats["p95_dr_mc"][i], stats["p99_dr_mc"][i] = quantiles
            stats["mean_dr_mc"][i] = summary.moments.mean[m + 3]
            stats["std_dr_mc"][i] = math.sqrt(summary.moments.variance()[m + 3])
            stats["max_dr_mc"][i] = summary.quantiles.largest
            stats["failed_mc"][i] = drawn - n
            if self.target_error is not None:
                stats["samples_mc"][i], stats["reached_error_mc"][i] = drawn, error
            if limit is not None:
                stats["yield_mc"][i] = summary.within / n
                rows += self._capability(summary, str(labels[i]), limit)
            chosen = i == critical if critical is not None else \
                best is None or stats["dr_mc"][i] > stats["dr_mc"][best[0]]
            if chosen:
                best = (i, summary.kept[: summary.n_kept], summary.moments)
        if bound > 0:
            notes.append(f"more than {EXACT_SAMPLES:,} samples per pose: the Monte Carlo quantiles come from a "
                         f"histogram of {BINS:,} bins, within {bound:.2g} m (half a bin)")
        if self.target_error is not None:
            self._target_note(self.target_error, stats["reached_error_mc"])
        i, d, moments = best
        return stats, d, variance_shares(moments, len(sources)), i, rows

    def _run(self, summary: _Summary, evaluate: Callable[[Floats], Floats], sources: Sequence[ErrorSource],
             rng: np.random.Generator, chunk: int, pose: int, poses: int, label: str) -> tuple[int, float]:
        """Draw and evaluate the samples of one pose into ``summary``, chunk by chunk: all ``samples``, or under a
        target error until it is reached (:func:`~mechatron.accuracy.capability.next_count`). Returns the samples
        drawn and the relative error reached (NaN without a target)."""
        samples, target_error = self.samples, self.target_error
        total = poses * samples
        drawn, error = 0, math.nan
        while drawn < samples:
            if target_error is None:
                count = min(chunk, samples - drawn)
            else:
                count = next_count(summary.moments.n, error, target_error, self.target, chunk, samples)
                count = min(count, samples - drawn)
            errors = draw_errors(sources, count, rng, self.k)
            summary.add(errors, evaluate(errors))
            drawn += count
            if target_error is not None:
                error = self._error(summary)
                if self.status:
                    self.status(f"pose {label}: relative error of {self._what()} {error:.3g} (target {target_error:g})")
                if error <= target_error:
                    break
            if self.progress:
                self.progress(pose * samples + drawn, total)
        if self.progress and drawn < samples:
            self.progress((pose + 1) * samples, total)
        return drawn, error

    def _what(self) -> str:
        return "σ" if self.target == "sigma" else "the PPM"

    def _error(self, summary: _Summary) -> float:
        """The relative standard error of the target: of σ (every axis with a spread and |Δr|) or of the PPM."""
        if self.target == "sigma":
            h = summary.higher
            return sigma_error(h.n, h.m2 / max(h.n, 1), h.m4 / max(h.n, 1))
        return ppm_error(int(summary.over[-1]), summary.moments.n)

    def _capability(self, summary: _Summary, label: str, limit: float) -> list[dict]:
        """The capability rows of a pose against ``limit`` (m; :func:`~mechatron.accuracy.capability.capability_rows`)
        with its label, samples and the relative errors of σ and of the PPM."""
        h, n = summary.higher, summary.higher.n
        extra = {"samples": n, "sigma_error": sigma_error(n, h.m2 / n, h.m4 / n),
                 "ppm_error": ppm_error(int(summary.over[-1]), n)}
        m2 = h.m2 / n
        spread = m2 > 0
        skewness = np.where(spread, h.m3 / n / np.where(spread, m2, 1.0) ** 1.5, 0.0)
        kurtosis = np.where(spread, h.m4 / n / np.where(spread, m2, 1.0) ** 2, 3.0)
        return [{"label": label, **row, **extra}
                for row in capability_rows(limit, n, h.mean, h.std(), summary.over, skewness, kurtosis)]

    def _target_note(self, target_error: float, reached: Floats) -> None:
        """A remark naming the poses whose target error was not reached within the cap."""
        from ..io.budget import option

        missed = reached > target_error
        if missed.any():
            self.notes.append(f"the target relative error {target_error:g} of {self._what()} was not reached "
                              f"at {int(missed.sum())} of {len(reached)} poses within the cap of "
                              f"{option('samples')} {self.samples:,} (largest reached {np.nanmax(reached):.3g}): "
                              f"raise {option('samples')}")


class _Summary:
    """The streamed statistics of one pose: moments of [errors, Δr, |Δr|], the central moments to the fourth of
    [Δx, Δy, Δz, |Δr|], the |Δr| quantiles, the counts within the limit and beyond it (|Δx|, |Δy|, |Δz|, |Δr| >
    L), and the first :data:`KEPT_SAMPLES` Δr samples (for the charts)."""

    def __init__(self, samples: int, n_errors: int, limit: float | None) -> None:
        self.moments = Moments(n_errors + 4)
        self.higher = CentralMoments(len(AXES))
        self.quantiles = Quantiles(samples)
        self.limit, self.within = limit, 0
        self.over = np.zeros(len(AXES), dtype=np.int64)
        self.kept, self.n_kept = np.empty((min(samples, KEPT_SAMPLES), 3)), 0

    def add(self, errors: Floats, delta: Floats) -> None:
        """Add a chunk: the errors (m, n_e) and Δr (m, 3) (m); samples with NaN (loops not closed) are left out."""
        good = np.all(np.isfinite(delta), axis=1)
        if not good.all():
            errors, delta = errors[good], delta[good]
        r = np.linalg.norm(delta, axis=1)
        values = np.concatenate([delta, r[:, None]], axis=1)
        self.moments.add(np.concatenate([errors, values], axis=1))
        self.higher.add(values)
        self.quantiles.add(r)
        if self.limit is not None:
            self.within += int(np.count_nonzero(r <= self.limit))
            self.over += np.count_nonzero(np.abs(values) > self.limit, axis=0)
        take = min(len(delta), len(self.kept) - self.n_kept)
        self.kept[self.n_kept:self.n_kept + take] = delta[:take]
        self.n_kept += take


def tolerance_study(mech: Mechanism, tolerances: Sequence[ErrorSource] | str | Path,
                    poses: ArrayLike | str | Path | None = None, labels: Sequence[str] | None = None,
                    **options) -> ToleranceResult:
    """The positioning error of a point of ``mech`` from the tolerances of its parameters and joints
    [Egorov, chapter 8]: :func:`analyse_tolerances` with its inputs read from files where paths are given.

    Args:
        tolerances: A list of :class:`~mechatron.accuracy.sources.ErrorSource` or a tolerances CSV path.
        poses: Coordinate values (N, n_c) (rad, m), a poses CSV path, or ``None`` for the reference pose.
        **options: Passed to :func:`analyse_tolerances` (``frame``, ``methods``, ``k``, ``samples``, ``seed``,
            ``limit`` in m, ``progress``).
    """
    from .sources import read_poses, read_tolerances, reference_pose

    if isinstance(tolerances, (str, Path)):
        need = "error" if "given" in options.get("methods", ()) else "tolerance"
        tolerances = read_tolerances(tolerances, mech, need)
    if poses is None:
        poses, labels = reference_pose(mech), ["reference"]
    elif isinstance(poses, (str, Path)):
        poses, labels = read_poses(poses, mech)
    return analyse_tolerances(mech, tolerances, poses, labels, **options)

