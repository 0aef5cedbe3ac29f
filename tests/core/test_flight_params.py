"""FlightParams carries its own serialisation: ``to_dict()`` (JSON) and ``from_dict`` rebuild every setting."""

from __future__ import annotations

import json
import math
import pickle

import numpy as np
import pytest

from tennislab.core.aero import aero_model_names, callable_model, get_aero_model
from tennislab.core.court import Court
from tennislab.core.flight import FlightParams, fly_batch
from tennislab.errors import InputError

TABLE = (np.array([10.0, 30.0]), np.array([0.0, 300.0]), np.array([[0.5, 0.6], [0.55, 0.65]]), np.zeros((2, 2)))

#: every setting away from its default
ODD = FlightParams.from_options(
    aero="launcher2015",
    cd=0.5,
    cl=0.4,
    mass=0.058,
    radius=0.034,
    inertia_factor=0.55,
    air_density=1.1,
    gravity=9.81,
    wind=(1.0, -2.0, 0.5),
    spin_decay=0.1,
    t_max=7.0,
    net_obstacle=True,
    court=Court(net_center_height=0.95),
)


def _round_trip(p: FlightParams) -> FlightParams:
    return FlightParams.from_dict(json.loads(json.dumps(p.to_dict(), allow_nan=False)))


@pytest.mark.parametrize("name", [n for n in aero_model_names() if n != "table"])
def test_every_registered_model_round_trips_through_json(name):
    p = FlightParams.from_options(aero=name)
    q = _round_trip(p)
    assert q == p and q.aero.batch_tol == p.aero.batch_tol


def test_every_setting_round_trips_and_is_honoured():
    q = _round_trip(ODD)
    assert q == ODD
    assert q.to_dict() == ODD.to_dict()
    d = ODD.to_dict()
    assert d["aero_options"] == {"cd": 0.5, "cl": 0.4} and d["court"]["net_center_height"] == 0.95
    assert (d["t_max"], d["net_obstacle"], d["inertia_factor"], d["wind"]) == (7.0, True, 0.55, [1.0, -2.0, 0.5])
    # the rebuilt parameters fly the same numbers
    s = np.array([[-11.885, 0.0, 2.6, 45.0, 1.0, -5.0, 0.0, 300.0, 0.0]])
    np.testing.assert_array_equal(fly_batch(s, q).data, fly_batch(s, ODD).data)


def test_capped_lift_and_table_round_trip():
    p = FlightParams.from_options(aero=get_aero_model("choppin2018", cl_max=math.inf))
    q = _round_trip(p)
    assert q.aero.options == {"cl_max": math.inf} and q == p and q.aero.batch_tol == p.aero.batch_tol
    t = FlightParams.from_options(aero="table", aero_table=TABLE)
    assert _round_trip(t) == t


def test_the_dict_and_the_params_pickle():
    assert pickle.loads(pickle.dumps(ODD)) == ODD
    assert FlightParams.from_dict(pickle.loads(pickle.dumps(ODD.to_dict()))) == ODD


def test_missing_keys_keep_the_defaults():
    assert FlightParams.from_dict({}) == FlightParams()
    assert FlightParams.from_dict({"t_max": 3.0}).t_max == 3.0


@pytest.mark.parametrize(
    "d,match",
    [
        ({"speed": 3}, "^speed: unknown physics setting"),
        ({"aero": "nope"}, "^aero: unknown model"),
        ({"mass": 5.0}, "^mass:"),
        ({"court": {"width": 3}}, "^court: unknown dimension"),
        ({"aero_options": [1]}, "^aero_options:"),
    ],
)
def test_bad_dicts_name_the_key(d, match):
    with pytest.raises(InputError, match=match):
        FlightParams.from_dict(d)


def test_a_callable_model_says_it_cannot_be_rebuilt():
    p = FlightParams(aero=callable_model(lambda v, w: (0.55, 0.0)))
    assert p.to_dict()["aero_options"] is None
    with pytest.raises(InputError, match="^aero: .*callable"):
        FlightParams.from_dict(p.to_dict())
