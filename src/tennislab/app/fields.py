"""Form fields of the web application: one definition for the page and the server.

Every input the browser can send is declared here as a :class:`Field` (kind,
range, unit, default).  The server validates each request body against its
form with :func:`validate` (unknown fields refused, every value range-checked
with :func:`tennislab.errors.check_range`, so the messages are the CLI's); the
page fetches the same definitions from ``/api/meta`` and checks each input
before it sends anything, showing the same message under the field.

Ranges are the physically meaningful ones of each model (e.g. the launcher's
are its machine spec; see ``docs/app.md``).  Values are in the units the user
sees (km/h, rpm, degrees) and converted to SI in :mod:`tennislab.app.services`.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

from tennislab.core.court import ITF_COURT
from tennislab.errors import InputError, check_range

AERO_CHOICES = ("stepanek1988", "launcher2015", "cross2014", "constant")


@dataclass(frozen=True)
class Field:
    """One form field.

    Attributes
    ----------
    name : key in the JSON body
    label : text shown in the page
    kind : ``float``, ``int``, ``choice`` or ``bool``
    default : value filled in the page
    lo, hi : allowed range (inclusive; ``lo_open`` makes the lower bound exclusive)
    unit : unit shown and named in messages
    step : input step in the page (does not restrict the server)
    choices : allowed values of a ``choice`` field
    optional : the field may be missing or null (then ``default`` is used)
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
    optional: bool = True
    lo_open: bool = False
    help: str = ""

    def parse(self, value):
        """Return the validated value or raise :class:`InputError` naming the field."""
        if isinstance(value, str) and len(value) > 60:
            raise InputError(
                f"{self.name}: expected {'one of ' + ', '.join(self.choices) if self.choices else 'a number'}"
                f", got a text of {len(value)} characters"
            )
        if value is None or (isinstance(value, str) and value.strip() == "" and self.kind != "choice"):
            if self.optional:
                return self.default
            raise InputError(f"{self.name}: a value is required")
        if self.kind == "choice":
            if not isinstance(value, str) or value not in self.choices:
                raise InputError(f"{self.name}: {short(value)} is not one of {', '.join(map(str, self.choices))}")
            return value
        if self.kind == "bool":
            if isinstance(value, bool):
                return value
            raise InputError(f"{self.name}: expected true or false, got {value!r}")
        if isinstance(value, bool) or not isinstance(value, (int, float, str)):
            raise InputError(f"{self.name}: expected a number, got {short(value)}")
        v = check_range(self.name, value, self.lo, self.hi, self.unit, lo_open=self.lo_open)
        if self.kind == "int":
            if v != math.floor(v):
                raise InputError(f"{self.name}: expected a whole number, got {value!r}")
            return int(v)
        return v

    def spec(self) -> dict:
        """The JSON description sent to the page."""
        d = asdict(self)
        d["choices"] = list(self.choices)
        return d


def _physics_fields(default_aero: str) -> list[Field]:
    return [
        Field("aero", "aero model", "choice", default_aero, choices=AERO_CHOICES),
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
        *_physics_fields("stepanek1988"),
    ],
)

PLAYERS = ("professional", "recreational", "junior", "custom")

_form(
    "serve",
    [
        Field("player", "player", "choice", "professional", choices=PLAYERS),
        Field("height", "impact height", "float", 3.0, 1.0, 3.5, "m", 0.01),
        Field("racket_speed", "racket speed", "float", 40.0, 5.0, 70.0, "m/s", 0.1),
        Field("impact_angle", "impact angle alpha", "float", 36.0, 0.0, 90.0, "deg", 1),
        Field("face_angle", "face angle beta", "float", 21.0, -10.0, 90.0, "deg", 1),
        Field(
            "target",
            "success criteria",
            "choice",
            "seed-2d",
            choices=("seed-2d", "deuce", "ad"),
            help="seed-2d: the paper's 2-D test; deuce/ad: the real service box in 3-D",
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
            help="turns the racket face toward +y (left); needs target deuce or ad",
        ),
        Field(
            "brush_deg",
            "brush direction / spin axis (3-D)",
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
        Field("step", "angle step", "float", 1.0, 0.5, 10.0, "deg", 0.5),
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
        Field("surface", "surface", "choice", "hard", choices=("hard", "clay", "grass", "carpet")),
    ],
)

#: shot type -> spin-axis angle [deg] (launcher convention: 0 topspin, 180 backspin, +-90 sidespin)
SHOT_AXIS = {"topspin": 0.0, "flat": 0.0, "backspin": 180.0, "sidespin-left": 90.0, "sidespin-right": -90.0}

#: limits of request sizes (bytes / counts)
MAX_BODY_BYTES = 1_100_000
MAX_TRACK_BYTES = 1_000_000
MAX_DRILL_SHOTS = 50


def short(value, n: int = 40) -> str:
    """``repr(value)`` cut to ``n`` characters (user text never makes a long or multi-line message)."""
    r = repr(value)
    return r if len(r) <= n else r[:n] + "..."


def field_label(name) -> str:
    """A user-given field name as shown in a message: as is if a plain identifier, else quoted."""
    return name if isinstance(name, str) and name.isidentifier() and len(name) <= 40 else short(name)


def validate(form: str, body) -> dict:
    """Validate a request body (dict) against a form; returns the parsed values.

    Raises :class:`InputError` for a body that is not an object, an unknown
    field, or any value out of its range.
    """
    if form not in FORMS:
        raise InputError(f"form: unknown form {form!r}")
    if not isinstance(body, dict):
        raise InputError("body: expected a JSON object")
    fields = FORMS[form].by_name()
    unknown = sorted(set(body) - set(fields))
    if unknown:
        raise InputError(f"{field_label(unknown[0])}: unknown field (allowed: {', '.join(fields)})")
    return {name: f.parse(body.get(name)) for name, f in fields.items()}


def forms_spec() -> dict:
    """All forms as JSON for the page."""
    return {name: [f.spec() for f in form.fields] for name, form in FORMS.items()}
