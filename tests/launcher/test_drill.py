"""Drill files: the shipped library compiles and passes its checks; malformed files fail clearly."""

import csv
import io
import json

import numpy as np
import pytest

from tennislab.errors import InputError
from tennislab.io.drill import MAX_BYTES, parse_drill_bytes, write_csv
from tennislab.launcher.drill_schema import drill_record, load_drill, parse_drill, shipped_drills, shipped_path
from tennislab.launcher.drills import CSV_COLUMNS, SHOT_TYPES, compile_drill, dealt_counts, drill_key, expand_program


def write_drill_csv(comp, fh):
    write_csv(comp.rows(), CSV_COLUMNS, fh)


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
    assert names[6:].count("b") == 15 and names[6:].count("a") == 5  # dealt 3:1
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
    j = c.to_dict()
    assert j["ok"] and j["n_shots"] == 3 and j["n_distinct"] == 1 and j["shots"][0]["rpm1"] < j["shots"][0]["rpm2"]


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
    with pytest.raises(InputError, match="^drill: '/nonexistent/drill.yaml' is not a file, nor a shipped drill"):
        load_drill("/nonexistent/drill.yaml")


def test_drill_record_for_storage():
    p = shipped_path("lobs")
    d = drill_record(parse_drill(open(p, "rb").read(), p))
    assert d["name"] == "Lobs" and d["key"] == "lobs" and len(d["shots"]) == 4 and len(d["sequence"]) == 10
    assert d["n_shots"] == 10 and d["n_distinct"] == 4
    assert d["shots"][0]["name"] == "lob-left" and d["shots"][0]["solution"] == "high"


def test_one_name_everywhere():
    assert drill_key("Baseline rally") == drill_key("baseline-rally") == drill_key("baseline_rally") == "baseline_rally"
    for key in shipped_drills():
        d = load_drill(key)
        assert d.key == key  # a shipped drill's title and its file name give the same key
        assert load_drill(d.name).name == d.name  # and the title finds it too


def test_random_blocks_draw_what_they_promise():
    """'slices mixed in': the baseline rally's random block deals every listed shot, whatever the seed."""
    d = load_drill("baseline_rally")
    block = d.program[-1]
    assert "slice-left" in block.shots
    for seed in range(300):
        b = type(block)(block.shots, block.weights, block.count, seed)
        names = expand_program(type(d)(d.name, d.description, d.spec, d.shots, (b,), 1))
        counts = {s: names.count(s) for s in block.shots}
        assert counts == {"deep-left": 4, "deep-right": 4, "drive-middle": 1, "slice-left": 1}, seed
    assert "slice-left" in expand_program(d)  # the shipped seed fires it too


@pytest.mark.parametrize("weights,count", [((3, 3, 1, 1), 10), ((1, 2, 3), 12), ((5, 1), 2), ((1, 1, 1), 7)])
def test_dealt_counts(weights, count):
    c = dealt_counts(weights, count)
    assert c.sum() == count and (c >= 1).all()
    share = count * np.asarray(weights) / sum(weights)
    assert (np.abs(c - share) < 1.0 + (share < 1)).all()  # within one shot of the weights (the one each adds)


def test_fewer_draws_than_shots_is_a_weighted_choice_without_repeats():
    d = parse_drill(
        "name: x\nshots: {a: {target: [8, 1]}, b: {target: [8, -1]}, c: {target: [9, 0]}}\n"
        "program: [{random: [{shot: a}, {shot: b}, {shot: c}], count: 2, seed: 1}]\n"
    )
    names = expand_program(d)
    assert len(names) == 2 and len(set(names)) == 2


def test_preferences_in_shots():
    d = parse_drill(
        "name: x\ndefaults: {speed_tolerance_kmh: 0}\nshots:\n"
        "  low: {target: [9, 2], speed_kmh: 80, spin_rpm: 1500, max_apex_m: 3.1}\n"
        "  lob: {target: [9, -2], speed_kmh: 80, spin_rpm: 1500, trajectory: high, spin_axis: topspin}\n"
    )
    c = compile_drill(d)
    by = {u.label: u for u in c.unique}
    assert by["low"].solution.apex_z_m <= 3.1 and by["lob"].solution.solution == "high"
    assert by["low"].solution.settings.speed_kmh == 80  # the drill's speed tolerance 0
    bad = parse_drill("name: x\nshots: {a: {target: [9, 2], speed_kmh: 80, max_apex_m: 1.2}}\n")
    with pytest.raises(InputError, match=r"^shots.a: max_apex_m: "):
        compile_drill(bad)


@pytest.mark.parametrize(
    "text,frag",
    [
        (
            "name: x\na: &a [1,1,1,1,1,1,1,1,1,1]\nb: &b [*a,*a,*a,*a,*a,*a,*a,*a,*a,*a]\n"
            "c: &c [*b,*b,*b,*b,*b,*b,*b,*b,*b,*b]\nd: &d [*c,*c,*c,*c,*c,*c,*c,*c,*c,*c]\n"
            "e: &e [*d,*d,*d,*d,*d,*d,*d,*d,*d,*d]\nf: [*e,*e,*e,*e,*e,*e,*e,*e,*e,*e]\n",
            "expands to more than",
        ),
        ("[" * 5000, "not valid YAML"),
        ("a:\n" + "".join("  " * i + "- x:\n" for i in range(1, 60)), "nested deeper than"),
        ("name: x\nshots: {a: {target: [8, 0], speed_kmh: 1" + "0" * 5000 + "}}", "not valid YAML"),
        ("name: x\nshots: {a: {target: [8, 0], speed_kmh: .nan}}", "expected a finite number"),
        ("name: x\nshots: {a: {target: [8, 0], description: !!binary aGVsbG8=}}", "expected a string"),
        ("- 1\n- 2\n", "drill: expected a mapping"),
    ],
)
def test_hostile_drill_files_are_refused_quickly(text, frag):
    import time

    t0 = time.perf_counter()
    with pytest.raises(InputError) as e:
        parse_drill(text, source="bad.yaml")
    assert time.perf_counter() - t0 < 2.0
    assert frag in str(e.value) and "\n" not in str(e.value)


def test_alias_bomb_of_876_bytes_and_a_50_mb_file(tmp_path):
    import time

    # the issue's shape: a program whose sequences alias each other, 10 levels of 10 (10^10 shots)
    levels = ["name: bomb", "shots: {a: {target: [9, 0]}}", "x0: &l0 {shot: a}"]
    for i in range(1, 11):
        levels.append(f"x{i}: &l{i} {{sequence: [" + ",".join([f"*l{i - 1}"] * 10) + "]}")
    bomb = ("\n".join(levels) + "\nprogram: [*l10]\n").encode()
    assert len(bomb) < 1000
    t0 = time.perf_counter()
    with pytest.raises(InputError, match="expands to more than"):
        parse_drill_bytes(bomb, "bomb.yaml")
    big = tmp_path / "big.yaml"
    with open(big, "wb") as fh:
        fh.write(b"name: big\n" + b"# " + b"x" * (50 * 1024 * 1024) + b"\n")
    with pytest.raises(InputError, match=f"larger than a drill file may be \\({MAX_BYTES} bytes\\)"):
        load_drill(str(big))
    assert time.perf_counter() - t0 < 2.0


def test_non_utf8_drill(tmp_path):
    f = tmp_path / "latin.yaml"
    f.write_bytes("name: caf\xe9\n".encode("latin-1"))
    with pytest.raises(InputError, match="not UTF-8"):
        load_drill(str(f))


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
