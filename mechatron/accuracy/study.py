r"""Tolerance studies of a point's position over poses (textbook chapter 8; anchors C for what tools report).

With the sensitivities J = ∂r/∂e of the error sources e (:mod:`~mechatron.accuracy.sensitivity`), tolerances
t_i, biases b_i and standard deviations σ_i (:class:`~mechatron.accuracy.sources.ErrorSource`), per axis:

- ``given`` — one set of signed errors e: Δr = J e (8.4), Δx, Δy, Δz (8.5), |Δr| (8.6); also the full nonlinear
  model's Δr for the same errors;
- ``worst`` — worst case: Δ = |J b| + Σ_i |J_i| t_i, every error at the end of its tolerance that hurts most;
- ``rss`` — statistical: Δ = |J b| + k √(Σ_i (J_i σ_i)²) (k = 3: with normal errors σ = t/3 and Δ = √Σ(J t)²);
- ``mc`` — Monte Carlo of the full nonlinear model: seeded samples of every error from its distribution, the
  point's position computed exactly (:mod:`~mechatron.accuracy.nonlinear`); per axis |mean| + k·std, |Δr| at the
  coverage of ±k σ of a normal (99.73 % for k = 3), mean, standard deviation, percentiles, the yield against a
  limit, and each source's share of the variance (least-squares regression of Δr on the sampled errors).

For worst and rss the modulus is (8.6) of the per-axis values (an upper bound of the largest |Δr|). The shares of
the linear methods are Σ_axes |J_i| t_i / Σ (worst) and Σ_axes (J_i σ_i)² / Σ (variance).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from ..errors import InputError, SingularityError, UnreachableError
from ..kinematics.loops import assemble
from ..model.mechanism import Mechanism
from .nonlinear import PerturbedChain, PerturbedLoop, sample_positions
from .sensitivity import Sensitivities, coordinate_names, sensitivities
from .sources import ErrorSource

METHODS = ("given", "worst", "rss", "mc")
#: Samples per chunk of the vectorized Monte Carlo.
CHUNK = 32768
#: Samples used for the Monte Carlo's variance shares (a least-squares fit).
REGRESSION_SAMPLES = 100_000


def configurations(mech: Mechanism, poses: np.ndarray, labels: Sequence[str] | None = None) -> np.ndarray:
    """Full configurations (N, nq) for poses given as coordinate values (N, n_c): the joints of a serial mechanism,
    the actuated inputs of a closed loop (assembled in order, each from the previous one)."""
    poses = np.atleast_2d(np.asarray(poses, dtype=float))
    names = coordinate_names(mech)
    if poses.shape[1] != len(names):
        raise InputError(f"a pose of {mech.name} gives {len(names)} values ({', '.join(names)})")
    labels = list(labels) if labels is not None else [str(i + 1) for i in range(len(poses))]
    if not mech.closures:
        return poses.copy()
    out, guess = np.empty((len(poses), mech.nq)), None
    for i, pose in enumerate(poses):
        try:
            out[i] = guess = assemble(mech, dict(zip(names, pose)), guess=guess)
        except (UnreachableError, SingularityError) as exc:
            raise InputError(f"pose {labels[i]}: {exc}") from None
    return out


@dataclass
class StudyResult:
    """The study over every pose: ``poses`` (per-pose table: label, coordinates, nominal x, y, z and, per method,
    dx_, dy_, dz_, dr_<method> and Monte Carlo statistics), ``contributions`` (per source, at the critical pose and
    averaged over the poses), the sensitivities, and the Monte Carlo samples of the critical pose (Δr, (N, 3))."""

    mechanism: str
    frame: str
    methods: tuple[str, ...]
    k: float
    sources: list[ErrorSource]
    poses: pd.DataFrame
    contributions: pd.DataFrame
    sensitivities: Sensitivities
    critical: int
    samples: np.ndarray | None = None
    limit: float | None = None
    notes: list[str] = field(default_factory=list)

    @property
    def main_method(self) -> str:
        return self.methods[0]

    def records(self) -> list[dict]:
        """One object per pose: label, coordinates, x, y, z, dx, dy, dz, dr of the main method (the first of
        ``methods``), and every method's numbers under ``methods``."""
        out = []
        names = coordinate_names_from(self.poses)
        for _, row in self.poses.iterrows():
            record = {"pose": row["label"], "coordinates": {n: float(row[n]) for n in names},
                      "x": float(row["x"]), "y": float(row["y"]), "z": float(row["z"])}
            for axis in ("dx", "dy", "dz", "dr"):
                record[axis] = float(row[f"{axis}_{self.main_method}"])
            record["methods"] = {m: {c[: -len(m) - 1]: _plain(row[c]) for c in self.poses.columns
                                     if c.endswith("_" + m)} for m in self.methods}
            out.append(record)
        return out


