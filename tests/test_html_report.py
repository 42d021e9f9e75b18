"""The HTML report (``--report FILE.html`` on size, tolerance and linkage) opened in a real headless browser.

Each report is written by the command line, then loaded by Chromium from the file system with networking off: the
page must log nothing to the console (no error, no blocked load, no injected script), every chart must decode (the
report's script counts them), the tables must hold every check of every joint and every pose, and the file must
name nothing to load but ``data:`` images and in-page anchors. The numbers checked are those of the hand rules the
report states (margin = 1 − value/limit, PASS when value ≤ limit or |Δr| ≤ the limit) and, for the four-bar, the
closed-form smallest transmission angle.
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import os
import re
import shutil
import subprocess
from html.parser import HTMLParser
from pathlib import Path

import pandas as pd
import pytest

from mechatron.cli import main
from mechatron.errors import InputError
from mechatron.report.html import Chart, Code, Method, Report, Section, Table, Text, render
from mechatron.report.references import REFERENCES

ROOT = Path(__file__).resolve().parent.parent
DATA = ROOT / "examples" / "data"
BROWSERS = ("chromium", "chromium-browser", "google-chrome")


# ------------------------------------------------------------------------------------------------------ helpers
def run(*argv: str) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(list(argv))
    return code, out.getvalue(), err.getvalue()


def browser() -> str:
    found = next((path for path in map(shutil.which, BROWSERS) if path), None)
    if found is None:
        message = "no Chromium to open the HTML report in (.ci/run installs the system's chromium package)"
        if os.environ.get("MECHATRON_SKIP_BROWSER"):  # only when asked: by default the browser check must run
            pytest.skip(message)
        pytest.fail(message)
    return found


def open_in_browser(path: Path, tmp_path: Path) -> tuple[str, list[str]]:
    """The DOM of ``path`` after its scripts ran, and the console messages, from headless Chromium."""
    result = subprocess.run(
        [browser(), "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run", "--disable-background-networking",
         "--disable-component-update", "--disable-sync", f"--user-data-dir={tmp_path / 'browser'}",
         "--enable-logging=stderr", "--v=0", "--window-size=1000,800", "--dump-dom", path.resolve().as_uri()],
        capture_output=True, text=True, timeout=90)
    assert result.returncode == 0, result.stderr[-2000:]
    console = [line for line in result.stderr.splitlines() if "CONSOLE" in line]
    return result.stdout, console


class Page(HTMLParser):
    """What a test needs of a DOM: its tables (by ``data-table``) as rows of cell texts, its images, the ids,
    every src/href, the citations, the body's attributes and the text of each section."""

    def __init__(self, text: str):
        super().__init__(convert_charrefs=True)
        self.tables: dict[str, list[list[str]]] = {}
        self.headers: dict[str, list[str]] = {}
        self.images: list[str] = []
        self.ids: set[str] = set()
        self.links: list[str] = []
        self.citations: list[str] = []
        self.body: dict[str, str] = {}
        self.sections: dict[str, str] = {}
        self.tags: list[str] = []
        self._table: str | None = None
        self._row: list[str] | None = None
        self._cell: list[str] | None = None
        self._section: str | None = None
        self.feed(text)

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        self.tags.append(tag)
        if "id" in attrs:
            self.ids.add(attrs["id"])
        for key in ("src", "href"):
            if key in attrs:
                self.links.append(attrs[key])
        if tag == "body":
            self.body = attrs
        elif tag == "section":
            self._section = attrs.get("id")
            self.sections[self._section] = ""
        elif tag == "table":
            self._table = attrs.get("data-table") or f"#{len(self.tables)}"
            self.tables[self._table] = []
        elif tag == "tr" and self._table is not None:
            self._row = []
        elif tag in ("td", "th") and self._row is not None:
            self._cell = []
        elif tag == "img":
            self.images.append(attrs.get("src", ""))
        elif tag == "a" and "citation" in attrs.get("class", ""):
            self.citations.append(attrs["href"])

    def handle_endtag(self, tag):
        if tag in ("td", "th") and self._cell is not None:
            self._row.append("".join(self._cell).strip())
            self._cell = None
        elif tag == "tr" and self._row is not None:
            if self._row and self._table is not None:
                if not self.headers.get(self._table):
                    self.headers[self._table] = self._row
                else:
                    self.tables[self._table].append(self._row)
            self._row = None
        elif tag == "table":
            self._table = None
        elif tag == "section":
            self._section = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell.append(data)
        if self._section is not None:
            self.sections[self._section] += data

    def table(self, name: str) -> pd.DataFrame:
        """The table ``name`` as text cells, its header row as the columns."""
        return pd.DataFrame(self.tables[name], columns=self.headers[name])


