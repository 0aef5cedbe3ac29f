"""The one JSON cleaner and the result base class."""

import dataclasses
import json
import math

import numpy as np
import pytest

from tennislab.errors import InputError
from tennislab.results import Result, jsonable


@dataclasses.dataclass(frozen=True)
class _Table(Result):
    x: np.ndarray
    name: str = "t"

    def rows(self):
        return [{"x": float(v)} for v in self.x]


def test_jsonable_cleans_numpy_and_non_finite():
    out = jsonable(
        {"a": np.float64(1.5), "b": float("nan"), "c": np.arange(3), "d": (np.bool_(True), math.inf), 1: np.int32(4)}
    )
    assert out == {"a": 1.5, "b": None, "c": [0, 1, 2], "d": [True, None], "1": 4}
    json.dumps(out, allow_nan=False)


def test_result_to_dict_and_frame():
    r = _Table(np.array([1.0, np.nan]))
    assert r.to_dict() == {"x": [1.0, None], "name": "t"}
    assert jsonable([r]) == [{"x": [1.0, None], "name": "t"}]
    pd = pytest.importorskip("pandas")
    f = r.to_frame()
    assert isinstance(f, pd.DataFrame) and list(f["x"][:1]) == [1.0]


def test_too_deep_is_an_input_error():
    deep: list = []
    cur = deep
    for _ in range(100):
        cur.append([])
        cur = cur[0]
    with pytest.raises(InputError, match="deeper"):
        jsonable(deep)
