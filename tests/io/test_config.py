"""tennislab.io.config: the form of tennislab.toml and of one-player files; one-line errors naming the key."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tennislab.errors import InputError
from tennislab.io.config import MAX_BYTES, PHYSICS_KEYS, parse_config, read_config, read_player_file

GOOD = """
[physics]
aero = "cross2014"
mass = 0.058
wind = [1, 0, 0.5]

[court]
surface = "clay"

[defaults]
player = "me"
machine = "club"

[players.me]
impact_height = 2.6
racket_speed = 33

[machines.club]
position = [-12.385, 0]
roller_radius = 0.1
"""


def write(tmp_path, text, name="tennislab.toml"):
    p = tmp_path / name
    p.write_text(text)
    return str(p)


def test_a_full_configuration_reads_into_plain_data(tmp_path):
    d = read_config(write(tmp_path, GOOD))
    assert d["physics"] == {"aero": "cross2014", "mass": 0.058, "wind": [1.0, 0.0, 0.5]}
    assert d["court"] == {"surface": "clay"} and d["defaults"] == {"player": "me", "machine": "club"}
    assert d["players"] == {"me": {"impact_height": 2.6, "racket_speed": 33.0}}
    assert d["machines"] == {"club": {"position": [-12.385, 0.0], "roller_radius": 0.1}}
    assert all(isinstance(v, float) for v in d["players"]["me"].values())


def test_an_empty_file_is_an_empty_configuration(tmp_path):
    assert read_config(write(tmp_path, "")) == {
        "physics": {},
        "court": {},
        "defaults": {},
        "players": {},
        "machines": {},
    }


@pytest.mark.parametrize(
    "text,expect",
    [
        ("[physics]\ndrag = 1\n", "physics.drag: unknown key; allowed: aero"),
        ("[physics]\nmas = 1\n", "physics.mas: unknown key (did you mean mass?)"),
        ("[phyiscs]\nmass = 1\n", "phyiscs: unknown key (did you mean physics?)"),
        ("[physics]\nmass = '1'\n", "physics.mass: expected a number"),
        ("[physics]\nmass = true\n", "physics.mass: expected a number"),
        ("[physics]\nmass = nan\n", "physics.mass: must be a finite number"),
        ("[physics]\nwind = [1, 2]\n", "physics.wind: expected a list of 3 numbers"),
        ("[physics]\nwind = [1, 'a', 2]\n", "physics.wind[1]: expected a number"),
        ("[physics]\naero = 3\n", "physics.aero: expected a text"),
        ("physics = 3\n", "physics: expected a table"),
        ("[court]\nsurfce = 'clay'\n", "court.surfce: unknown key (did you mean surface?)"),
        ("[machines.club]\nradius = 0.1\n", "machines.club.radius: unknown key"),
        ("[players.me]\nimpact_height = [[1]]\n", "players.me.impact_height: expected a list of numbers or texts"),
        ("[players.me]\nx = {a = 1}\n", "players.me.x: expected a number, a text or a list, got a table"),
        ("players = 1\n", "players: expected tables [players.NAME]"),
        ("[physics\n", "not valid TOML"),
        ("a = 1\na = 2\n", "not valid TOML"),
    ],
)
def test_errors_are_one_line_and_name_the_file_and_key(tmp_path, text, expect):
    path = write(tmp_path, text)
    with pytest.raises(InputError) as e:
        read_config(path)
    msg = str(e.value)
    assert "\n" not in msg and msg.startswith(path + ": ") and expect in msg, msg


def test_not_utf8_and_too_big(tmp_path):
    p = tmp_path / "t.toml"
    p.write_bytes(b"[physics]\naero = '\xff'\n")
    with pytest.raises(InputError, match="not UTF-8"):
        read_config(str(p))
    p.write_text("# " + "x" * MAX_BYTES + "\n")
    with pytest.raises(InputError, match="larger than"):
        read_config(str(p))


def test_one_player_files(tmp_path):
    assert read_player_file(write(tmp_path, 'name = "Ana"\nimpact_height = 2.5\nracket_speed = 31\n', "a.toml")) == {
        "name": "Ana",
        "impact_height": 2.5,
        "racket_speed": 31.0,
    }
    assert read_player_file(write(tmp_path, "[player]\nimpact_height = 2.5\n", "b.toml")) == {"impact_height": 2.5}
    with pytest.raises(InputError, match="c.toml: x: expected a number, a text or a list"):
        read_player_file(write(tmp_path, "[x]\ny = 1\n", "c.toml"))


def test_the_physics_keys_are_the_physics_flags():
    from tennislab.cli.common import PHYSICS_DESTS
    from tennislab.cli.config import FLAG_DESTS

    assert set(PHYSICS_KEYS) == set(PHYSICS_DESTS) == set(FLAG_DESTS["physics"])


@settings(max_examples=200, deadline=None)
@given(
    st.recursive(
        st.none() | st.booleans() | st.floats(allow_nan=True) | st.integers() | st.text(max_size=8),
        lambda children: st.lists(children, max_size=3) | st.dictionaries(st.text(max_size=8), children, max_size=3),
        max_leaves=12,
    )
)
def test_any_parsed_document_gives_data_or_one_input_error(doc):
    data = doc if isinstance(doc, dict) else {"physics": doc}
    try:
        out = parse_config(data, where="t.toml")
    except InputError as exc:
        assert "\n" not in str(exc) and str(exc).startswith("t.toml: ")
    else:
        assert set(out) == {"physics", "court", "defaults", "players", "machines"}


def test_a_key_with_a_newline_stays_on_one_line():
    """Hypothesis found it: TOML allows a quoted key "0\\n"; ``$`` in a regex matched before the newline."""
    with pytest.raises(InputError) as exc:
        parse_config({"0\n": None}, where="t.toml")
    assert "\n" not in str(exc.value) and '"0\\n"' in str(exc.value)
