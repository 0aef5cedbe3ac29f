"""Drill files: the shipped library compiles and passes its checks; malformed files fail clearly."""

import csv
import io
import json

import pytest

from tennislab.errors import InputError
from tennislab.io.drill import CSV_COLUMNS, load_drill, parse_drill, shipped_drills, write_drill_csv
from tennislab.launcher.drills import SHOT_TYPES, compile_drill, expand_program

LIBRARY = {"baseline_rally", "approach_and_volley", "lobs", "return_of_serve"}


def test_library_is_shipped():
    assert LIBRARY <= set(shipped_drills())


@pytest.mark.parametrize("name", sorted(LIBRARY))
def test_every_shipped_drill_compiles_and_passes(name):
    d = load_drill(name)
    c = compile_drill(d)
    assert c.ok, [u.problem for u in c.unique if not u.ok]
    for u in c.unique:
        x0, x1, y0, y1 = u.shot.zone_bounds()
        assert x0 <= u.solution.landing[0] <= x1 and y0 <= u.solution.landing[1] <= y1
        assert u.solution.net_clearance_m > 0
        d.spec.validate(u.solution.settings, require_steps=True)
    assert len(c.shots) == len(expand_program(d))
    times = [t for _, t, _ in c.shots]
    assert times == sorted(times) and times[0] == 0


def test_return_of_serve_is_from_3m():
    c = compile_drill(load_drill("return_of_serve"))
    assert all(u.solution.settings.height_m == 3.0 for u in c.unique)
    assert all(u.solution.settings.elevation_deg < 0 for u in c.unique if u.shot.speed_kmh >= 150)


MINI = """
name: mini
defaults: {interval_s: 2}
shots:
  a: {type: topspin, zone: [7, 11.885, -2, 2]}
  b: {type: slice, target: [9, 2], speed_kmh: 75}
program:
  - shot: a
    repeats: 2
  - sequence: [{shot: b}, {shot: {type: lob, target: [10, 0]}}]
    repeats: 2
  - random: [{shot: a, weight: 1}, {shot: b, weight: 3}]
    count: 20
    seed: 7
"""


def test_program_expansion_and_defaults():
    d = parse_drill(MINI)
    names = expand_program(d)
    assert names[:6] == ["a", "a", "b", "program[1].sequence[1].shot", "b", "program[1].sequence[1].shot"]
    assert len(names) == 26 and names == expand_program(d)  # seeded: reproducible
    assert 10 <= names[6:].count("b") <= 19  # weighted 3:1
    a = d.shots["a"]
    assert a.target == (pytest.approx(9.4425), 0.0)  # zone centre
    assert (a.spin_rpm, a.solution, a.interval_s) == (SHOT_TYPES["topspin"].spin_rpm, "low", 2)
    assert d.shots["b"].spin_axis_deg == 180 and d.shots["b"].speed_kmh == 75
    assert d.shots["b"].zone == "full-doubles"


def test_json_and_csv_export():
    d = parse_drill(
        json.dumps({"name": "j", "program": [{"shot": {"type": "drive", "target": [8, 1]}, "repeats": 3}]}), fmt="json"
    )
    c = compile_drill(d)
    buf = io.StringIO()
    write_drill_csv(c, buf)
    rows = list(csv.DictReader(io.StringIO(buf.getvalue())))
    assert len(rows) == 3 and tuple(rows[0]) == CSV_COLUMNS
    assert [float(r["time_s"]) for r in rows] == [0, 4, 8]
    j = c.as_dict()
    assert j["ok"] and j["n_shots"] == 3 and j["shots"][0]["rpm1"] < j["shots"][0]["rpm2"]


