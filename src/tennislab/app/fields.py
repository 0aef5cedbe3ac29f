"""Form fields of the web application: one definition for the page and the server.

Every input the browser can send is declared here as a :class:`Field` (label,
kind, range, unit, default).  The server validates each request body against
its form with :func:`validate` (unknown fields refused, every value
range-checked with :func:`tennislab.errors.check_range`); the page fetches the
same definitions from ``/api/meta`` and checks each input before it sends
anything, showing the same message under the field.

Messages name a field by its **label on screen** ("impact angle α: 120 deg is
outside ..."), never by its key in the JSON body.  Errors raised by the
library name its parameters (``speed_ms: ...``); :func:`label_message` turns a
leading parameter name into the label of the field it comes from
(:data:`LIBRARY_NAMES` is the one table of those names).

Ranges are the physically meaningful ones of each model (e.g. the launcher's
are its machine spec; see ``docs/app.md``).  Values are in the units the user
sees (km/h, rpm, degrees) and converted to SI where the workflows are called.
"""

from __future__ import annotations

import math
import re
from dataclasses import asdict, dataclass, field

from tennislab.core.aero import DEFAULT_AERO, aero_model_names
from tennislab.core.court import ITF_COURT
from tennislab.core.launch import SPIN_AXES_DEG
from tennislab.core.surfaces import surface_names
from tennislab.errors import InputError, check_range
from tennislab.serve.players import player_names

#: aero models the page offers: every registered model but ``table`` (which needs a file)
AERO_CHOICES = tuple([DEFAULT_AERO] + [n for n in aero_model_names() if n not in (DEFAULT_AERO, "table")])


@dataclass(frozen=True)
class Field:
    """One form field.

    Attributes
    ----------
    name : key in the JSON body
    label : text shown in the page and in every message about the field
    kind : ``float``, ``int`` or ``choice``
    default : value filled in the page (and used when the key is missing from a request)
    lo, hi : allowed range (inclusive; ``lo_open`` makes the lower bound exclusive)
    unit : unit shown and named in messages
    step : input step in the page (does not restrict the server)
    choices : allowed values of a ``choice`` field
    choice_labels : text shown in the page for each of ``choices`` (default the value itself)
    """

    name: str
    label: str
    kind: str = "float"
    default: object = None
    lo: float | None = None
    hi: float | None = None
    unit: str = ""
    step: float | None = None
    choices: tuple = ()
    choice_labels: tuple = ()
    lo_open: bool = False
    help: str = ""

    def parse(self, value):
        """Return the validated value or raise :class:`InputError` naming the field by its label.

        A missing key is the caller's business (:func:`validate` uses the default); a value that
        is present must be valid: ``null`` or an empty text is "a value is required".
        """
        lab = self.label
        if isinstance(value, str) and len(value) > 60:
            raise InputError(
                f"{lab}: expected {'one of ' + ', '.join(self.choices) if self.choices else 'a number'}"
                f", got a text of {len(value)} characters"
            )
        if value is None or (isinstance(value, str) and value.strip() == ""):
            raise InputError(f"{lab}: a value is required")
        if self.kind == "choice":
            if not isinstance(value, str) or value not in self.choices:
                raise InputError(f"{lab}: {short(value)} is not one of {', '.join(map(str, self.choices))}")
            return value
        if isinstance(value, bool) or not isinstance(value, (int, float, str)):
            raise InputError(f"{lab}: expected a number, got {short(value)}")
        if isinstance(value, int) and abs(value) > 10**15:  # float() of a 400-digit integer overflows
            raise InputError(f"{lab}: {short(value, 20)} is outside the allowed range {self.range_text()}")
        v = check_range(lab, value, self.lo, self.hi, self.unit, lo_open=self.lo_open)
        if self.kind == "int":
            if v != math.floor(v):
                raise InputError(f"{lab}: expected a whole number, got {short(value)}")
            return int(v)
        return v

    def range_text(self) -> str:
        u = f" {self.unit}" if self.unit else ""
        lo = "-inf" if self.lo is None else self.lo
        hi = "inf" if self.hi is None else self.hi
        return f"{'(' if self.lo_open else '['}{lo}, {hi}]{u}"

    def spec(self) -> dict:
        """The JSON description sent to the page."""
        d = asdict(self)
        d["choices"] = list(self.choices)
        d["choice_labels"] = list(self.choice_labels) or list(self.choices)
        return d


