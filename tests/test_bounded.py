"""Bounded work (issue 13): every request whose memory (or time) grows with a count the user gives is estimated
before the work starts and refused past the limit in one line; the estimates bound the measured peaks (tracemalloc)
within FACTOR on small cases; the structural group search is bounded; the sizing's per-pair checks go a block of
samples at a time with the same results."""

from __future__ import annotations

import gc
import itertools
import tracemalloc

import numpy as np
import pytest
from corpus import assert_clean_error

from mechatron.errors import InputError
from mechatron.io import budget
from mechatron.library import load

#: An estimate is at least the measured peak and at most FACTOR times it.
FACTOR = 4.0
TOLERANCES = "examples/data/tolerances_puma560.csv"


def peak(function) -> tuple[int, object]:
    """The peak of the memory traced while ``function()`` runs, above what was traced before (bytes)."""
    gc.collect()
    tracemalloc.start()
    try:
        base = tracemalloc.get_traced_memory()[0]
        result = function()
        return tracemalloc.get_traced_memory()[1] - base, result
    finally:
        tracemalloc.stop()


def assert_bounds(estimate: float, measured: float) -> None:
    assert measured <= estimate <= FACTOR * measured, (estimate, measured, estimate / measured)


@pytest.fixture
def limit_gb(monkeypatch):
    """A fixed limit, whatever the machine has free."""
    monkeypatch.setenv(budget.ENVIRONMENT, "2")
    monkeypatch.delenv(budget.TIME_ENVIRONMENT, raising=False)
    return 2.0


@pytest.fixture(scope="module")
def puma():
    return load("puma560")


# ------------------------------------------------------------------------------------------------- the module
def test_limit_from_the_environment_and_the_api(monkeypatch):
    monkeypatch.delenv(budget.ENVIRONMENT, raising=False)
    default = budget.limit_bytes()
    available = budget.available_bytes()
    assert default == pytest.approx(budget.DEFAULT_FRACTION * available, rel=0.2) if available else \
        default == budget.FALLBACK_GB * budget.GIB
    monkeypatch.setenv(budget.ENVIRONMENT, "1.5")
    assert budget.limit_bytes() == 1.5 * budget.GIB
    with budget.memory_limit(0.25):
        assert budget.limit_bytes() == 0.25 * budget.GIB
    assert budget.limit_bytes() == 1.5 * budget.GIB
    for bad in ("0", "-1", "nan", "inf", "abc"):
        monkeypatch.setenv(budget.ENVIRONMENT, bad)
        with pytest.raises(InputError, match="MECHATRON_MEMORY_GB must be a finite number > 0"):
            budget.limit_bytes()
    with pytest.raises(InputError, match="memory_gb must be"):
        with budget.memory_limit(-2):
            pass


def test_refusal_is_one_line_with_the_figure_the_limit_and_the_way_out(limit_gb):
    with pytest.raises(budget.BudgetError) as info:
        budget.samples("dt", 1e-9, 5e9, 8.0, advice="use a larger {name} or a shorter move")
    assert str(info.value) == "dt 1e-09 gives 5.0e+09 samples (37 GiB, limit 2 GiB): use a larger dt or a " \
                              "shorter move"
    assert info.value.estimate == 4e10 and info.value.limit == 2 * budget.GIB
    with budget.command_line(), pytest.raises(budget.BudgetError, match=r"^--grid-step 1e-09 gives"):
        budget.samples("grid_step", 1e-9, 5e9, 8.0, advice="x")
    assert budget.require("x", 1000, 8.0, advice="-") == 8000.0
    with pytest.raises(budget.BudgetError, match="more memory than there is"):
        budget.require("x", float("inf"), 8.0, advice="-")


def test_time_limit(monkeypatch):
    monkeypatch.delenv(budget.TIME_ENVIRONMENT, raising=False)
    assert budget.time_limit_s() == budget.DEFAULT_TIME_S
    with pytest.raises(budget.BudgetError, match=r"^x \(at least 2.8 h, limit 60 min\): fewer$"):
        budget.seconds("x", 1e4, 1.0, advice="fewer")
    monkeypatch.setenv(budget.TIME_ENVIRONMENT, "1e5")
    assert budget.seconds("x", 1e4, 1.0, advice="fewer") == 1e4
    with budget.time_limit(10), pytest.raises(budget.BudgetError, match="limit 10 s"):
        budget.seconds("x", 11, 1.0, advice="fewer")