def coordinate_names_from(table: pd.DataFrame) -> list[str]:
    fixed = {"label", "x", "y", "z"}
    return [c for c in table.columns if c not in fixed and not any(c.endswith("_" + m) for m in METHODS)]


def _plain(value):
    value = float(value)
    return value if math.isfinite(value) else None


def _columns(study_sources: Sequence[ErrorSource], sens: Sensitivities) -> np.ndarray:
    index = {name: i for i, name in enumerate(sens.sources)}
    return sens.matrix[:, :, [index[s.name] for s in study_sources]]


def run_study(mech: Mechanism, sources: Sequence[ErrorSource], poses: np.ndarray, labels: Sequence[str] | None = None,
              *, frame: str | None = None, methods: Sequence[str] = ("worst", "rss"), k: float = 3.0,
              samples: int = 10000, seed: int = 0, limit: float | None = None,
              progress: Callable[[int, int], None] | None = None) -> StudyResult:
    """Run the ``methods`` (of :data:`METHODS`) for the error ``sources`` at every pose (coordinate values, see
    :func:`configurations`). ``k``: the coverage factor (σ = t/k for normal errors, results at ±kσ); ``samples``
    and ``seed``: the Monte Carlo; ``limit``: the largest acceptable |Δr| (m) for the yield."""
    methods = tuple(methods)
    for m in methods:
        if m not in METHODS:
            raise InputError(f"unknown method {m!r}; expected one of: {', '.join(METHODS)} or all")
    if not sources:
        raise InputError("no error sources")
    if not (k > 0 and math.isfinite(k)):
        raise InputError(f"the coverage factor k must be > 0, got {k:g}")
    if "mc" in methods and not samples >= 2:
        raise InputError(f"the Monte Carlo needs at least 2 samples, got {samples}")
    if "given" in methods and any(s.error is None for s in sources):
        raise InputError("--method given needs an error for every source")
    frame = frame or mech.tool_frame
    poses = np.atleast_2d(np.asarray(poses, dtype=float))
    labels = list(labels) if labels is not None else [str(i + 1) for i in range(len(poses))]
    Q = configurations(mech, poses, labels)
    parameters = [s.name for s in sources if s.kind == "parameter"]
    coordinates = [s.name for s in sources if s.kind == "coordinate"]
    sens = sensitivities(mech, Q, frame, parameters, coordinates)
    J = _columns(sources, sens)  # (N, 3, n_e)
    t = np.array([s.tolerance for s in sources])
    sigma = np.array([s.sigma(k) for s in sources])
    bias = np.array([s.bias for s in sources])
    table = pd.DataFrame({"label": labels})
    for j, name in enumerate(coordinate_names(mech)):
        table[name] = poses[:, j]
    table["x"], table["y"], table["z"] = sens.positions.T
    shift = np.abs(J @ bias)
    results: dict[str, np.ndarray] = {}
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
    variance = (J**2 * sigma**2).sum(axis=1)  # (N, n_e)
    for m, values in results.items():
        table[f"dx_{m}"], table[f"dy_{m}"], table[f"dz_{m}"] = values.T
        table[f"dr_{m}"] = np.linalg.norm(values, axis=1)
    mc_samples, mc_shares = None, None
    lead = next((m for m in methods if m in results), None)  # the critical pose: the main method's largest |Δr|
    critical = int(np.argmax(table[f"dr_{lead}"])) if lead else 0
    if "mc" in methods:
        stats, mc_samples, mc_shares, critical = _monte_carlo(mech, frame, sources, Q, sens.positions, samples, seed,
                                                              k, limit, critical if lead else None, progress, notes)
        for column, values in stats.items():
            table[column] = values
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
    return StudyResult(mech.name, frame, methods, k, list(sources), table, contributions, sens, critical, mc_samples,
                       limit, notes)