def check_page(path: Path, tmp_path: Path) -> Page:
    """Open ``path`` in the browser and check what every report must: no console message, every chart decoded,
    nothing to load but data: images and in-page anchors, every citation resolved to its full reference."""
    text = path.read_text(encoding="utf-8")
    assert not re.search(r"https?://", text), "the report names a URL"
    assert "url(" not in text and "@import" not in text
    dom, console = open_in_browser(path, tmp_path)
    assert console == [], "\n".join(console)
    page = Page(dom)
    assert page.images and all(src.startswith("data:image/png;base64,") for src in page.images)
    assert page.body.get("data-charts-shown") == f"{len(page.images)} of {len(page.images)}"
    assert page.body.get("data-page-width") == "fits", "the page is wider than the window (a table overflows)"
    assert not [name for name, text in page.sections.items() if "**" in text], "markup shown as text"
    for link in page.links:
        assert link.startswith(("data:", "#")), link
        assert not link.startswith("#") or link[1:] in page.ids, f"{link} points nowhere"
    for href in page.citations:
        assert href[1:] in page.ids
    return page


def number(cell: str) -> float:
    return float(cell)


# --------------------------------------------------------------------------------------------------- the commands
def test_size_report_has_every_check_of_every_joint(tmp_path):
    path = tmp_path / "puma.html"
    code, out, err = run("size", "puma560", "--json", "--report", str(path))
    assert code == 0 and f"wrote {path}" in err
    result = json.loads(out)
    page = check_page(path, tmp_path)

    # every check of every joint, as --json gives them, margin = 1 − value/limit and PASS iff value ≤ limit
    for joint in result["joints"]:
        table = page.table(f"checks {joint['joint']}")
        assert list(table["check"]) == [c["name"] for c in joint["checks"]]
        for (_, row), check in zip(table.iterrows(), joint["checks"]):
            value, limit, margin = number(row["value"]), number(row["limit"]), number(row["margin"])
            rpm = check["unit"] == "rad/s"  # speeds in rpm, as the text report gives them: n = 60 ω / 2π
            assert row["unit"] == ("rpm" if rpm else check["unit"])
            assert value == pytest.approx(check["value"] * (30 / math.pi if rpm else 1), rel=1e-5)
            assert limit == pytest.approx(check["limit"] * (30 / math.pi if rpm else 1), rel=1e-5)
            assert margin == pytest.approx(1 - value / limit, rel=1e-4, abs=1e-5)
            assert row["pass"] == ("PASS" if value <= limit else "FAIL")
        alternatives = page.table(f"alternatives {joint['joint']}")
        assert list(alternatives["motor"]) == [a["motor"] for a in joint["alternatives"]]
    drives = page.table("drives")
    assert list(drives["joint"]) == [j["joint"] for j in result["joints"]]
    for (_, row), joint in zip(drives.iterrows(), result["joints"]):
        smallest = min(joint["checks"], key=lambda c: c["margin"])
        assert row["deciding check"] == smallest["name"]
        assert number(row["smallest margin"]) == pytest.approx(smallest["margin"], rel=1e-5)
        assert joint["deciding_check"]["name"] == smallest["name"]
        assert number(row["drive mass (kg)"]) == pytest.approx(joint["drive_mass_kg"], rel=1e-5)
        assert [r.split(":")[0] for r in row["runner-up"].split(" | ")] == [r["candidate"] for r in joint["runner_up"]]
    totals = dict(page.table("totals").values)
    assert number(totals["drive_mass_kg"]) == pytest.approx(sum(j["drive_mass_kg"] for j in result["joints"]), rel=1e-5)
    assert number(totals["energy_per_cycle_J"]) == pytest.approx(result["totals"]["energy_per_cycle_J"], rel=1e-5)
    assert len(page.table("iterations")) == len(result["iterations"])
    # one chart per joint and the arm at its binding pose; the inputs and the method
    assert len(page.images) == len(result["joints"]) + 2  # and the electrical power over the task
    electrical = page.table("electrical")
    assert list(electrical["axis"]) == [j["joint"] for j in result["joints"]] + ["DC bus"]
    assert number(electrical["energy_regenerated"].iloc[-1]) == pytest.approx(
        result["electrical"]["bus"]["energy_regenerated"], rel=1e-5)
    options = dict(page.table("options").values)
    assert options["robot"] == "puma560" and options["--objective"] == "mass" and options["--report"] == str(path)
    assert dict(page.table("mechanism").values)["name"] == "puma560"
    critical = min(result["joints"], key=lambda j: min(c["margin"] for c in j["checks"]))
    peak = next(c["value"] for c in critical["checks"] if c["name"] == "transmission peak torque")
    loaded = page.sections["s-binding-pose"]
    assert f"where {critical['joint']} (the smallest margin)" in loaded
    assert float(re.search(r"largest \|τ\| = (\S+) N·m", loaded).group(1)) == pytest.approx(peak, rel=1e-3)
    assert "T_m = (J_m + J_c) u ω̇ + τ* / u" in page.sections["s-method"]
    assert "Siemens SINAMICS" in page.sections["s-references"]  # [Vendor sizing] resolved


