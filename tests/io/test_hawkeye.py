"""Point JSON reader (Hawk-Eye-style tracker output): variants, errors naming the field, fuzzing."""

import json

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tennislab.cli import main
from tennislab.errors import InputError
from tennislab.io.hawkeye import MAX_DEPTH, Point, parse_points, read_points


def point(n=12, **extra):
    samples = [
        {"time": 10 + 0.02 * i, "ball": {"pos": {"x": -11 + i, "y": 0.1 * i, "z": 2.0 - 0.1 * i}}} for i in range(n)
    ]
    samples[0]["event"] = "hit"
    samples[n // 2]["event"] = "bounce"
    doc = {
        "match": {"season": 2025, "tournament_id": 1, "players": [{"team": 1, "external_id": "AB12"}]},
        "sequences": {"set": 1, "game": 2, "point": 3, "serve": 1, "rally": 1},
        "shots": [
            {
                "shot_no": 1,
                "team": 2,
                "stroke": "Serve",
                "time": 10.0,
                "duration": 0.69,
                "time_utc": "2025-01-01T11:10:49.761Z",
                "speed_ms": 59.6,
                "spin": {"type": "backspin", "rpm": -3656.0},
                "call": "out",
                "distance": 0.12,
            }
        ],
        "samples": samples,
        "events": [{"time": 10.16, "type": "bounce"}, {"junk": 1}],
    }
    doc.update(extra)
    return doc


def test_one_point_all_fields():
    (p,) = parse_points(json.dumps(point()), "p.json")
    assert isinstance(p, Point) and len(p) == 12 and p.name == "p.json"
    assert np.allclose(p.t, 10 + 0.02 * np.arange(12)) and p.xyz[3, 0] == pytest.approx(-8.0)
    assert (10.0, "hit") in p.events and (10.16, "bounce") in p.events
    assert p.event_positions[0][1] == "hit" and p.sequences == {"set": 1, "game": 2, "point": 3, "serve": 1, "rally": 1}
    s = p.shots[0]
    assert s.stroke == "serve" and s.spin_rpm == -3656.0 and s.spin_type == "backspin" and s.call == "out"
    assert s.distance == 0.12 and s.speed_ms == 59.6 and s.team == 2 and s.time == 10.0
    assert p.match["players"][0]["external_id"] == "AB12"


def test_variants_list_points_lines_and_directory(tmp_path):
    doc = point()
    assert len(parse_points(json.dumps([doc, doc]))) == 2
    assert len(parse_points(json.dumps({"points": [doc, doc, doc]}))) == 3
    assert len(parse_points(json.dumps(doc) + "\n" + json.dumps(doc) + "\n")) == 2
    for i in range(3):
        (tmp_path / f"p{i}.json").write_text(json.dumps(doc))
    (tmp_path / "notes.txt").write_text("not a point")
    assert [p.name.endswith(f"p{i}.json") for i, p in enumerate(read_points(str(tmp_path)))] == [True] * 3
    (tmp_path / "empty").mkdir()
    with pytest.raises(InputError, match="no .json point files"):
        read_points(str(tmp_path / "empty"))


def test_tolerant_of_missing_unsorted_gaps_and_absent_balls():
    doc = point(n=15)
    doc["samples"][3]["ball"] = None
    doc["samples"][4]["ball"] = {"pos": None}
    doc["samples"][5]["ball"] = {"pos": {"x": 1.0, "y": 2.0, "z": float("nan")}}
    del doc["samples"][6]["ball"]
    doc["samples"][7] = {"time": doc["samples"][2]["time"], "ball": {"pos": [0, 0, 1]}}  # duplicate time
    doc["samples"] = doc["samples"][::-1]  # unsorted
    doc["samples"][0]["ball"] = {"pos": [1.0, 2.0, 3.0]}  # list form
    del doc["shots"][0]["call"], doc["shots"][0]["spin"], doc["match"], doc["events"]
    (p,) = parse_points(json.dumps(doc))  # the NaN is written as the literal NaN
    assert np.all(np.diff(p.t) > 0) and np.all(np.isfinite(p.xyz))
    assert p.n_without_ball == 4 and p.n_duplicate == 1 and len(p) == 15 - 4 - 1
    assert p.shots[0].call is None and p.shots[0].spin_rpm is None and p.match == {}


def test_minimal_point_samples_only():
    (p,) = parse_points('{"samples": [{"t": 1, "ball": [0, 0, 1]}, {"t": 2, "ball": {"x": 1, "y": 0, "z": 1}}]}')
    assert len(p) == 2 and p.shots == () and p.events == ()


@pytest.mark.parametrize(
    "mutate, field",
    [
        (lambda d: d["samples"][2].update(time="soon"), "samples[2].time"),
        (lambda d: d["samples"][2].pop("time"), "samples[2].time"),
        (lambda d: d["samples"][1]["ball"]["pos"].update(x="a"), "samples[1].ball.pos.x"),
        (lambda d: d["samples"][1]["ball"].update(pos=[1, 2]), "samples[1].ball.pos"),
        (lambda d: d["samples"][1]["ball"]["pos"].update(z=5000), "samples[1].ball.pos.z"),
        (lambda d: d["samples"][1].update(ball=7), "samples[1].ball"),
        (lambda d: d["shots"][0].update(speed_ms="fast"), "shots[0].speed_ms"),
        (lambda d: d["shots"][0].update(speed_ms=-3), "shots[0].speed_ms"),
        (lambda d: d["shots"][0]["spin"].update(rpm=[1]), "shots[0].spin.rpm"),
        (lambda d: d["shots"][0].update(call={"x": 1}), "shots[0].call"),
        (lambda d: d.update(shots={"a": 1}), "shots"),
        (lambda d: d.update(samples=None), "samples"),
        (lambda d: d.pop("samples"), "samples"),
        (lambda d: d.update(sequences=[1]), "sequences"),
        (lambda d: d["samples"].__setitem__(0, 3), "samples[0]"),
    ],
)
def test_errors_name_the_field(mutate, field):
    doc = point()
    mutate(doc)
    with pytest.raises(InputError) as e:
        parse_points(json.dumps(doc), "f.json")
    msg = str(e.value)
    assert msg.startswith("f.json: ") and field in msg and "\n" not in msg


@pytest.mark.parametrize(
    "text, msg",
    [
        ("", "empty"),
        ("{nope", "not valid JSON"),
        ("3", "expected a point object"),
        ("[]", "no points"),
        ('{"points": 3}', "points: expected a list"),
        ("[" * 40 + "]" * 40, f"deeper than {MAX_DEPTH}"),
        ("[" * 100_000, f"deeper than {MAX_DEPTH}"),
        ('{"samples": [{"time": ' + "9" * 5000 + "}]}", "not valid JSON"),
        (b'{"samples": []}\xff', "UTF-8"),
    ],
)
def test_file_errors(text, msg):
    with pytest.raises(InputError, match=msg):
        parse_points(text, "f.json")


def test_strings_with_brackets_do_not_count_as_depth():
    doc = point()
    doc["match"]["note"] = "[" * 100 + '\\"{{{'
    assert len(parse_points(json.dumps(doc))) == 1


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.binary(max_size=400))
def test_fuzz_bytes(data):
    try:
        parse_points(data)
    except InputError:
        pass