def _nonlinear_given(mech: Mechanism, frame: str, sources: Sequence[ErrorSource], Q: np.ndarray,
                     error: np.ndarray) -> np.ndarray:
    """Positions (N, 3) of the full model with the given errors at every pose."""
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


def _coordinate_errors(mech: Mechanism, sources: Sequence[ErrorSource], errors: np.ndarray) -> np.ndarray:
    """Errors of the error coordinates (N, n) as the evaluators take them: a full (N, nq) joint vector for a serial
    mechanism, the actuated coordinates (N, n_act) of a closed loop."""
    names = list(mech.actuated) if mech.closures else mech.joint_names
    out = np.zeros((len(errors), len(names)))
    for j, s in enumerate(sources):
        if s.kind == "coordinate":
            out[:, names.index(s.name)] = errors[:, j]
    if not mech.closures:  # joint order → q index
        full = np.zeros((len(errors), mech.nq))
        for n, name in enumerate(names):
            full[:, mech.model.joints[mech.joint_id(name)].idx_q] = out[:, n]
        return full
    return out


def draw_errors(sources: Sequence[ErrorSource], count: int, rng: np.random.Generator, k: float) -> np.ndarray:
    """``count`` samples (count, n_e) of every source's error: bias + normal(σ = t/k), uniform on ±t or
    triangular on ±t (drawn in single precision: ample for errors, twice as fast)."""
    out = np.empty((count, len(sources)))
    for j, s in enumerate(sources):
        if s.distribution == "normal":
            out[:, j] = rng.standard_normal(count, dtype=np.float32) * s.sigma(k)
        elif s.distribution == "uniform":
            out[:, j] = (2 * rng.random(count, dtype=np.float32) - 1) * s.tolerance
        else:
            out[:, j] = (rng.random(count, dtype=np.float32) + rng.random(count, dtype=np.float32) - 1) * s.tolerance
        out[:, j] += s.bias
    return out