# ------------------------------------------------------------------------------- estimates bound the measured
def test_trajectory_and_loads_estimates_bound_the_measured_peak(puma):
    from mechatron.drives.loads import loads_bytes, trajectory_loads
    from mechatron.dynamics.motion import cycle, trajectory_bytes

    for mech in (puma, load("planar_2r")):
        ends = [np.zeros(mech.nv), np.ones(mech.nv)]
        cycle(mech, ends, dt=1e-2)  # warm caches
        measured, trajectory = peak(lambda: cycle(mech, ends, dt=2e-4))
        assert_bounds(len(trajectory) * trajectory_bytes(mech.nv), measured)
        measured, _ = peak(lambda: trajectory_loads(mech, trajectory))
        assert_bounds(len(trajectory) * loads_bytes(mech.nv), measured)


def test_monte_carlo_estimate_bounds_the_measured_peak(puma):
    from mechatron.accuracy.study import monte_carlo_budget, tolerance_study

    tolerance_study(puma, TOLERANCES, methods=("mc",), samples=1000)
    sources = sum(1 for line in open(TOLERANCES) if line.strip() and not line.startswith(("#", "parameter")))
    for samples in (30_000, 150_000):
        measured, _ = peak(lambda: tolerance_study(puma, TOLERANCES, methods=("mc",), samples=samples))
        assert_bounds(monte_carlo_budget(samples, sources, 1), measured)


def test_sweep_estimate_bounds_the_measured_peak():
    from mechatron.kinematics.sweeps import position_bytes, sweep

    for name in ("crank_slider", "six_bar_bucket", "grab", "delta", "front_shovel"):
        mech = load(name)
        sweep(mech, samples=3000, links=mech.link_names)  # kernels built
        fixed, per_position = position_bytes(mech)
        for samples in (400, 3000, 20_000):
            measured, _ = peak(lambda: sweep(mech, samples=samples, links=mech.link_names))
            assert_bounds(fixed + samples * per_position, measured)


@pytest.mark.parametrize("single_pass", [True, False])
def test_sizing_estimate_bounds_the_measured_peak(puma, monkeypatch, single_pass):
    from mechatron.drives import checks
    from mechatron.drives.loads import loads_bytes
    from mechatron.drives.sizing import size_mechanism, sizing_bytes, sizing_fixed_bytes
    from mechatron.drives.system import _catalog_counts
    from mechatron.dynamics.motion import Trajectory

    t = np.linspace(0.0, 4.0, 4000)
    q = 0.5 * np.sin(np.outer(t, np.arange(1, puma.nv + 1)) * 0.8)
    v, a = np.gradient(q, t, axis=0), np.gradient(np.gradient(q, t, axis=0), t, axis=0)
    names = [f"q{i + 1}" for i in range(puma.nv)]
    trajectory = Trajectory(t, puma.configuration(q), v, a, names, q, [True] * puma.nv)
    size_mechanism(puma, Trajectory(t[:50], trajectory.q[:50], v[:50], a[:50], names, q[:50], [True] * puma.nv),
                   single_pass=True)
    monkeypatch.setattr(checks, "SAMPLE_BLOCK", 1 << 15)  # full blocks at a test's size
    measured, _ = peak(lambda: size_mechanism(puma, trajectory, single_pass=single_pass))
    fixed = sizing_fixed_bytes(len(t), *_catalog_counts(None, None, None))
    assert_bounds(len(t) * (sizing_bytes(puma.nv, single_pass) + loads_bytes(puma.nv)) + fixed, measured)