@pytest.mark.parametrize(
    "text,frag",
    [
        ("name: x\nprogram: []", "program: a non-empty list"),
        ("name: x\nshots: []", "shots: no shots and no program"),
        ("name: x\nshots: [{target: [8, 0], name: a}, {target: [9, 0], name: a}]", "shots[1].name: 'a' is used twice"),
        ("name: x\nversion: [1]\nshots: [{target: [8, 0]}]", "version: expected an integer or a string"),
        ("program: [{shot: a}]", "name: required"),
        (
            "name: x\nshots: {a: {target: [8, 0], speed_kmh: 250}}\nprogram: [{shot: a}]",
            "shots.a.speed_kmh: 250 km/h is outside the allowed range [30, 200] km/h",
        ),
        (
            "name: x\nshots: {a: {target: [8, 0], interval_s: 20}}\nprogram: [{shot: a}]",
            "shots.a.interval_s: 20 s is outside the allowed range [1, 15] s",
        ),
        (
            "name: x\nshots: {a: {target: [8, 0], spin_rpm: 3000}}\nprogram: [{shot: a}]",
            "shots.a.spin_rpm: 3000 rpm is outside the allowed range [0, 2000] rpm",
        ),
        ("name: x\nshots: {a: {target: [8, 0], colour: red}}\nprogram: [{shot: a}]", "shots.a.colour: unknown field"),
        (
            "name: x\nshots: {a: {target: [8, 0], type: forehand}}\nprogram: [{shot: a}]",
            "shots.a.type: unknown shot type",
        ),
        ("name: x\nshots: {a: {speed_kmh: 80}}\nprogram: [{shot: a}]", "shots.a: needs a target"),
        (
            "name: x\nshots: {a: {target: [8, 0], zone: ad-box}}\nprogram: [{shot: a}]",
            "shots.a.target: (8, 0) m is outside its zone",
        ),
        ("name: x\nshots: {a: {zone: centre-court}}\nprogram: [{shot: a}]", "shots.a.zone: area: unknown name"),
        ("name: x\nprogram: [{shot: nope}]", "program[0].shot: unknown shot 'nope'"),
        (
            "name: x\nprogram: [{shot: {target: [8, 0]}, repeats: 0}]",
            "program[0].repeats: 0 is not an integer in the allowed range [1, 1000]",
        ),
        (
            "name: x\nprogram: [{random: [{shot: {target: [8, 0]}, weight: -1}]}]",
            "program[0].random[0].weight: -1 is outside",
        ),
        (
            "name: x\nprogram: [{shot: {target: [8, 0]}, sequence: []}]",
            "program[0]: needs exactly one of shot, sequence, random",
        ),
        ("name: x\nprogram: [{shot: {target: [8, zero]}}]", "program[0].shot.target"),
        (
            "name: x\nmachine: {position: [1]}\nprogram: [{shot: {target: [8, 0]}}]",
            "machine.position: expected 2 numbers",
        ),
        ("name: [unclosed", "not valid YAML"),
    ],
)
def test_malformed_drills(text, frag):
    with pytest.raises(InputError) as e:
        parse_drill(text, source="bad.yaml")
    msg = str(e.value)
    assert msg.startswith("bad.yaml: ") and frag in msg and "\n" not in msg


def test_unreachable_shot_names_the_shot():
    d = parse_drill("name: x\nshots: {far: {target: [11.5, 0], speed_kmh: 30}}\nprogram: [{shot: far}]")
    with pytest.raises(InputError, match="shots.far: target: .* beyond its reach"):
        compile_drill(d)


def test_unknown_file():
    with pytest.raises(InputError, match="not a shipped drill"):
        load_drill("/nonexistent/drill.yaml")


def test_parse_drill_text_for_storage():
    from tennislab.io.drill import _shipped_path, parse_drill_text

    p = _shipped_path("lobs")
    d = parse_drill_text(open(p).read(), p)
    assert d["name"] == "Lobs" and len(d["shots"]) == 4 and len(d["sequence"]) == 10
    assert d["shots"][0]["name"] == "lob-left" and d["shots"][0]["solution"] == "high"


def test_shot_list_without_program():
    d = parse_drill(
        "name: corners\nversion: 1\nshots:\n  - {target: [10, 3.5], speed_kmh: 90, spin_rpm: 1200}\n"
        "  - {name: right, target: [10, -3.5], speed_kmh: 90, spin_rpm: 1200}\n"
    )
    assert expand_program(d) == ["shots[0]", "right"] and d.version == "1"
    assert compile_drill(d).ok


def test_shot_type_spelling_variants():
    d = parse_drill(
        "name: x\nshots:\n  - {type: Serve Return, target: [5.5, 2], zone: deuce-box}\n"
        "  - {type: serve_return, target: [5.5, -2], zone: ad-box}\nmachine: {position: [-12.2, -0.5]}\n"
    )
    assert {s.type for s in d.shots.values()} == {"serve-return"}
    assert all(s.height_m == 3.0 for s in d.shots.values())