def test_tolerance_report_has_every_pose(tmp_path):
    path = tmp_path / "four_bar_tolerance.html"
    code, _, _ = run("tolerance", str(DATA / "four_bar.toml"), "--tolerances", str(DATA / "tolerances_four_bar.csv"),
                     "--grid", "10", "--samples", "2000", "--limit-mm", "0.3", "--report", str(path))
    assert code == 0
    page = check_page(path, tmp_path)
    poses = page.table("poses")
    assert list(poses["label"]) == [str(k) for k in range(1, 11)]
    crank = poses["q1"].map(number)
    assert crank.diff().dropna().to_numpy() == pytest.approx(2 * math.pi / 9, abs=2e-5)  # one turn, 6 digits
    worst = poses["|Δr| worst (mm)"].map(number)
    assert list(poses["pass"]) == ["PASS" if dr <= 0.3 else "FAIL" for dr in worst]
    assert (worst >= poses["|Δr| rss (mm)"].map(number)).all()  # the worst case bounds the RSS stack-up
    critical = int(worst.idxmax())
    assert f"critical pose {poses['label'][critical]}" in page.sections["s-critical-pose"]
    sources = page.table("tolerances")
    assert list(sources["name"]) == ["a", "b", "c", "d", "D_y", "q1"]  # the rows of the tolerances file
    assert float(sources["tolerance"][0]) == pytest.approx(27e-6)  # IT8 at 100 mm: 54 µm zone, ±27 µm
    shares = page.table("contributions")["variance_share"].map(number)
    assert shares.sum() == pytest.approx(100, abs=1e-3)
    assert len(page.images) == 3 + 1  # error map, Monte Carlo, contributions; the four-bar at the critical pose
    assert "ISBN 978-5-7028-0744-7" in page.sections["s-references"]  # [Egorov, 8.4] resolved


