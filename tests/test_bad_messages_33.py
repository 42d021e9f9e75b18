"""Issue 33, the older kinds: ``show`` of a mechanism file with many points in linear time (the frame look-up and the
declared-length partners were quadratic: 478 s for 20,000 points); a refusal that names what causes it (``--dwell``,
not ``--dt``; ``--input``; a list of names that is not a robot file's links)."""

from __future__ import annotations

import itertools
import time

import pytest
from corpus import assert_clean_error, run

from mechatron.model.linkage_file import linkage_spec
from mechatron.model.linkage_spec import declared_partners
from mechatron.model.mechanism import _FRAME_PREFERENCE, find_frame, frame_index

FOUR_BAR = "examples/data/four_bar.toml"


def _many_points(n: int) -> str:
    """The four-bar of examples/data with ``n`` more points drawn on its coupler."""
    with open(FOUR_BAR, encoding="utf-8") as f:
        text = f.read()
    points = "".join(f"P{i} = [{100 + i * 0.001:.4f}, {150 + i * 0.0005:.4f}]\n" for i in range(n))
    text = text.replace("M = { between", points + "M = { between", 1)
    names = ", ".join(f'"P{i}"' for i in range(n))
    return text.replace('points = ["B", "C", "M"]', f'points = ["B", "C", "M", {names}]', 1)


def test_show_of_a_mechanism_with_ten_thousand_points_is_fast(tmp_path, capfd):
    """10,000 points on one body: every point a frame of the model (10,000 names P0…P9999 in the frame list) in
    seconds, not the minutes of a quadratic look-up (478 s for 20,000 points before)."""
    (tmp_path / "big.toml").write_text(_many_points(10_000))
    start = time.perf_counter()
    outcome = run(["show", "big.toml", "--json"], capfd, tmp_path)
    elapsed = time.perf_counter() - start
    assert outcome.code == 0, outcome.err
    import json

    frames = json.loads(outcome.out)["frames"]
    assert {f"P{i}" for i in range(10_000)} <= set(frames)
    assert elapsed < 40, elapsed


def test_the_frame_index_is_the_linear_search_it_replaces():
    """For every frame name of a loaded mechanism (the shovel: pins on several bodies, joint and body frames of one
    name): the first frame of that name of the most preferred type, found by scanning every frame."""
    import mechatron

    model = mechatron.load("front_shovel").model
    index = frame_index(model)
    for name in {f.name for f in model.frames}:
        matches = [i for i, f in enumerate(model.frames) if f.name == name]
        best = min(matches, key=lambda i: (_FRAME_PREFERENCE.index(model.frames[i].type), i))
        assert index[name] == best == find_frame(model, name)
    assert find_frame(model, "no such frame") is None


def test_declared_partners_are_every_earlier_point_with_a_declared_length():
    """Brute force over all pairs of a body's drawn points (the definition) for every body of the four-bar."""
    from mechatron.io.toml import read_toml

    spec = linkage_spec(read_toml(FOUR_BAR), file=FOUR_BAR, default_name="four_bar")
    lengths = {length.name: length.value for length in spec.lengths}
    for body in spec.bodies:
        drawn = [p for p in body.points if spec.point(p).at is not None]
        expected = {p: [] for p in drawn}
        for q, p in itertools.combinations(drawn, 2):
            names = [length.name for length in spec.lengths if set(length.points) == {p, q}]
            if names:
                expected[p].append((q, names[-1]))
        assert declared_partners(spec, body, lengths) == expected
    assert any(declared_partners(spec, b, lengths)[p] for b in spec.bodies for p in
               declared_partners(spec, b, lengths))  # the four-bar declares its link lengths


def test_a_long_dwell_is_named_not_the_step(tmp_path, capfd):
    """Two rests of 1e9 s at the step 0.005 s: 2 · 1e9 / 0.005 = 4e11 samples, caused by --dwell."""
    outcome = assert_clean_error(["dynamics", "planar_2r", "--move", "0,0;1,1;0,0", "--dwell", "1e9"], capfd,
                                 tmp_path, ["--dwell 1e+09 at --dt 0.005 gives 4.0e+11 samples",
                                  "use a shorter --dwell", "or a larger --dt"])
    assert not outcome.err.startswith("mechatron: error: --dt")


def test_a_small_step_is_still_named_as_the_step(tmp_path, capfd):
    """A 1 rad move at vmax 1e-3 rad/s takes ≥ 1000 s; at --dt 1e-6 that is ≥ 1e9 samples: the step's doing."""
    assert_clean_error(["dynamics", "planar_2r", "--move", "0,0;1,1", "--vmax", "1e-3", "--dt", "1e-6"], capfd,
                       tmp_path, ["--dt 1e-06 gives", "use a larger --dt", "--vmax"])


def test_a_dwell_in_a_task_file_is_named_as_its_field(tmp_path, capfd):
    (tmp_path / "t.toml").write_text("waypoints = [[0, 0], [1, 1]]\ndwell = 1e9\n")
    assert_clean_error(["size", "planar_2r", "--task", "t.toml"], capfd, tmp_path,
                       ["t.toml: field 'dwell' 1e+09 at dt 0.005 gives", "use a shorter dwell"])


def test_an_unknown_input_names_the_option(tmp_path, capfd):
    assert_clean_error(["reduced", "crank_slider", "--input", "nope"], capfd, tmp_path,
                       ["--input 'nope' is not an actuated coordinate of crank_slider (q1)"])


@pytest.mark.parametrize("text", ['links = ["base", "arm"]\n[[joints]]\ntype = "revolute"\n',
                                  'name = "cam"\nlinks = ["1", "2", "3"]\n'])
def test_a_list_of_link_names_is_not_called_a_structural_description(tmp_path, capfd, text):
    """Without [[pairs]] a list of names is neither a robot file's [[links]] tables nor a structural description:
    the message says both, naming the field."""
    (tmp_path / "r.toml").write_text(text)
    outcome = assert_clean_error(["show", "r.toml"], capfd, tmp_path,
                                 ["r.toml: field 'links'", "not a robot file's links", "needs its [[pairs]]"])
    assert "a structural description (moving links" not in outcome.err


def test_a_structural_description_is_still_one(tmp_path, capfd):
    (tmp_path / "s.toml").write_text('links = ["1", "2"]\n[[pairs]]\nname = "A"\nclass = 5\nlinks = ["0", "1"]\n')
    assert_clean_error(["show", "s.toml"], capfd, tmp_path, ["a structural description", "mechatron structure"])
