"""Form-field validation of the web app: only InputError ever, clear messages, defaults valid."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tennislab.app.fields import FORMS, Field, validate
from tennislab.errors import InputError

json_values = st.recursive(
    st.none()
    | st.booleans()
    | st.integers(-(10**12), 10**12)
    | st.floats(allow_nan=True, allow_infinity=True)
    | st.text(max_size=20),
    lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=5), inner, max_size=3),
    max_leaves=6,
)


@settings(max_examples=300, deadline=None)
@given(
    form=st.sampled_from(sorted(FORMS)),
    body=st.dictionaries(st.text(max_size=12), json_values, max_size=4),
    known=st.dictionaries(
        st.sampled_from(
            ["x", "z", "speed_kmh", "player", "impact_angle", "step", "target_x", "shot", "line", "surface", "aero"]
        ),
        json_values,
        max_size=3,
    ),
)
def test_validate_raises_only_input_error(form, body, known):
    data = {**body, **{k: v for k, v in known.items() if k in FORMS[form].by_name()}}
    try:
        out = validate(form, data)
    except InputError as exc:
        msg = str(exc)
        assert msg and "\n" not in msg
        assert len(msg) < 500, msg  # bounded: user text is cut to 40 characters
        from tennislab.app.fields import field_label

        # the message opens with the offending field's label on screen (or the unknown key as given)
        fields = FORMS[form].by_name()
        heads = {fields[k].label if k in fields else field_label(k) for k in data} | {"request"}
        assert any(msg.startswith(h + ": ") for h in heads), msg
        return
    # accepted: every value is of its kind and within range
    for name, f in FORMS[form].by_name().items():
        v = out[name]
        if f.kind == "choice":
            assert v in f.choices
        else:
            assert isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
            assert f.lo is None or v >= f.lo
            assert f.hi is None or v <= f.hi


@pytest.mark.parametrize("body", [None, [], "x", 3, [("a", 1)]])
def test_body_must_be_an_object(body):
    with pytest.raises(InputError, match="^request:"):
        validate("flight", body)


def test_defaults_validate_and_empty_body_gives_defaults():
    for name, form in FORMS.items():
        out = validate(name, {})
        assert out == {f.name: f.default for f in form.fields}


@pytest.mark.parametrize(
    "value, msg",
    [
        (91, "angle: 91 deg is outside the allowed range [0.0, 90.0] deg"),
        (-1e-9, "angle: -1e-09 deg is outside the allowed range [0.0, 90.0] deg"),
        ("12x", "angle: expected a number, got '12x'"),
        (float("nan"), "angle: must be a finite number, got nan"),
        (True, "angle: expected a number, got True"),
        ([1], "angle: expected a number, got [1]"),
    ],
)
def test_messages(value, msg):
    f = Field("a", "angle", "float", 0.0, 0.0, 90.0, "deg")
    with pytest.raises(InputError) as exc:
        f.parse(value)
    assert str(exc.value) == msg


def test_long_or_odd_user_text_is_cut():
    f = Field("a", "angle", "float", 0.0, 0.0, 90.0, "deg")
    with pytest.raises(InputError) as exc:
        f.parse("9" * 10_000)
    assert str(exc.value) == "angle: expected a number, got a text of 10000 characters"
    with pytest.raises(InputError) as exc:
        f.parse(list(range(1000)))
    assert len(str(exc.value)) < 100
    with pytest.raises(InputError) as exc:
        validate("flight", {"<script>\n" * 20: 1})
    assert "\n" not in str(exc.value) and len(str(exc.value)) < 300


def test_numeric_strings_and_ints():
    f = Field("n", "count", "int", 1, 1, 10)
    assert f.parse("7") == 7 and f.parse(3.0) == 3
    with pytest.raises(InputError, match="whole number"):
        f.parse(2.5)
    g = Field("c", "choice", "choice", "a", choices=("a", "b"))
    assert g.parse("b") == "b"
    with pytest.raises(InputError, match="'z' is not one of a, b"):
        g.parse("z")


@pytest.mark.parametrize("value", [None, "", "   "])
def test_a_present_but_empty_value_is_required(value):
    """An emptied field never silently takes its default: missing key = default, empty value = error."""
    with pytest.raises(InputError, match="^speed: a value is required$"):
        validate("flight", {"speed_kmh": value})
    assert validate("flight", {})["speed_kmh"] == FORMS["flight"].by_name()["speed_kmh"].default


def test_huge_integers_are_refused_cleanly():
    with pytest.raises(InputError, match="^position x: .* outside the allowed range"):
        validate("flight", {"x": 10**400})


def test_every_message_names_the_label_never_the_key():
    """For every field of every form, a bad value gives a message opening with the label on screen."""
    for name, form in FORMS.items():
        for f in form.fields:
            bad = "not-a-choice" if f.kind == "choice" else (f.hi + 1 if f.hi is not None else "x")
            with pytest.raises(InputError) as exc:
                validate(name, {f.name: bad})
            msg = str(exc.value)
            assert msg.startswith(f.label + ": "), msg
            if "_" in f.name:  # an internal key such as speed_kmh never reaches the user
                assert f.name not in msg, msg


@pytest.mark.parametrize(
    "form, message, want",
    [
        ("flight", "speed_ms: -1 m/s is outside", "speed: -1 m/s is outside"),
        ("flight", "spin_axis: unknown axis 'x'", "spin axis: unknown axis 'x'"),
        ("flight", "flight: the ball does not land", "flight: the ball does not land"),
        ("serve", "impact angle: 95 deg is outside", "impact angle α: 95 deg is outside"),
        ("serve", "racket_speed: 0 m/s", "racket speed: 0 m/s"),
        ("aim", "speed_kmh: 250 km/h is outside", "ball speed: 250 km/h is outside"),
        ("aim", "target: cannot be reached", "target: cannot be reached"),
        ("linecall", "csv: line 3: expected 4 numbers", "track file: line 3: expected 4 numbers"),
        (None, "shots: expected a list", "drill: expected a list"),
        (None, "shots[2].target x: expected a number", "shot 3: target x: expected a number"),
        (None, "shots[0].speed_kmh: 250 km/h", "shot 1: ball speed: 250 km/h"),
        (None, "shots[1]: every shot must", "shot 2: every shot must"),
        ("flight", "something\nelse: x", "something else: x"),
        (
            "aim",
            "target: beyond its reach; raise speed_kmh (max 200)",
            "target: beyond its reach; raise ball speed (max 200)",
        ),
        ("aim", "target: no_such_name here", "target: no_such_name here"),
        ("serve", "azimuth/brush/server_y: need target", "azimuth/brush/server position y (3-D): need target"),
    ],
)
def test_label_message(form, message, want):
    from tennislab.app.fields import label_message

    assert label_message(form, message.replace("\\n", "\n")) == want


def test_choice_labels_name_the_paper_not_the_seed():
    """The page shows the success criteria by the paper's name; the value sent stays ``seed-2d``."""
    from tennislab.app.fields import FORMS

    f = FORMS["serve"].by_name()["target"]
    spec = f.spec()
    assert spec["choices"][0] == "seed-2d" and "Grosen" in spec["choice_labels"][0]
    assert len(spec["choice_labels"]) == len(spec["choices"])
    assert not any("seed" in lab for lab in spec["choice_labels"])
