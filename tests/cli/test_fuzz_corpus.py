"""Fuzz suite of the hardening issue: malformed input for every reader, and every output flag pointed at
a bad place, fed through the CLI commands that use them.

What it promises, for every case: ``tennislab.cli.main`` returns exit code 2, stderr is exactly one
non-empty line (``tennislab[ COMMAND]: error: ...``), no "Traceback" appears on stdout or stderr, and
nothing is written: the working folder (``tmp_path``, entered with ``monkeypatch.chdir``) holds the same
files and folders with the same bytes afterwards (input files included; a refused ``drills import``
creates no database).  Readers covered: track CSV, tracker point JSON, camera JSON + detections CSV,
aero table CSV, material CSVs, drill YAML/JSON, CourtVision serves CSV, surface TOML/JSON,
``tennislab.toml`` and player TOML, the batch manifest, the launcher SQLite database; outputs: every
``--plot``, ``--csv``, ``--out-table``, ``--out-surface``, ``--out``, ``--out-dir``, ``--db`` and the
``drills export`` file.  Hypothesis feeds random bytes (and random near-valid documents) to the track
CSV and point JSON readers through ``call``, using the reader itself as the oracle of "malformed".

Size and run time: about 630 cases, about 17-22 s on 2 cores (every case fails in its checks, before any physics).

Gaps it found, all closed since (2026-12-01) and now among its cases: TOML nested 10^5 deep or holding
a 5000-digit integer (``--config``, ``./tennislab.toml``, ``--player FILE``) gave tracebacks; material
rows of 1e308 N / 1e-308 m answered an infinite modulus; ``serve-window --csv`` and ``launcher drill
--csv`` took any extension; ``--db newdir/`` wrote a file named ``newdir``; ``launcher table`` checked a
300-character ``--db`` name and a malformed ``--out-dir`` manifest only after printing its estimate.
Left as designed: ``drills export NAME OUT`` creates the missing folders of the ``OUT`` the user named.
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import sqlite3

import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from tennislab.cli import main
from tennislab.errors import InputError
from tennislab.io.hawkeye import parse_points
from tennislab.io.track import parse_track

# ---------------------------------------------------------------- helpers

DIGITS = "1" * 5000  #: a 5000-digit number (beyond Python's 4300-digit int conversion limit)
DEEP_JSON = "[" * 100_000 + "]" * 100_000  #: 10^5-deep nesting
DEEP_TOML = "a = " + "[" * 100_000 + "]" * 100_000 + "\n"
NOT_UTF8 = b"\xff\xfe\xfa"
BIG_FIELD = '"' + "a" * 200_000 + '"'  #: one CSV field over the csv module's 128 kB field limit


def _snapshot(root: str) -> dict[str, bytes | None]:
    """Every file (its bytes) and folder (None) under ``root``, hidden ones included."""
    out: dict[str, bytes | None] = {}
    for d, dirs, files in os.walk(root):
        for name in dirs:
            out[os.path.relpath(os.path.join(d, name), root)] = None
        for name in files:
            p = os.path.join(d, name)
            with open(p, "rb") as fh:
                out[os.path.relpath(p, root)] = fh.read()
    return out


def _write(files: dict[str, str | bytes]) -> None:
    for name, content in files.items():
        parent = os.path.dirname(name)
        if parent:
            os.makedirs(parent, exist_ok=True)
        data = content if isinstance(content, bytes) else content.encode("utf-8")
        with open(name, "wb") as fh:
            fh.write(data)


def _main(argv) -> int:
    try:
        return main([str(a) for a in argv])
    except SystemExit as exc:  # argparse's own errors
        return exc.code


def assert_refused(capsys, argv, files=None) -> str:
    """Run the CLI in the current (working) folder holding ``files``; assert the suite's promise."""
    _write(files or {})
    before = _snapshot(".")
    capsys.readouterr()
    rc = _main(argv)
    out, err = capsys.readouterr()
    after = _snapshot(".")
    shown = f"argv={list(argv)!r}\nrc={rc}\nstderr={err[:2000]!r}"
    assert "Traceback" not in out and "Traceback" not in err, shown
    assert rc == 2, shown
    lines = err.splitlines()
    assert len(lines) == 1 and lines[0].strip(), shown
    assert "error:" in lines[0], shown
    assert sorted(after) == sorted(before), f"files written or removed: {set(after) ^ set(before)}\n{shown}"
    changed = [p for p in before if before[p] != after[p]]
    assert not changed, f"files changed: {changed}\n{shown}"
    return err