def _physics_fields() -> list[Field]:
    return [
        Field("aero", "aero model", "choice", DEFAULT_AERO, choices=AERO_CHOICES),
        Field("air_density", "air density", "float", 1.199, 0.5, 1.5, "kg/m^3", 0.001),
        Field("wind_x", "wind along the court", "float", 0.0, -20.0, 20.0, "m/s", 0.1),
        Field("wind_y", "wind across the court", "float", 0.0, -20.0, 20.0, "m/s", 0.1),
    ]


@dataclass(frozen=True)
class Form:
    """A named list of fields (one per endpoint)."""

    name: str
    fields: tuple = field(default_factory=tuple)

    def by_name(self) -> dict[str, Field]:
        return {f.name: f for f in self.fields}


FORMS: dict[str, Form] = {}


def _form(name: str, fields: list[Field]) -> Form:
    f = Form(name, tuple(fields))
    FORMS[name] = f
    return f


_form(
    "flight",
    [
        Field("x", "position x", "float", -11.885, -15.0, 15.0, "m", 0.01),
        Field("y", "position y", "float", 0.5, -8.0, 8.0, "m", 0.01),
        Field("z", "height", "float", 2.8, 0.04, 5.0, "m", 0.01),
        Field("speed_kmh", "speed", "float", 180.0, 1.0, 260.0, "km/h", 1),
        Field("elevation_deg", "elevation", "float", -4.0, -60.0, 80.0, "deg", 0.1),
        Field("heading_deg", "heading", "float", -1.5, -60.0, 60.0, "deg", 0.1),
        Field("spin_rpm", "spin", "float", 0.0, 0.0, 8000.0, "rpm", 10),
        Field(
            "spin_axis_deg",
            "spin axis",
            "float",
            0.0,
            -180.0,
            180.0,
            "deg",
            1,
            help="0 = topspin, 180 = backspin, +-90 = sidespin",
        ),
        Field("bounces", "bounces", "int", 0, 0, 5, "", 1, help="how many bounces to follow after the landing"),
        Field("surface", "court surface", "choice", "hard", choices=tuple(surface_names())),
        *_physics_fields(),
    ],
)

PLAYERS = (*player_names(), "custom")

#: The serve the explorer opens on: the professional's topspin serve deepest inside its alpha x beta
#: window (:func:`tennislab.serve.default_serve`: the default physics, 2-D criteria of the paper); not
#: computed at import (a window takes seconds on a cold cache): ``tests/app/test_api.py::test_default_serve_succeeds``
#: checks that these are its values and that the serve succeeds.
DEFAULT_SERVE = {"player": "professional", "impact_angle": 44.0, "face_angle": 20.0}