def _monte_carlo(mech, frame, sources, Q, nominal, samples, seed, k, limit, critical, progress, notes):
    parameters = [j for j, s in enumerate(sources) if s.kind == "parameter"]
    names = [sources[j].name for j in parameters]
    serial = not mech.closures
    evaluator = PerturbedChain(mech, frame, names) if serial else PerturbedLoop(mech, frame, names)
    if not evaluator.exact:
        notes.append("some placements are not products of one-parameter exponentials: the Monte Carlo is exact "
                     "in the coordinates and to first order in those parameters")
    coverage = math.erf(k / math.sqrt(2))
    total = len(Q) * samples
    stats = {c: np.empty(len(Q)) for c in ("dx_mc", "dy_mc", "dz_mc", "dr_mc", "mean_dr_mc", "std_dr_mc",
                                           "p50_dr_mc", "p95_dr_mc", "p99_dr_mc", "max_dr_mc", "failed_mc")}
    if limit is not None:
        stats["yield_mc"] = np.empty(len(Q))
    best = None  # (pose, Δr samples, error samples) of the critical pose
    for i, q in enumerate(Q):
        rng = np.random.default_rng(seed)  # the same samples at every pose (common random numbers)
        delta = np.empty((samples, 3))
        regression = min(samples, REGRESSION_SAMPLES)
        errors_kept = np.empty((regression, len(sources)))
        for start in range(0, samples, CHUNK):
            count = min(CHUNK, samples - start)
            errors = draw_errors(sources, count, rng, k)
            if start < regression:
                errors_kept[start:min(start + count, regression)] = errors[: regression - start]
            dl, dq = errors[:, parameters], _coordinate_errors(mech, sources, errors)
            if serial:
                delta[start:start + count] = evaluator.positions(q, dl, dq) - nominal[i]
            else:
                positions, _ = sample_positions(lambda n: evaluator.position(q, dl[n], dq[n]), count)
                delta[start:start + count] = positions - nominal[i]
            if progress:
                progress(i * samples + start + count, total)
        good = np.all(np.isfinite(delta), axis=1)
        d = delta[good]
        if len(d) < 2:
            raise InputError(f"pose {i + 1}: the loops do not close for the sampled errors")
        r = np.linalg.norm(d, axis=1)
        mean, std = d.mean(axis=0), d.std(axis=0, ddof=1)
        stats["dx_mc"][i], stats["dy_mc"][i], stats["dz_mc"][i] = np.abs(mean) + k * std
        quantiles = np.quantile(r, [coverage, 0.5, 0.95, 0.99])
        stats["dr_mc"][i], stats["p50_dr_mc"][i], stats["p95_dr_mc"][i], stats["p99_dr_mc"][i] = quantiles
        stats["mean_dr_mc"][i], stats["std_dr_mc"][i] = r.mean(), r.std(ddof=1)
        stats["max_dr_mc"][i] = r.max()
        stats["failed_mc"][i] = samples - len(d)
        if limit is not None:
            stats["yield_mc"][i] = float(np.mean(r <= limit))
        chosen = i == critical if critical is not None else best is None or stats["dr_mc"][i] > stats["dr_mc"][best[0]]
        if chosen:
            best = (i, d, errors_kept[good[:regression]])
    i, d, e = best
    return stats, d, _variance_shares(d[: len(e)], e), i


def _variance_shares(delta: np.ndarray, errors: np.ndarray) -> np.ndarray:
    """Each source's share (%) of the total variance of Δr: Σ_axes (β_i σ_i)² / Σ_axes var, β from a least-squares
    fit of Δr on the sampled errors."""
    centred = errors - errors.mean(axis=0)
    response = delta - delta.mean(axis=0)
    beta, *_ = np.linalg.lstsq(centred, response, rcond=None)  # (n_e, 3)
    spread = centred.std(axis=0)
    part = ((beta * spread[:, None]) ** 2).sum(axis=1)
    return 100 * part / max(response.var(axis=0).sum(), 1e-300)


def tolerance_study(mech: Mechanism, tolerances, poses=None, labels: Sequence[str] | None = None,
                    **options) -> StudyResult:
    """The positioning error of a point of ``mech`` from the tolerances of its parameters and joints
    ([Egorov, chapter 8]): :func:`run_study` with its inputs read from files where paths are given.

    Args:
        tolerances: A list of :class:`~mechatron.accuracy.sources.ErrorSource` or a tolerances CSV path.
        poses: Coordinate values (N, n_c) (rad, m), a poses CSV path, or ``None`` for the reference pose.
        **options: Passed to :func:`run_study` (``frame``, ``methods``, ``k``, ``samples``, ``seed``, ``limit`` in m,
            ``progress``).
    """
    from .sources import read_poses, read_tolerances, reference_pose

    if isinstance(tolerances, (str, Path)):
        need = "error" if "given" in options.get("methods", ()) else "tolerance"
        tolerances = read_tolerances(tolerances, mech, need)
    if poses is None:
        poses, labels = reference_pose(mech), ["reference"]
    elif isinstance(poses, (str, Path)):
        poses, labels = read_poses(poses, mech)
    return run_study(mech, tolerances, poses, labels, **options)