@pytest.fixture
def cwd(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    return tmp_path


def _params(prefix: str, argv: list[str], name: str, variants: dict, extra: dict | None = None) -> list:
    """One case per variant: the file ``name`` holding the variant's content, read by ``argv``."""
    return [
        pytest.param(argv, {**(extra or {}), name: content}, id=f"{prefix}-{key}") for key, content in variants.items()
    ]


# ---------------------------------------------------------------- the corpus of malformed input files

TRACK_HEAD = "t,x,y,z\n"
TRACK = {
    "missing-column": "t,x,y\n0,0,0\n0.1,0.3,0\n",
    "nan": TRACK_HEAD + "0,0,0,1\n0.1,nan,0,1\n",
    "inf": TRACK_HEAD + "0,0,0,1\n0.1,0,-inf,1\n",
    "non-numeric": TRACK_HEAD + "0,0,0,1\n0.1,abc,0,1\n",
    "non-increasing-time": TRACK_HEAD + "0,0,0,1\n0.1,0.3,0,1\n0.1,0.6,0,1\n",
    "decreasing-time": TRACK_HEAD + "0.2,0,0,1\n0.1,0.3,0,1\n",
    "non-utf8": TRACK_HEAD.encode() + b"0,0,0,1\n" + NOT_UTF8 + b",0,0,1\n",
    "empty": "",
    "only-comments": "# a comment\n\n# another\n",
    "bom-only": "\ufeff",
    "header-only": TRACK_HEAD,
    "5000-digit-number": TRACK_HEAD + f"0,{DIGITS},0,1\n",
    "huge-value": TRACK_HEAD + "0,1e308,0,1\n0.1,0,0,1\n",
    "beyond-float": TRACK_HEAD + "0,1e999,0,1\n",
    "nul-bytes": b"t,x,y,z\n0,0,0,\x00\n",
    "short-row": TRACK_HEAD + "0,0\n",
    "unclosed-quote": TRACK_HEAD + '"0,0,0,1\n',
    "field-over-csv-limit": TRACK_HEAD + BIG_FIELD + ",0,0,1\n",
    "duplicate-column": "t,x,y,z,x\n0,0,0,1,0\n",
    "sigma-out-of-range": "t,x,y,z,sigma\n0,0,0,1,5\n",
    "sigma-zero": "t,x,y,z,sigma\n0,0,0,1,0\n",
    "binary": bytes(range(256)),
}

_SAMPLE = '{"time": 1.0, "ball": {"pos": {"x": 0, "y": 0, "z": 1}}}'
POINT = {
    "invalid-json": '{"samples": [',
    "trailing-comma": '{"samples": [1,],}',
    "samples-number": '{"samples": 5}',
    "samples-null": '{"samples": null}',
    "samples-string": '{"samples": "abc"}',
    "top-number": "42",
    "top-null": "null",
    "top-string": '"point"',
    "deep-nesting-1e5": DEEP_JSON,
    "deep-objects-1e5": '{"a":' * 100_000 + "1" + "}" * 100_000,
    "deep-unclosed-1e5": "[" * 100_000,
    "5000-digit-integer": '{"samples": [{"time": ' + DIGITS + ', "ball": [0, 0, 1]}]}',
    "5000-digit-top": DIGITS,
    "missing-samples": '{"shots": []}',
    "missing-time": '{"samples": [{"ball": {"pos": {"x": 0, "y": 0, "z": 1}}}]}',
    "nan-time": '{"samples": [{"time": NaN, "ball": [0, 0, 1]}]}',
    "coordinate-string": '{"samples": [{"time": 1, "ball": {"pos": {"x": "a", "y": 0, "z": 1}}}]}',
    "coordinate-huge": '{"samples": [{"time": 1, "ball": [1e300, 0, 1]}]}',
    "ball-two-numbers": '{"samples": [{"time": 1, "ball": [0, 1]}]}',
    "ball-number": '{"samples": [{"time": 1, "ball": 5}]}',
    "sample-list": '{"samples": [[1, 2, 3]]}',
    "shots-number": '{"samples": [' + _SAMPLE + '], "shots": 3}',
    "shot-null": '{"samples": [' + _SAMPLE + '], "shots": [null]}',
    "spin-list": '{"samples": [' + _SAMPLE + '], "shots": [{"spin": [1]}]}',
    "sequences-list": '{"samples": [' + _SAMPLE + '], "sequences": [1]}',
    "event-object": '{"samples": [{"time": 1, "ball": [0, 0, 1], "event": [{"type": {"a": 1}}]}]}',
    "points-number": '{"points": 7}',
    "points-empty": '{"points": []}',
    "empty-list": "[]",
    "empty": "",
    "whitespace": " \n\t\n",
    "non-utf8": b'{"samples": ["' + NOT_UTF8 + b'"]}',
    "json-lines-bad-line": '{"samples": []}\n{"samples": [\n',
}

_CAM = {"fx": 2000, "fy": 2000, "cx": 960, "cy": 540, "R": [[1, 0, 0], [0, 1, 0], [0, 0, 1]]}
GOOD_CAMERAS = json.dumps(
    {"cameras": [dict(_CAM, name="a", position=[-5, -20, 5]), dict(_CAM, name="b", position=[5, -20, 5])]}
)
GOOD_DETECTIONS = "t,camera,u,v\n0,a,100,100\n0,b,200,100\n0.01,a,110,100\n0.01,b,210,100\n"


def _cams(first: dict) -> str:
    return json.dumps({"cameras": [first, dict(_CAM, name="b", position=[5, -20, 5])]})


CAMERAS = {
    "invalid-json": '{"cameras": [',
    "empty": "",
    "non-utf8": b'{"cameras": "' + NOT_UTF8 + b'"}',
    "deep-nesting-1e5": DEEP_JSON,
    "5000-digit-integer": '{"cameras": [{"fx": ' + DIGITS + "}]}",
    "top-list": "[]",
    "one-camera": json.dumps({"cameras": [dict(_CAM, name="a", position=[0, -20, 5])]}),
    "cameras-number": '{"cameras": 3}',
    "cameras-null": '{"cameras": null}',
    "camera-null": '{"cameras": [null, null]}',
    "fx-string": _cams(dict(_CAM, name="a", fx="x", position=[0, -20, 5])),
    "fx-null": _cams(dict(_CAM, name="a", fx=None, position=[0, -20, 5])),
    "fx-negative": _cams(dict(_CAM, name="a", fx=-1, position=[0, -20, 5])),
    "fx-infinity": _cams(dict(_CAM, name="a", position=[0, -20, 5])).replace('"fx": 2000', '"fx": Infinity', 1),
    "R-not-rotation": _cams(dict(_CAM, name="a", R=[[2, 0, 0], [0, 1, 0], [0, 0, 1]], position=[0, -20, 5])),
    "R-number": _cams(dict(_CAM, name="a", R=1, position=[0, -20, 5])),
    "R-short-row": _cams(dict(_CAM, name="a", R=[[1, 0], [0, 1, 0], [0, 0, 1]], position=[0, -20, 5])),
    "missing-position": _cams(dict(_CAM, name="a")),
    "position-1e9": _cams(dict(_CAM, name="a", position=[1e9, 0, 0])),
    "width-1e300": _cams(dict(_CAM, name="a", width=1e300, position=[0, -20, 5])),
}

DETECTIONS = {
    "missing-column": "t,camera,u\n0,a,100\n",
    "empty": "",
    "header-only": "t,camera,u,v\n",
    "unknown-camera": "t,camera,u,v\n0,zz,1,1\n",
    "camera-index-out-of-range": "t,camera,u,v\n0,7,1,1\n",
    "non-numeric": "t,camera,u,v\n0,a,x,1\n",
    "nan": "t,camera,u,v\n0,a,nan,1\n",
    "5000-digit-number": f"t,camera,u,v\n0,a,{DIGITS},1\n",
    "short-row": "t,camera,u,v\n0,a\n",
    "non-utf8": b"t,camera,u,v\n0," + NOT_UTF8 + b",1,1\n",
    "nul-bytes": b"t,camera,u,v\n\x00\n",
    "negative-sigma": "t,camera,u,v,sigma_px\n0,a,1,1,-1\n",
    "field-over-csv-limit": "t,camera,u,v\n" + BIG_FIELD + ",a,1,1\n",
    "one-detection": "t,camera,u,v\n0,a,100,100\n",
}

AERO_HEAD = "speed_ms,spin_rpm,cd,cl\n"


def _grid(cd="0.6", cl="0.2", speeds=(10, 60)) -> str:
    return AERO_HEAD + "".join(f"{v},{w},{cd},{cl}\n" for v in speeds for w in (0, 3000))


AERO = {
    "non-utf8": AERO_HEAD.encode() + b"10,0,0.6," + NOT_UTF8 + b"\n",
    "missing-column": "speed_ms,spin_rpm,cd\n10,0,0.6\n",
    "cl-1e6": _grid(cl="1e6"),
    "cd-negative": _grid(cd="-1"),
    "nan": _grid(cd="nan"),
    "non-numeric": _grid(cd="abc"),
    "5000-digit-number": AERO_HEAD + f"{DIGITS},0,0.6,0.2\n",
    "negative-speed": _grid(speeds=(-10, 60)),
    "empty": "",
    "header-only": AERO_HEAD,
    "not-a-full-grid": AERO_HEAD + "10,0,0.6,0.2\n60,0,0.6,0.2\n60,3000,0.6,0.2\n",
    "duplicate-point": AERO_HEAD + "10,0,0.6,0.2\n10,0,0.6,0.2\n",
    "short-row": AERO_HEAD + "10,0\n",
    "nul-bytes": AERO_HEAD.encode() + b"\x00\n",
    "unclosed-quote": AERO_HEAD + '"10,0,0.6,0.2\n',
    "field-over-csv-limit": AERO_HEAD + BIG_FIELD + ",0,0.6,0.2\n",
}

YOUNG = {
    "missing-column": "load_n\n10\n",
    "non-numeric": "load_n,deformation_m\n10,abc\n",
    "nan": "load_n,deformation_m\nnan,0.001\n",
    "inf": "load_n,deformation_m\n1e999,0.001\n",
    "5000-digit-number": f"load_n,deformation_m\n{DIGITS},0.001\n",
    "empty-cell": "load_n,deformation_m\n10,\n",
    "empty": "",
    "header-only": "load_n,deformation_m\n",
    "non-utf8": b"load_n,deformation_m\n10," + NOT_UTF8 + b"\n",
    "nul-bytes": b"load_n,deformation_m\n10,0.001\x00\n",
    "zero-deformation": "load_n,deformation_m\n10,0\n20,0\n",
    "negative-load": "load_n,deformation_m\n-10,-0.001\n",
    "overflowing-modulus": "load_n,deformation_m\n1e308,1e-308\n",
    "subnormal-deformation": "load_n,deformation_m\n10,1e-320\n",
    "deformation-beyond-diameter": "load_n,deformation_m\n10,1\n",
    "huge-negative-load-kg": "load_kg,deformation_m\n-1e300,0.001\n",
    "unclosed-quote": 'load_n,deformation_m\n"10,0.001\n',
    "field-over-csv-limit": "load_n,deformation_m\n" + BIG_FIELD + ",1\n",
}

FRICTION = {
    "missing-column": "angle\n30\n",
    "non-numeric": "friction_angle_deg\nabc\n",
    "nan": "friction_angle_deg\nnan\n",
    "empty": "",
    "header-only": "friction_angle_deg\n",
    "non-utf8": b"friction_angle_deg\n" + NOT_UTF8 + b"\n",
    "angle-90": "friction_angle_deg\n90\n",
    "angle-1e6": "friction_angle_deg\n1e6\n",
    "angle-negative": "friction_angle_deg\n-5\n",
    "contact-length-non-numeric": "friction_angle_deg,contact_length_m\n30,abc\n",
    "contact-length-negative": "friction_angle_deg,contact_length_m\n30,-1\n",
}

DRILL_OK = """name: T
shots:
  a:
    type: drive
    target: [9.0, 0.0]
program:
  - shot: a
    repeats: 1
"""
#: "billion laughs": 9 levels of 9 aliases, 9^9 ~ 3.9e8 values from a few hundred bytes
YAML_BOMB = 'a: &a ["lol","lol","lol","lol","lol","lol","lol","lol","lol"]\n' + "".join(
    f"{n}: &{n} [{','.join([f'*{p}'] * 9)}]\n" for p, n in zip("abcdefgh", "bcdefghi")
)
assert len(YAML_BOMB) < 1000

DRILL_YAML = {
    "alias-bomb": YAML_BOMB,
    "invalid-yaml": "name: [unclosed\n  - : :\n",
    "tab-indentation": "name: T\n\tshots: 1\n",
    "unknown-top-key": DRILL_OK + "colour: red\n",
    "unknown-shot-key": DRILL_OK.replace("type: drive", "type: drive\n    wobble: 3"),
    "non-utf8": b"name: " + NOT_UTF8 + b"\n",
    "negative-count": DRILL_OK.replace(
        "  - shot: a\n    repeats: 1\n", "  - random: [{shot: a, weight: 1}]\n    count: -3\n"
    ),
    "zero-repeats": DRILL_OK.replace("repeats: 1", "repeats: 0"),
    "negative-repeats": DRILL_OK.replace("repeats: 1", "repeats: -1"),
    "5000-digit-repeats": DRILL_OK.replace("repeats: 1", f"repeats: {DIGITS}"),
    "top-list": "- 1\n- 2\n",
    "top-scalar": "hello\n",
    "empty": "",
    "null": "~\n",
    "deep-flow-1e5": DEEP_JSON,
    "deep-block-200": "".join("  " * i + "a:\n" for i in range(200)),
    "python-tag": "name: !!python/object/apply:os.system ['echo hi']\n",
    "unknown-shot-reference": DRILL_OK.replace("- shot: a", "- shot: zz"),
    "target-string": DRILL_OK.replace("[9.0, 0.0]", "far"),
    "target-nan": DRILL_OK.replace("[9.0, 0.0]", "[.nan, 0.0]"),
    "alias-before-anchor": "name: *nope\n",
}
DRILL_JSON = {
    "invalid-json": '{"name": ',
    "deep-nesting-1e5": DEEP_JSON,
    "5000-digit-integer": '{"name": "T", "repeats": ' + DIGITS + "}",
    "unknown-key": json.dumps(
        {"name": "T", "shots": {"a": {"type": "drive", "target": [9, 0]}}, "program": [{"shot": "a"}], "colour": 1}
    ),
    "top-number": "3",
    "non-utf8": b'{"name": "' + NOT_UTF8 + b'"}',
    "over-size-limit": json.dumps({"name": "T", "x": list(range(60_000))}),
}

CV_HEAD = (
    "match,point_ID,serve_num,spd,spin_rpm,x_ball_serve_impact,y_ball_serve_impact,z_ball_serve_impact,"
    "x_net_serve,y_net_serve,z_net_serve,x_serve_bounce,y_serve_bounce,z_serve_bounce,serve_type\n"
)
CV_ROW = (
    "atp_x2020MS001,1_1_1_1,1,144.1323,1512.2739,11.252379,0.005690,2.877171,"
    "0.0,-0.628946,1.315455,-5.525037,-1.052516,0.033500,Flat\n"
)
COURTVISION = {
    "missing-column": CV_HEAD.replace(",spin_rpm", "") + CV_ROW.replace(",1512.2739", ""),
    "non-numeric": CV_HEAD + CV_ROW.replace("144.1323", "fast"),
    "missing-value": CV_HEAD + CV_ROW.replace("144.1323", "NA"),
    "huge-value": CV_HEAD + CV_ROW.replace("144.1323", "1e9"),
    "5000-digit-number": CV_HEAD + CV_ROW.replace("144.1323", DIGITS),
    "empty": "",
    "header-only": CV_HEAD,
    "non-utf8": (CV_HEAD + CV_ROW).encode().replace(b"Flat", NOT_UTF8),
    "nul-bytes": (CV_HEAD + CV_ROW).encode().replace(b"Flat", b"\x00"),
    "short-row": CV_HEAD + "a,b,1\n",
    "duplicate-column": CV_HEAD.replace("serve_type", "spd") + CV_ROW,
    "empty-match": CV_HEAD + CV_ROW.replace("atp_x2020MS001", ""),
    "field-over-csv-limit": "match,point_ID\n" + BIG_FIELD + ",1\n",
}

SURFACE_TOML = {
    "invalid-toml": "e = \n",
    "unknown-key": "e = 0.7\nmu = 0.5\ncolour = 1\n",
    "missing-key": "e = 0.7\n",
    "empty": "",
    "string-value": 'e = "x"\nmu = 0.5\n',
    "boolean-value": "e = true\nmu = 0.5\n",
    "nan": "e = nan\nmu = 0.5\n",
    "out-of-range": "e = 7\nmu = 0.5\n",
    "non-utf8": b'e = 0.7\nmu = 0.5\nname = "' + NOT_UTF8 + b'"\n',
    "deep-nesting-1e5": DEEP_TOML,
    "long-name": 'e = 0.7\nmu = 0.5\nname = "' + "x" * 300 + '"\n',
}
SURFACE_JSON = {
    "invalid-json": '{"e": ',
    "top-list": "[1, 2]",
    "deep-nesting-1e5": DEEP_JSON,
    "5000-digit-integer": '{"e": ' + DIGITS + ', "mu": 0.5}',
    "unknown-key": '{"e": 0.7, "mu": 0.5, "colour": 1}',
}

CONFIG = {
    "invalid-toml": "[physics\n",
    "unknown-key": "[physics]\ndrag = 0.5\n",
    "unknown-table": "[colour]\na = 1\n",
    "wrong-type": '[physics]\ncd = "high"\n',
    "nan": "[physics]\ncd = nan\n",
    "wind-two-numbers": "[physics]\nwind = [1, 2]\n",
    "mass-out-of-range": "[physics]\nmass = -1\n",
    "non-utf8": b'[physics]\naero = "' + NOT_UTF8 + b'"\n',
    "unknown-surface": '[court]\nsurface = "lava"\n',
    "unknown-default-player": '[defaults]\nplayer = "nobody"\n',
    "machine-wrong-type": '[machines.m]\nroller_radius = "x"\n',
    "bad-profile-name": '[players."a b"]\nimpact_height = 2\n',
    "player-unknown-field": "[players.p]\nwobble = 2\n",
    "missing-aero-table": '[physics]\naero = "table"\naero_table = "nope.csv"\n',
    "physics-not-a-table": "physics = 3\n",
    "10^5-deep-nesting": DEEP_TOML,
    "5000-digit-integer": f"[physics]\ncd = {DIGITS}\n",
}

PLAYER = {
    "10^5-deep-nesting": DEEP_TOML,
    "5000-digit-integer": f"impact_height = {DIGITS}\n",
    "invalid-toml": "impact_height = \n",
    "unknown-key": "impact_height = 2.5\nwobble = 1\n",
    "string-value": 'impact_height = "tall"\n',
    "negative-height": "impact_height = -5\n",
    "non-utf8": b'name = "' + NOT_UTF8 + b'"\n',
    "empty": "",
    "nested-table": "[a.b]\nc = 1\n",
}

MANIFEST = {
    "empty-list": "[]",
    "garbage": "garbage{{",
    "empty": "",
    "null": "null",
    "number": "3",
    "wrong-object": '{"a": 1}',
    "non-utf8": b'{"' + NOT_UTF8 + b'": 1}',
    "deep-nesting-1e5": DEEP_JSON,
    "5000-digit-integer": '{"format": ' + DIGITS + "}",
    "nul-bytes": b"\x00\x00",
}

FLY = ["fly", "--speed-kmh", "100", "--elevation-deg", "5"]
STATE = ["call", "--position", "-11.9", "0.4", "2.85", "--velocity", "50", "1", "-4.4"]
SERVE_WINDOW = ["serve-window", "--step", "30"]

CORPUS = [
    *_params("track", ["call", "--track", "in.csv"], "in.csv", TRACK),
    *_params(
        "calibrate-tracks",
        ["calibrate", "tracks", "in.csv", "--quiet"],
        "in.csv",
        {k: TRACK[k] for k in ("missing-column", "nan", "non-utf8", "empty")},
    ),
    *_params(
        "calibrate-surface-track",
        ["calibrate", "surface", "--track", "in.csv", "--quiet"],
        "in.csv",
        {k: TRACK[k] for k in ("missing-column", "non-increasing-time")},
    ),
    *_params("point", ["call", "--rally", "in.json"], "in.json", POINT),
    *_params(
        "point-dir",
        ["call", "--rally", "pts"],
        "pts/b.json",
        {
            "one-bad-file": "{",
            "deep-nesting-1e5": DEEP_JSON,
        },
        extra={"pts/a.json": '{"samples": []}'},
    ),
    pytest.param(["call", "--rally", "pts"], {"pts/readme.txt": "x"}, id="point-dir-no-json-files"),
    *_params(
        "calibrate-surface-point",
        ["calibrate", "surface", "--rally", "in.json", "--quiet"],
        "in.json",
        {k: POINT[k] for k in ("invalid-json", "deep-unclosed-1e5", "missing-samples")},
    ),
    *_params(
        "cameras",
        ["call", "--cameras", "cams.json", "--detections", "det.csv"],
        "cams.json",
        CAMERAS,
        extra={"det.csv": GOOD_DETECTIONS},
    ),
    *_params(
        "detections",
        ["call", "--cameras", "cams.json", "--detections", "det.csv"],
        "det.csv",
        DETECTIONS,
        extra={"cams.json": GOOD_CAMERAS},
    ),
    pytest.param(["call", "--cameras", "cams.json"], {"cams.json": GOOD_CAMERAS}, id="cameras-without-detections"),
    *_params("aero-table-fly", [*FLY, "--aero", "table", "--aero-table", "aero.csv"], "aero.csv", AERO),
    *_params(
        "aero-table-call",
        [*STATE, "--aero", "table", "--aero-table", "aero.csv"],
        "aero.csv",
        {k: AERO[k] for k in ("non-utf8", "missing-column", "cl-1e6", "nan")},
    ),
    *_params(
        "aero-table-launcher-aim",
        ["launcher", "aim", "--target", "9", "0", "--speed-kmh", "100", "--aero", "table", "--aero-table", "aero.csv"],
        "aero.csv",
        {k: AERO[k] for k in ("non-utf8", "missing-column", "cl-1e6", "nan")},
    ),
    *_params(
        "aero-table-calibrate",
        ["calibrate", "validate", "--serves", "s.csv", "--aero-table", "aero.csv", "--quiet"],
        "aero.csv",
        {k: AERO[k] for k in ("non-utf8", "missing-column", "cl-1e6", "nan")},
        extra={"s.csv": CV_HEAD + CV_ROW},
    ),
    *_params("material-young", ["material", "young", "--csv", "m.csv"], "m.csv", YOUNG),
    *_params("material-friction", ["material", "friction", "--csv", "m.csv"], "m.csv", FRICTION),
    *_params("drill-yaml", ["launcher", "drill", "--drill", "d.yaml"], "d.yaml", DRILL_YAML),
    *_params(
        "drill-yaml-positional",
        ["launcher", "drill", "d.yaml"],
        "d.yaml",
        {k: DRILL_YAML[k] for k in ("alias-bomb", "invalid-yaml", "unknown-top-key", "non-utf8", "negative-count")},
    ),
    *_params("drill-json", ["launcher", "drill", "--drill", "d.json"], "d.json", DRILL_JSON),
    *_params(
        "drills-import-yaml", ["launcher", "drills", "import", "--db", "drills.sqlite", "d.yaml"], "d.yaml", DRILL_YAML
    ),
    *_params(
        "drills-import-json", ["launcher", "drills", "import", "--db", "drills.sqlite", "d.json"], "d.json", DRILL_JSON
    ),
    *_params(
        "drills-import-second-file",
        ["launcher", "drills", "import", "--db", "drills.sqlite", "lobs", "d.yaml"],
        "d.yaml",
        {k: DRILL_YAML[k] for k in ("alias-bomb", "invalid-yaml", "unknown-top-key", "non-utf8", "negative-count")},
    ),
    *_params("courtvision-validate", ["calibrate", "validate", "--serves", "s.csv", "--quiet"], "s.csv", COURTVISION),
    *_params(
        "courtvision-serves",
        ["calibrate", "serves", "--serves", "s.csv", "--quiet"],
        "s.csv",
        {k: COURTVISION[k] for k in ("missing-column", "non-numeric", "non-utf8")},
    ),
    *_params(
        "courtvision-sensitivity",
        ["calibrate", "sensitivity", "--serves", "s.csv", "--quiet"],
        "s.csv",
        {k: COURTVISION[k] for k in ("missing-column", "non-numeric", "non-utf8")},
    ),
    *_params("surface-toml-call", [*STATE, "--surface", "court.toml"], "court.toml", SURFACE_TOML),
    *_params("surface-toml-fly", [*FLY, "--bounces", "1", "--surface", "court.toml"], "court.toml", SURFACE_TOML),
    *_params("surface-json-call", [*STATE, "--surface", "court.json"], "court.json", SURFACE_JSON),
    *_params("surface-json-fly", [*FLY, "--bounces", "1", "--surface", "court.json"], "court.json", SURFACE_JSON),
    *_params("config", [*FLY, "--config", "c.toml"], "c.toml", CONFIG),
    *_params(
        "config-before-command",
        ["--config", "c.toml", *FLY],
        "c.toml",
        {k: CONFIG[k] for k in ("invalid-toml", "unknown-key")},
    ),
    *_params(
        "config-in-working-folder",
        FLY,
        "tennislab.toml",
        {k: CONFIG[k] for k in ("invalid-toml", "unknown-key", "non-utf8")},
    ),
    *_params(
        "config-launcher-aim",
        ["launcher", "aim", "--target", "9", "0", "--speed-kmh", "100", "--config", "c.toml"],
        "c.toml",
        {k: CONFIG[k] for k in ("invalid-toml", "unknown-key")},
    ),
    *_params("player-file", [*SERVE_WINDOW, "--player", "p.toml"], "p.toml", PLAYER),
    *_params("batch-manifest", [*SERVE_WINDOW, "--out-dir", "out"], "out/manifest.json", MANIFEST),
    pytest.param([*SERVE_WINDOW, "--out-dir", "out"], {"out/other.txt": "x"}, id="batch-dir-without-manifest"),
    pytest.param([*SERVE_WINDOW, "--out-dir", "out"], {"out/manifest.json/x": "x"}, id="batch-manifest-is-a-dir"),
]

#: a missing input file and a directory given as the input file, for every reader
MISSING_OR_DIRECTORY = {
    "track": ["call", "--track", "{p}"],
    "point": ["call", "--rally", "{p}"],
    "cameras": ["call", "--cameras", "{p}", "--detections", "{p}"],
    "aero-table": [*FLY, "--aero", "table", "--aero-table", "{p}"],
    "material-young": ["material", "young", "--csv", "{p}"],
    "material-friction": ["material", "friction", "--csv", "{p}"],
    "drill": ["launcher", "drill", "{p}.yaml"],
    "drills-import": ["launcher", "drills", "import", "--db", "drills.sqlite", "{p}.yaml"],
    "courtvision": ["calibrate", "validate", "--serves", "{p}", "--quiet"],
    "surface": [*FLY, "--bounces", "1", "--surface", "{p}.toml"],
    "config": [*FLY, "--config", "{p}"],
    "player-file": [*SERVE_WINDOW, "--player", "{p}.toml"],
    "database-info": ["launcher", "info", "--db", "{p}"],
    "database-lookup": ["launcher", "lookup", "--db", "{p}", "--target", "9", "0"],
    "calibrate-tracks": ["calibrate", "tracks", "{p}", "--quiet"],
}
for _key, _argv in MISSING_OR_DIRECTORY.items():
    CORPUS.append(pytest.param([a.format(p="nope") for a in _argv], {}, id=f"{_key}-missing-file"))
    CORPUS.append(
        pytest.param(
            [a.format(p="adir") for a in _argv],
            {"adir/x": "", "adir.yaml/x": "", "adir.toml/x": ""},
            id=f"{_key}-is-a-directory",
        )
    )


@pytest.mark.parametrize("argv,files", CORPUS)
def test_malformed_input_is_refused_in_one_line(cwd, capsys, argv, files):
    assert_refused(capsys, argv, files)
    assert not os.path.exists("drills.sqlite")  # a refused import creates no database


# ---------------------------------------------------------------- the launcher database


@pytest.fixture(scope="module")
def launcher_db(tmp_path_factory) -> dict[str, bytes]:
    """A real launcher database (the shipped drill 'lobs' imported) and one of another application."""
    d = tmp_path_factory.mktemp("db")
    real = str(d / "real.sqlite")
    with contextlib.redirect_stdout(io.StringIO()):
        assert main(["launcher", "drills", "import", "--db", real, "lobs"]) == 0
    other = str(d / "other.sqlite")
    con = sqlite3.connect(other)
    con.execute("create table t (x)")
    con.execute("insert into t values (1)")
    con.commit()
    con.close()
    with open(real, "rb") as fh, open(other, "rb") as gh:
        return {"real": fh.read(), "other": gh.read()}


BROKEN_DB = {
    "text-file": lambda db: b"hello, I am not a database\n" * 10,
    "empty-file": lambda db: b"",
    "zeros": lambda db: b"\x00" * 4096,
    "json-file": lambda db: b'{"hits": []}',
    "sqlite-header-only": lambda db: db["real"][:100],
    "truncated-to-half": lambda db: db["real"][: len(db["real"]) // 2],
    "truncated-to-one-page": lambda db: db["real"][:4096],
    "garbage-after-magic": lambda db: db["real"][:16] + bytes(range(256)) * (len(db["real"]) // 256),
    "damaged-page": lambda db: db["real"][:4096] + b"\xff" * 4096 + db["real"][8192:],
    "another-application": lambda db: db["other"],
}
DB_COMMANDS = {
    "info": ["launcher", "info", "--db", "x.sqlite"],
    "info-check": ["launcher", "info", "--check", "--db", "x.sqlite"],
    "info-json": ["launcher", "info", "--json", "--db", "x.sqlite"],
    "lookup": ["launcher", "lookup", "--db", "x.sqlite", "--target", "9", "0"],
    "play": ["launcher", "play", "--db", "x.sqlite", "--drill", "Lobs"],
    "drill": ["launcher", "drill", "--db", "x.sqlite", "Lobs"],
    "drills-list": ["launcher", "drills", "list", "--db", "x.sqlite"],
    "drills-export": ["launcher", "drills", "export", "--db", "x.sqlite", "Lobs", "-"],
    "drills-import": ["launcher", "drills", "import", "--db", "x.sqlite", "lobs"],
}
DB_CASES = [
    pytest.param(cmd, broken, id=f"{cmd}-{broken}")
    for cmd in DB_COMMANDS
    for broken in BROKEN_DB
    if not (cmd == "drills-import" and broken == "empty-file")  # an empty file is a new database: fine
]


@pytest.mark.parametrize("cmd,broken", DB_CASES)
def test_broken_database_is_refused_in_one_line(cwd, capsys, launcher_db, cmd, broken):
    assert_refused(capsys, DB_COMMANDS[cmd], {"x.sqlite": BROKEN_DB[broken](launcher_db)})


# ---------------------------------------------------------------- output flags pointed at bad places

BAD_PLACES = {
    "under-a-regular-file": ("afile/x{ext}", {"afile": "not a folder"}),
    "unknown-extension": ("x.xyz", {}),
    "no-extension": ("x", {}),
    "300-character-name": ("n" * 296 + "{ext}", {}),
    "missing-directory": ("nodir/x{ext}", {}),
    "an-existing-directory": ("adir", {"adir/keep": "x"}),
    "trailing-slash": ("newdir/", {}),
    "empty-string": ("", {}),
}
_VALID_SERVES = {"s.csv": CV_HEAD + CV_ROW}
_VALID_TRACK = {"t.csv": TRACK_HEAD + "".join(f"{i / 100},{-10 + i * 0.3},0,{2 - 0.01 * i}\n" for i in range(30))}
#: (id, argv, output flag, extension it takes, input files, bad places that are fine for it)
OUTPUTS = [
    ("fly", FLY, "--plot", ".png", {}, ()),
    ("call-state", STATE, "--plot", ".png", {}, ()),
    ("call-track", ["call", "--track", "t.csv"], "--plot", ".png", _VALID_TRACK, ()),
    ("call-rally", ["call", "--rally", "p.json"], "--plot", ".png", {"p.json": '{"samples": []}'}, ()),
    ("call-rally", ["call", "--rally", "p.json"], "--csv", ".csv", {"p.json": '{"samples": []}'}, ()),
    ("serve-window", SERVE_WINDOW, "--plot", ".png", {}, ()),
    ("serve-window", SERVE_WINDOW, "--csv", ".csv", {}, ()),
    ("launcher-aim", ["launcher", "aim", "--target", "9", "0", "--speed-kmh", "100"], "--plot", ".png", {}, ()),
    ("launcher-drill", ["launcher", "drill", "lobs"], "--plot", ".png", {}, ()),
    ("launcher-drill", ["launcher", "drill", "lobs"], "--csv", ".csv", {}, ()),
    ("serve", ["serve", "--impact-angle", "3", "--face-angle", "8"], "--plot", ".png", {}, ()),
    ("impact", ["impact", "--racket-speed", "40", "--impact-angle", "10"], "--plot", ".png", {}, ()),
    ("serve-mc", ["serve-mc", "--impact-angle", "3", "--face-angle", "8", "--n", "100"], "--plot", ".png", {}, ()),
    (
        "calibrate-validate",
        ["calibrate", "validate", "--serves", "s.csv", "--quiet"],
        "--plot",
        ".png",
        _VALID_SERVES,
        (),
    ),
    (
        "calibrate-validate",
        ["calibrate", "validate", "--serves", "s.csv", "--quiet"],
        "--csv",
        ".csv",
        _VALID_SERVES,
        (),
    ),
    (
        "calibrate-serves",
        ["calibrate", "serves", "--serves", "s.csv", "--quiet"],
        "--out-table",
        ".csv",
        _VALID_SERVES,
        (),
    ),
    ("calibrate-tracks", ["calibrate", "tracks", "t.csv", "--quiet"], "--csv", ".csv", _VALID_TRACK, ()),
    ("calibrate-tracks", ["calibrate", "tracks", "t.csv", "--quiet"], "--out-table", ".csv", _VALID_TRACK, ()),
    (
        "calibrate-surface",
        ["calibrate", "surface", "--track", "t.csv", "--quiet"],
        "--out-surface",
        ".toml",
        _VALID_TRACK,
        (),
    ),
    ("calibrate-surface", ["calibrate", "surface", "--track", "t.csv", "--quiet"], "--csv", ".csv", _VALID_TRACK, ()),
    # --out DIR|FILE.html: any other name is a directory, created if missing
    (
        "report",
        ["report", "--quiet"],
        "--out",
        ".html",
        {},
        ("unknown-extension", "no-extension", "an-existing-directory", "trailing-slash"),
    ),
    # --out-dir DIR: created if missing, any name
    (
        "serve-window",
        SERVE_WINDOW,
        "--out-dir",
        "",
        {},
        ("unknown-extension", "no-extension", "missing-directory", "trailing-slash"),
    ),
    (
        "serve-mc",
        ["serve-mc", "--impact-angle", "3", "--face-angle", "8", "--n", "100"],
        "--out-dir",
        "",
        {},
        ("unknown-extension", "no-extension", "missing-directory", "trailing-slash"),
    ),
    # --db FILE: any extension
    (
        "launcher-table",
        [
            "launcher",
            "table",
            "--height",
            "1",
            "--speed-kmh",
            "90",
            "90",
            "--spin-rpm",
            "0",
            "0",
            "--spin-axis-deg",
            "0",
            "0",
            "--no-progress",
        ],
        "--db",
        ".sqlite",
        {},
        ("unknown-extension", "no-extension"),
    ),
    (
        "drills-import",
        ["launcher", "drills", "import", "lobs"],
        "--db",
        ".sqlite",
        {},
        ("unknown-extension", "no-extension"),
    ),
]
OUTPUT_CASES = [
    pytest.param(argv, flag, place.format(ext=ext), {**files, **extra}, id=f"{name}{flag}-{bad}")
    for name, argv, flag, ext, files, fine in OUTPUTS
    for bad, (place, extra) in BAD_PLACES.items()
    if bad not in fine
]


@pytest.mark.parametrize("argv,flag,place,files", OUTPUT_CASES)
def test_output_to_a_bad_place_is_refused_in_one_line(cwd, capsys, argv, flag, place, files):
    err = assert_refused(capsys, [*argv, flag, place], files)
    assert flag in err  # refused for the output, not for something else on the line


#: ``drills export NAME OUT``: OUT of any name is fine, and its missing folders are created (as designed)
@pytest.mark.parametrize(
    "bad", [b for b in BAD_PLACES if b not in ("unknown-extension", "no-extension", "missing-directory")]
)
def test_drills_export_to_a_bad_place_is_refused_in_one_line(cwd, capsys, launcher_db, bad):
    place, extra = BAD_PLACES[bad]
    argv = ["launcher", "drills", "export", "--db", "real.sqlite", "Lobs", place.format(ext=".yaml")]
    assert_refused(capsys, argv, {"real.sqlite": launcher_db["real"], **extra})


# ---------------------------------------------------------------- random input (hypothesis)

FUZZ = settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])


def _refused_by(reader, data: bytes) -> bool:
    """True when the reader refuses ``data`` with an InputError (any other exception is a bug: raised)."""
    try:
        reader(data)
    except InputError:
        return True
    return False


def _fuzz(tmp_path, monkeypatch, capsys, argv, name, data: bytes) -> None:
    work = tmp_path / f"ex{len(os.listdir(tmp_path))}"
    work.mkdir()
    monkeypatch.chdir(work)
    assert_refused(capsys, argv, {name: data})


_CSV_TEXT = st.text(alphabet='0123456789.,-+eEnaif"# \t\r\n', max_size=200)


@FUZZ
@given(data=st.one_of(st.binary(max_size=400), _CSV_TEXT.map(lambda s: (TRACK_HEAD + s).encode())))
def test_random_track_csv_is_refused_in_one_line(tmp_path, monkeypatch, capsys, data):
    assume(_refused_by(parse_track, data))
    _fuzz(tmp_path, monkeypatch, capsys, ["call", "--track", "in.csv"], "in.csv", data)


_KEYS = st.sampled_from(["samples", "time", "t", "ball", "pos", "x", "y", "z", "shots", "points", "event", "spin"])
_JSON = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats() | st.text(max_size=4),
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(_KEYS, inner, max_size=4),
    max_leaves=25,
)


@FUZZ
@given(data=st.one_of(st.binary(max_size=400), _JSON.map(lambda doc: json.dumps(doc).encode())))
def test_random_point_json_is_refused_in_one_line(tmp_path, monkeypatch, capsys, data):
    assume(_refused_by(parse_points, data))
    _fuzz(tmp_path, monkeypatch, capsys, ["call", "--rally", "in.json"], "in.json", data)