# --------------------------------------------------------------------- the sizing's checks, a block at a time
def test_evaluation_in_blocks_of_samples_gives_the_same_checks(monkeypatch, puma):
    from mechatron.drives import checks
    from mechatron.drives.catalogs import default_catalog
    from mechatron.drives.converters import converters_for
    from mechatron.drives.duty import joint_duties
    from mechatron.dynamics.motion import cycle

    trajectory = cycle(puma, [np.zeros(6), np.full(6, 0.8), np.zeros(6)], dt=2e-3)
    duty = joint_duties(puma, trajectory)[1]
    motors = default_catalog("motors")
    conv = converters_for(duty, default_catalog("gearboxes"))
    whole = checks.evaluate(duty, motors, conv)
    monkeypatch.setattr(checks, "SAMPLE_BLOCK", 997)  # many blocks of samples, one pair per refine batch
    blocks = checks.evaluate(duty, motors, conv)
    assert len(checks._blocks(len(duty.t), len(conv))) > 10
    np.testing.assert_allclose(blocks.values, whole.values, rtol=1e-12, atol=0)
    np.testing.assert_array_equal(blocks.limits, whole.limits)


# ------------------------------------------------------------------------------------------ the group search
def test_group_search_is_bounded():
    import time

    from mechatron.structure.description import Pair, StructuralDescription
    from mechatron.structure.groups import decompose

    links = [f"L{i}" for i in range(1, 41)]
    chain = StructuralDescription("chain", links, [Pair(f"P{i}", 5, "R", (["0", *links][i], links[i]))
                                                    for i in range(40)], planar=True)
    start = time.perf_counter()
    assert decompose(chain).unplaced == tuple(links)  # an open chain of 40 pairs: no group, at once
    dense = StructuralDescription("dense", links, [Pair("P0", 4, "C", ("0", "L1"))] + [
        Pair(f"P{k + 1}", 4, "C", pair) for k, pair in enumerate(itertools.combinations(links, 2))], planar=True)
    with pytest.raises(InputError, match=r"^structure dense: the search for structural groups would try more "
                                         r"than 50,000 sets of links"):
        decompose(dense)
    assert time.perf_counter() - start < 30


# ---------------------------------------------------------------------------- the command line refuses cleanly
CLI_REFUSALS = [
    (["dynamics", "puma560", "--move", "0,0,0,0,0,0;1,1,1,1,1,1", "--dt", "1e-6", "--vmax", "1e-3"],
     ["--dt 1e-06 gives", "GiB", "use a larger --dt"]),
    (["dynamics", "planar_2r", "--move", "0,0;1,1;0,0", "--dwell", "100", "--dt", "1e-6"],
     ["--dt 1e-06", "limit 2 GiB", "dwells"]),
    (["tolerance", "puma560", "--tolerances", TOLERANCES, "--samples", "1000000000"],
     ["--samples 1.0e+09: the Monte Carlo", "at least", "use fewer --samples"]),  # memory is constant: time only
    (["tolerance", "puma560", "--tolerances", TOLERANCES, "--method", "mc", "--samples", "100000000"],
     ["--samples 1.0e+08", "at least", "limit 60 s"], {budget.TIME_ENVIRONMENT: "60"}),
    (["tolerance", "planar_2r", "--tolerances", "TOL2R", "--grid", "100000"],
     ["--grid 100000 gives 1.0e+10 poses", "use a smaller --grid"]),
    (["excavator", "--samples", "100000"], ["--samples 100,000 gives 6.0e+10 positions", "use fewer --samples"]),
    (["excavator", "--samples", "1000", "--json"], ["positions of front_shovel", "at least", "limit 60 min"]),
    (["reduced", "crank_slider", "--samples", "1000000000"], ["--samples 1.0e+09", "one-mass model", "GiB"]),
    (["reduced", "crank_slider", "--samples", "10000000"], ["--samples 1.0e+07", "at least", "h, limit 60 min"]),
    (["linkage", "front_shovel", "--samples", "100000000"], ["--samples 1.0e+08", "positions of front_shovel"]),
    (["dynamics", "crank_slider", "--move", "0;1000", "--dt", "1e-3"], ["the loads along 1.0e+06 samples",
                                                                         "use fewer samples"]),
    (["dynamics", "crank_slider", "--move", "0;1000", "--dt", "1e-1"], ["closed-loop loads at 10,003 positions",
                                                                         "at least 10 s, limit 5 s"],
     {budget.TIME_ENVIRONMENT: "5"}),
]