def test_linkage_report_draws_the_smallest_transmission_angle_and_escapes_names(tmp_path):
    """The crank-rocker four-bar (crank a = 0.1, coupler b = 0.3, rocker c = 0.25, frame d = 0.3 m): the
    transmission angle is smallest with the crank pointing at the rocker's pivot, |BD| = d − a, where
    cos μ = (b² + c² − (d − a)²) / (2 b c) = 0.75, μ = 41.41°. The file's description carries markup and a script,
    which the report must show as text."""
    source = (DATA / "four_bar.toml").read_text(encoding="utf-8")
    hostile = "<script>console.log('injected')</script><img src=x onerror=console.log(1)> & \"quotes\""
    mechanism = tmp_path / "four_bar.toml"
    mechanism.write_text(re.sub(r'^description = ".*"$', f"description = {json.dumps(hostile)}", source, count=1,
                                flags=re.M), encoding="utf-8")
    path = tmp_path / "four_bar_linkage.html"
    samples = 120
    code, _, _ = run("linkage", str(mechanism), "--samples", str(samples), "--report", str(path))
    assert code == 0
    page = check_page(path, tmp_path)
    assert dict(page.table("mechanism").values)["description"] == hostile  # shown, not run: no console message
    assert page.tags.count("script") == 1 and len(page.images) == 2  # the report's own: sweep chart, drawing
    positions = page.table("positions")
    assert list(positions["sample"]) == [str(k) for k in range(samples)]  # every position
    mu = positions["mu (deg)"].map(number)
    smallest = math.degrees(math.acos((0.3**2 + 0.25**2 - (0.3 - 0.1) ** 2) / (2 * 0.3 * 0.25)))
    assert mu.min() == pytest.approx(smallest, abs=0.05)
    points = page.table("points").set_index("point")
    assert points.loc["A", ["x min", "x max", "y min", "y max"]].map(number).tolist() == [0, 0, 0, 0]  # a pivot
    crank_pin = points.loc["B", ["x min", "x max", "y min", "y max"]].map(number).to_numpy()
    assert crank_pin == pytest.approx([-0.1, 0.1, -0.1, 0.1], abs=1e-4)  # B turns on the circle |AB| = a
    measures = page.table("measures")
    assert measures.iloc[0].tolist()[:2] == ["mu", "transmission_angle"]
    assert number(measures["min"][0]) == pytest.approx(mu.min(), rel=1e-5) and measures["pass"][0] == "PASS"
    critical = int(mu.idxmin())
    crank = number(positions["q1 (deg)"][critical])
    assert math.remainder(crank, 360) == pytest.approx(0, abs=360 / (samples - 1))  # the crank points at D
    assert f"position {critical}: mu = {mu.min():.4g} deg" in page.sections["s-critical-position"]


# ------------------------------------------------------------------------------------ the renderer and its file
def test_renderer_escapes_user_text_and_keeps_citations_and_equations():
    import numpy as np
    from matplotlib.figure import Figure

    figure = Figure()
    figure.add_subplot().plot([0, 1], [0, 1])
    evil = "<b onclick=alert(1)>q1</b> & 'x'"
    frame = pd.DataFrame({"check": [evil, "ok"], "value": [np.float64(1.23456789), math.nan], "pass": [True, False]})
    report = Report(evil, [Section(evil, [Text(f"{evil} [Egorov, 4.63] [Unknown, 1]"), Code(evil),
                                         Method("Title.\n\n    T = J ε  [Pinocchio]\n\n- ``a`` item *b*"),
                                         Table(frame, evil, evil), Chart(figure, evil)])], evil)
    html = render(report)
    assert "<b onclick" not in html and "&lt;b onclick=alert(1)&gt;q1&lt;/b&gt; &amp; &#x27;x&#x27;" in html
    page = Page(html)
    assert page.table(evil).values.tolist() == [[evil, "1.23457", "PASS"], ["ok", "", "FAIL"]]
    assert page.citations == ["#ref-Egorov", "#ref-Pinocchio"] and "[Unknown, 1]" in html
    assert "<pre>T = J ε  <a class=\"citation\" href=\"#ref-Pinocchio\">[Pinocchio]</a></pre>" in html
    assert "<li><code>a</code> item <em>b</em></li>" in html
    assert REFERENCES["Egorov"].replace("*", "").split(",")[0] in html


def test_default_report_of_any_result(tmp_path):
    """A result with no report of its own gets its text report, its table (every row) and its chart."""
    import mechatron
    from mechatron.dynamics.motion import move

    trajectory = move(mechatron.load("planar_2r"), [0.0, 0.0], [0.5, -1.0], profile="quintic", dt=0.01)
    page = Page(trajectory.write_html(tmp_path / "move.html").read_text(encoding="utf-8"))
    assert len(page.tables["result"]) == len(trajectory.to_frame()) and len(page.images) == 1


def test_references_are_those_of_references_md():
    text = (ROOT / "docs" / "references.md").read_text(encoding="utf-8")
    rows = dict(re.findall(r"^\| ([^|]+?) \| (.+) \|$", text, re.M))
    rows.pop("key"), rows.pop("---")
    assert REFERENCES == rows


def test_report_is_written_whole_or_not_at_all(tmp_path):
    import mechatron

    path = tmp_path / "report.html"
    path.write_text("previous", encoding="utf-8")
    puma = mechatron.load("puma560")
    result = mechatron.size(puma)
    with pytest.raises(InputError, match="needs that task"):  # the task it was sized for, not another one
        result.write_html(path, mechanism=puma, task=DATA / "pick_and_place.toml")
    assert path.read_text(encoding="utf-8") == "previous" and [p.name for p in tmp_path.iterdir()] == ["report.html"]
    code, _, err = run("linkage", str(DATA / "four_bar.toml"), "--report", str(tmp_path / "missing" / "x.html"))
    assert code == 2 and len(err.strip().splitlines()) == 1 and "missing" in err and "does not exist" in err