_form(
    "serve",
    [
        Field("player", "player", "choice", DEFAULT_SERVE["player"], choices=PLAYERS),
        Field("height", "impact height", "float", 3.0, 1.0, 3.5, "m", 0.01),
        Field("racket_speed", "racket speed", "float", 40.0, 5.0, 70.0, "m/s", 0.1),
        Field("impact_angle", "impact angle α", "float", DEFAULT_SERVE["impact_angle"], 0.0, 90.0, "deg", 1),
        Field("face_angle", "face angle β", "float", DEFAULT_SERVE["face_angle"], -10.0, 90.0, "deg", 1),
        Field(
            "target",
            "success criteria",
            "choice",
            "seed-2d",
            choices=("seed-2d", "deuce", "ad"),
            choice_labels=(
                "paper's 2-D test (Grosen et al. 2021)",
                "deuce service box (3-D)",
                "ad service box (3-D)",
            ),
            help="the paper's 2-D test (value seed-2d), or the real deuce / ad service box in 3-D",
        ),
        Field(
            "azimuth_deg",
            "face azimuth (3-D)",
            "float",
            0.0,
            -30.0,
            30.0,
            "deg",
            0.5,
            help="turns the racket face toward +y (left); needs success criteria deuce or ad",
        ),
        Field(
            "brush_deg",
            "brush direction (3-D)",
            "float",
            0.0,
            -90.0,
            90.0,
            "deg",
            1,
            help="0 = the seed's pure topspin; tilts the brush (and the spin axis) sideways for slice/kick",
        ),
        Field("server_y", "server position y (3-D)", "float", 0.0, -4.0, 4.0, "m", 0.05),
        Field(
            "toss_vz",
            "ball vertical speed at impact",
            "float",
            0.0,
            -6.0,
            6.0,
            "m/s",
            0.1,
            help="negative: the ball is falling when hit",
        ),
    ],
)

_form(
    "window",
    [
        Field("player", "player", "choice", "professional", choices=PLAYERS),
        Field("height", "impact height", "float", 3.0, 1.0, 3.5, "m", 0.01),
        Field("racket_speed", "racket speed", "float", 40.0, 5.0, 70.0, "m/s", 0.1),
        Field("step", "angle step", "float", 2.0, 0.5, 10.0, "deg", 0.5),
    ],
)

SHOT_TYPES = ("topspin", "flat", "backspin", "sidespin-left", "sidespin-right", "custom")

_form(
    "aim",
    [
        Field("target_x", "target x", "float", 8.0, -11.885, 11.885, "m", 0.01),
        Field("target_y", "target y", "float", 0.0, -5.485, 5.485, "m", 0.01),
        Field("speed_kmh", "ball speed", "float", 80.0, 30.0, 200.0, "km/h", 1),
        Field("spin_rpm", "spin", "float", 1000.0, 0.0, 2000.0, "rpm", 1),
        Field("shot", "shot type", "choice", "topspin", choices=SHOT_TYPES),
        Field("spin_axis_deg", "spin axis (custom)", "float", 0.0, -180.0, 180.0, "deg", 1),
        Field("solution", "solution", "choice", "low", choices=("low", "high")),
        Field("height", "launch height", "float", 1.0, 0.1, 3.0, "m", 0.1),
        Field("machine_x", "machine x", "float", -12.385, -20.0, 0.0, "m", 0.1),
        Field("machine_y", "machine y", "float", 0.0, -8.0, 8.0, "m", 0.1),
    ],
)

_form(
    "linecall",
    [
        Field("line", "line", "choice", "auto", choices=("auto",) + tuple(ITF_COURT.lines())),
        Field("target", "target area", "choice", "auto", choices=("auto",) + tuple(ITF_COURT.area_names())),
        Field("surface", "surface", "choice", "hard", choices=tuple(surface_names())),
    ],
)

#: shot type -> spin-axis angle [deg] (the launch vocabulary of :mod:`tennislab.core.launch`)
SHOT_AXIS = {
    "topspin": SPIN_AXES_DEG["topspin"],
    "flat": SPIN_AXES_DEG["topspin"],
    "backspin": SPIN_AXES_DEG["backspin"],
    "sidespin-left": SPIN_AXES_DEG["sidespin-left"],
    "sidespin-right": SPIN_AXES_DEG["sidespin-right"],
}

#: limits of request sizes (bytes / counts / nesting)
MAX_BODY_BYTES = 1_100_000
MAX_TRACK_BYTES = 1_000_000
MAX_DRILL_SHOTS = 50
MAX_JSON_DEPTH = 8

#: Labels of the request keys that are not form fields (the track text, the drill's shots and name).
EXTRA_LABELS = {"csv": "track file", "shots": "drill", "name": "drill name", "body": "request"}