@pytest.mark.parametrize("case", CLI_REFUSALS, ids=lambda case: " ".join(case[0]))
def test_cli_refuses_growing_requests(case, capfd, tmp_path, limit_gb, monkeypatch):
    import shutil
    from pathlib import Path

    argv, names, environment = case if len(case) == 3 else (*case, {})
    for key, value in environment.items():
        monkeypatch.setenv(key, value)
    repo = Path(__file__).resolve().parents[1]
    shutil.copy(repo / TOLERANCES, tmp_path / "tolerances_puma560.csv")
    (tmp_path / "examples" / "data").mkdir(parents=True)
    shutil.copy(repo / TOLERANCES, tmp_path / TOLERANCES)
    (tmp_path / "TOL2R").write_text("parameter,tolerance\na1,1e-4\nq1,1e-3\n")
    assert_clean_error(argv, capfd, tmp_path, names)


def test_size_refuses_a_task_past_the_limit(capfd, tmp_path, monkeypatch):
    rows = 2000
    t = np.linspace(0.0, 2.0, rows)
    lines = ["t,q1,q2"] + [f"{x:.6f},{0.3 * np.sin(x):.6f},{0.2 * np.cos(x):.6f}" for x in t]
    (tmp_path / "long.csv").write_text("\n".join(lines) + "\n")
    monkeypatch.setenv(budget.ENVIRONMENT, "0.001")  # 1 MiB: 2,000 samples of planar_2r need more
    assert_clean_error(["size", "planar_2r", "--task", "long.csv", "--csv", "out.csv"], capfd, tmp_path,
                       ["sizing along 2,000 samples of planar_2r", "limit 0.001 GiB", "fewer samples"])


def test_cli_group_search_past_its_bound_names_the_file(capfd, tmp_path):
    links = [f"L{i}" for i in range(1, 41)]
    lines = ['name = "dense"', "planar = true", "links = [" + ", ".join(f'"{x}"' for x in links) + "]"]
    for k, (a, b) in enumerate([("0", "L1"), *itertools.combinations(links, 2)]):
        lines += ["[[pairs]]", f'name = "P{k}"', 'kind = "C"', f'links = ["{a}", "{b}"]']
    (tmp_path / "dense.toml").write_text("\n".join(lines) + "\n")
    assert_clean_error(["structure", "dense.toml"], capfd, tmp_path,
                       ["dense.toml: structure dense: the search for structural groups would try more than 50,000"])


def test_cli_task_file_dt_is_named_as_the_field(capfd, tmp_path, limit_gb):
    (tmp_path / "task.toml").write_text('name = "t"\ndt = 1e-6\nvmax = [1e-3, 1e-3]\n'
                                        'waypoints = [[0.0, 0.0], [1.0, 1.0]]\n')
    assert_clean_error(["size", "planar_2r", "--task", "task.toml"], capfd, tmp_path,
                       ["task.toml: field 'dt' 1e-06 gives", "samples", "limit 2 GiB", "use a larger dt"])


def test_study_refuses_poses_past_the_limit(puma):
    from mechatron.accuracy.study import tolerance_study

    with budget.memory_limit(0.001), pytest.raises(budget.BudgetError, match=r"^1,000 poses \(0.0047 GiB, limit "
                                                                             r"0.001 GiB\): use fewer poses$"):
        tolerance_study(puma, TOLERANCES, np.zeros((1000, 6)))


def test_simulation_steps_are_bounded(limit_gb):
    from mechatron.dynamics.integrate import time_steps

    assert time_steps(1.0, 1e-3) == 1000
    with pytest.raises(budget.BudgetError, match=r"^dt 1e-12 gives 1.0e\+12 steps over 1 s \(1.9e\+06 GiB, limit "
                                                 r"2 GiB\): use a larger dt or a shorter duration$"):
        time_steps(1.0, 1e-12)
    with pytest.raises(budget.BudgetError, match=r"^dt 1e-06 gives 1.0e\+06 steps over 1 s \(at least 100 s, limit "
                                                 r"10 s\)"), budget.time_limit(10):
        time_steps(1.0, 1e-6)
    with pytest.raises(InputError, match="dt must be a finite number > 0 s, got 0"):
        time_steps(1.0, 0.0)