def test_size_report_shows_the_tasks_loads(tmp_path):
    task = tmp_path / "task.toml"
    task.write_text((ROOT / "examples" / "data" / "pick_and_place.toml").read_text(encoding="utf-8")
                    + '\n[[loads]]\nframe = "tool"\nforce = [0.0, 0.0, -20.0]\nmoment = [0.0, 1.5, 0.0]\n')
    path = tmp_path / "loads.html"
    code, _, err = run("size", "puma560", "--task", str(task), "--single-pass", "--report", str(path))
    assert code == 0, err
    loads = check_page(path, tmp_path).table("loads")
    assert list(loads["frame"]) == ["tool", "tool"]  # the example's own load, then this one
    assert number(loads["Fz (N)"].iloc[1]) == -20.0 and number(loads["My (N·m)"].iloc[1]) == 1.5


def test_study_report_has_the_pareto_front_and_every_failure(tmp_path):
    """A study of a central crank-slider (crank l1, rod l2): its travel is 2 l1 and its reach l1 + l2 [Egorov,
    fig. 4.18], and it cannot turn its crank through a full turn where l2 < l1. The report's Pareto front (travel
    maximised, reach minimised) is the brute-force front of those closed forms over the study's designs, its failed
    designs are exactly those with l2 < l1, and every design has its row."""
    spec = tmp_path / "crank.toml"
    spec.write_text('mechanism = "crank_slider"\n[parameters.l1]\nlow_mm = 80\nhigh_mm = 120\n[parameters.l2]\n'
                    'low_mm = 60\nhigh_mm = 450\n[designs]\nmethod = "lhs"\nsamples = 24\nseed = 3\n'
                    '[analyses.linkage]\nsamples = 13\n[output.pareto]\nx = "x_travel_m"\nx_goal = "maximize"\n'
                    'y = "reach_m"\ny_goal = "minimize"\n', encoding="utf-8")
    path = tmp_path / "study.html"
    code, _, _ = run("study", str(spec), "--out", str(tmp_path / "out"), "--report", str(path))
    assert code == 0
    page = check_page(path, tmp_path)
    designs = page.table("designs")
    assert len(designs) == 24
    l1, l2 = designs["l1"].map(number), designs["l2"].map(number)
    assert sorted(page.table("failed")["design"].map(int)) == sorted(designs["design"][l2 < l1].map(int))
    travel, reach, ok = 2 * l1, l1 + l2, l2 >= l1
    front = [int(designs["design"][i]) for i in designs.index[ok]
             if not any(travel[j] >= travel[i] and reach[j] <= reach[i] and (travel[j] > travel[i] or reach[j] <
                                                                             reach[i]) for j in designs.index[ok])]
    pareto = page.table("pareto")
    assert sorted(pareto["design"].map(int)) == sorted(front)
    assert pareto["x_travel_m"].map(number).to_numpy() == pytest.approx(
        2 * pareto["l1"].map(number).to_numpy(), rel=1e-5)  # 6 digits shown
    assert len(page.images) == 1  # the chart of the designs and the front


def test_optimize_report_has_the_optimum(tmp_path):
    """The crank-reach design problem: least reach l1 + l2 with travel 2 l1 ≥ 0.2 m, l1 ∈ [0.08, 0.12] and
    l2 ∈ [0.35, 0.45] m, is l1 = 0.1, l2 = 0.35, reach 0.45 m (by hand: reach grows with both, the travel binds
    l1). The HTML report of ``optimize`` shows it."""
    path = tmp_path / "optimize.html"
    code, _, _ = run("optimize", str(ROOT / "examples" / "design" / "crank_reach.toml"), "--report", str(path))
    assert code == 0
    page = check_page(path, tmp_path)
    text = page.sections["s-results"]
    assert "best design: l1 = 0.1, l2 = 0.35" in text and re.search(r"minimize reach_m: 0\.45 m", text), text[:2000]
    assert len(page.images) >= 1