#: Parameter names used by the library's errors (``speed_ms: ...``) -> the form field they come from.
#: The one table that turns library names into labels (:func:`label_message`).
LIBRARY_NAMES = {
    "speed_ms": "speed_kmh",
    "spin_axis": "spin_axis_deg",
    "impact angle": "impact_angle",
    "impact_angle_deg": "impact_angle",
    "alpha_deg": "impact_angle",
    "face angle": "face_angle",
    "beta_deg": "face_angle",
    "azimuth": "azimuth_deg",
    "brush": "brush_deg",
    "impact_height": "height",
    "position": "z",
}


def short(value, n: int = 40) -> str:
    """``repr(value)`` cut to ``n`` characters (user text never makes a long or multi-line message)."""
    r = repr(value)
    return r if len(r) <= n else r[:n] + "..."


def field_label(name) -> str:
    """A user-given (unknown) key as shown in a message: as is if a plain identifier, else quoted."""
    return name if isinstance(name, str) and name.isidentifier() and len(name) <= 40 else short(name)


def label_of(form: str | None, name: str) -> str | None:
    """The on-screen label of a key of ``form`` (a field, a library parameter name or an extra key)."""
    fields = FORMS[form].by_name() if form in FORMS else {}
    key = LIBRARY_NAMES.get(name, name)
    if key in fields:
        return fields[key].label
    return EXTRA_LABELS.get(name)


_LEADING = re.compile(r"^(shots\[(\d+)\]\.?)?([A-Za-z_][A-Za-z0-9_ ]*?)?(\[\d+\])?(?=: )")
#: an internal name inside a message (``speed_kmh``): words joined by underscores
_IDENTIFIER = re.compile(r"\b[a-z][a-z0-9]*(?:_[a-z0-9]+)+\b")


def label_message(form: str | None, message: str) -> str:
    """A one-line message whose leading parameter name is replaced by the label of its field.

    ``speed_ms: -1 m/s is ...`` -> ``speed: -1 m/s is ...`` on the flight form;
    ``shots[2].target_x: ...`` -> ``shot 3: target x: ...``; an internal name inside the message
    (``... raise speed_kmh``) becomes its label too.  Unknown names are left as they are.
    """
    msg = " ".join(str(message).split())
    m = _LEADING.match(msg)
    shot, name = (m.group(2), m.group(3)) if m else (None, None)
    in_form = "aim" if shot is not None else form

    def inner(mm: re.Match) -> str:  # "raise speed_kmh (max 200)" -> "raise ball speed (max 200)"
        return label_of(in_form, mm.group(0)) or mm.group(0)

    if not m:
        return _IDENTIFIER.sub(inner, msg)
    rest = _IDENTIFIER.sub(inner, msg[m.end() :])
    if shot is not None:
        lab = label_of("aim", name) if name else None
        return f"shot {int(shot) + 1}" + (f": {lab or name}" if name else "") + rest
    lab = label_of(form, name) if name else None
    return (lab or msg[: m.end()]) + rest


def validate(form: str, body) -> dict:
    """Validate a request body (dict) against a form; returns the parsed values.

    A missing key takes the field's default; every key present must be valid.  Raises
    :class:`InputError` (labelled) for a body that is not an object, an unknown key, or any value
    out of its range.
    """
    if form not in FORMS:
        raise InputError(f"form: unknown form {form!r}")
    if not isinstance(body, dict):
        raise InputError("request: expected a JSON object")
    fields = FORMS[form].by_name()
    unknown = sorted(set(body) - set(fields), key=str)
    if unknown:
        raise InputError(f"{field_label(unknown[0])}: unknown field (allowed: {', '.join(fields)})")
    return {name: (f.parse(body[name]) if name in body else f.default) for name, f in fields.items()}


def forms_spec() -> dict:
    """All forms as JSON for the page."""
    return {name: [f.spec() for f in form.fields] for name, form in FORMS.items()}