json_values = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats() | st.text(max_size=5),
    lambda children: st.lists(children, max_size=4) | st.dictionaries(st.text(max_size=5), children, max_size=4),
    max_leaves=20,
)
KEYS = ["samples", "shots", "time", "t", "ball", "pos", "x", "y", "z", "event", "spin", "rpm", "call", "points"]


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(json_values)
def test_fuzz_json_structures(doc):
    try:
        pts = parse_points(json.dumps(doc))
    except InputError:
        return
    for p in pts:
        assert np.all(np.isfinite(p.xyz)) and np.all(np.diff(p.t) > 0)


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.data())
def test_fuzz_mutated_points(data):
    """A valid point with one value anywhere replaced by arbitrary JSON: a point or one InputError."""
    doc = point(n=6)
    paths = []

    def walk(o, path):
        if isinstance(o, dict):
            for k, v in o.items():
                paths.append(path + [k])
                walk(v, path + [k])
        elif isinstance(o, list):
            for i, v in enumerate(o):
                paths.append(path + [i])
                walk(v, path + [i])

    walk(doc, [])
    path = data.draw(st.sampled_from(paths))
    value = data.draw(json_values | st.sampled_from(KEYS))
    target = doc
    for k in path[:-1]:
        target = target[k]
    target[path[-1]] = value
    try:
        pts = parse_points(json.dumps(doc))
    except InputError as e:
        assert "\n" not in str(e)
        return
    assert all(np.all(np.isfinite(p.xyz)) for p in pts)


def test_cli_malformed_point_file_is_one_line_exit_2(tmp_path, capsys):
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(point()).replace('"z": 2.0', '"z": "high"'))
    out = tmp_path / "calls.csv"
    rc = main(["call", "--rally", str(bad), "--csv", str(out)])
    err = capsys.readouterr().err
    assert rc == 2 and "samples[0].ball.pos.z" in err and len(err.strip().splitlines()) == 1
    assert "Traceback" not in err and not out.exists()
    rc = main(["call", "--rally", str(tmp_path / "missing.json")])
    assert rc == 2 and "missing.json" in capsys.readouterr().err
