"""Fuzz suite of the hardening issues (21 and 24): malformed and hostile input for every reader, every
output flag pointed at a bad place, crafted databases, numbers at the edge of the floats, fed through the
CLI commands that use them.

What it promises, for every refused case: ``tennislab.cli.main`` returns exit code 2, stderr is exactly
one non-empty line (``tennislab[ COMMAND]: error: ...``), no "Traceback" appears on stdout or stderr, and
nothing is written: the working folder (``tmp_path``, entered with ``monkeypatch.chdir``) holds the same
files, folders, links and special files with the same bytes afterwards (input files included; a refused
``drills import`` creates no database, no ``-wal``/``-shm``).  Readers covered: track CSV, tracker point
JSON (a file and a folder), camera JSON + detections CSV, aero table CSV, material CSVs, drill YAML/JSON,
CourtVision serves CSV, surface TOML/JSON, ``tennislab.toml`` and player TOML, the batch manifest, the
launcher SQLite database (and its ``-wal``); outputs: every ``--plot``, ``--csv``, ``--out-table``,
``--out-surface``, ``--out``, ``--out-dir``, ``--db`` and the ``drills export`` file.

Issue 24 added (docs/security.md F11-F15, D6-D9, N1-N3, A3/A4/A8): every reader given a FIFO, a socket
and a link to /dev/zero (each case under a 60 s alarm: a blocking open fails instead of hanging); every
output given a FIFO, a socket, a link to /dev/null and a link to /dev/stdout; crafted databases (views,
triggers, recursive CTEs, extra or changed schema objects; 10^5-deep and duplicate-key stored JSON; hits
and drills out of range) for every database command; outputs that are inputs of the same command; every
float flag given subnormals, NaN and infinities; impact steps that would not end a contact; output names
that are not UTF-8; an OS error while writing.  Hypothesis feeds random bytes (and random near-valid
documents) to the track CSV and point JSON readers through ``call``, using the reader itself as the oracle
of "malformed".

Size and run time: about 1,100 cases, every one failing in its checks before any physics except a few
that write a small file or fill a 8,181-setting table once (about 1-2 min on 2 shared cores).

Left as designed: ``drills export NAME OUT`` creates the missing folders of the ``OUT`` the user named
(and removes them again when the write fails).
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import re
import signal
import socket
import sqlite3
import stat

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


class Special:
    """A file that is not a regular file, made by :func:`_write`: ``Special("fifo")``, ``Special("socket")``
    or ``Special("link", target)`` (a symbolic link, e.g. to the character device /dev/zero)."""

    def __init__(self, kind: str, target: str = "") -> None:
        self.kind, self.target = kind, target

    def __repr__(self) -> str:
        return f"Special({self.kind!r}, {self.target!r})"


FIFO = Special("fifo")
SOCKET = Special("socket")
DEVICE = Special("link", "/dev/zero")  #: a character device that never ends
NULL_DEVICE = Special("link", "/dev/null")
STDOUT = Special("link", "/dev/stdout")
_SOCKETS: list = []  #: bound sockets stay open while the test runs


def _snapshot(root: str) -> dict[str, object]:
    """Every file (its bytes), folder (None), link (its target) and special file (its type) under
    ``root``, hidden ones included; nothing but regular files is ever opened."""
    out: dict[str, object] = {}
    for d, dirs, files in os.walk(root):
        for name in dirs + files:
            p = os.path.join(d, name)
            st = os.lstat(p)
            key = os.path.relpath(p, root)
            if stat.S_ISLNK(st.st_mode):
                out[key] = ("link", os.readlink(p))
            elif stat.S_ISDIR(st.st_mode):
                out[key] = None
            elif stat.S_ISREG(st.st_mode):
                with open(p, "rb") as fh:
                    out[key] = fh.read()
            else:
                out[key] = ("special", stat.S_IFMT(st.st_mode))
    return out


def _write(files: dict) -> None:
    for name, content in files.items():
        parent = os.path.dirname(name)
        if parent:
            os.makedirs(parent, exist_ok=True)
        if isinstance(content, Special):
            if content.kind == "fifo":
                os.mkfifo(name)
            elif content.kind == "socket":
                s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
                s.bind(name)
                _SOCKETS.append(s)
            elif content.kind == "hardlink":
                os.link(content.target, name)
            else:
                os.symlink(content.target, name)
            continue
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
    "duplicate-key": '{"samples": [], "samples": [' + _SAMPLE + "]}",
    "duplicate-key-in-a-sample": '{"samples": [{"time": 1, "time": 2, "ball": [0, 0, 1]}]}',
    "lone-surrogate": '{"samples": [], "shots": [{"name": "\\udfff"}]}',
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
    "duplicate-key": _cams(dict(_CAM, name="a", position=[0, -20, 5])).replace('"fx": 2000', '"fx": 2000, "fx": 1', 1),
    # two cameras of one name: which one a detection of "b" means would be a guess (it took the last)
    "duplicate-camera-name": _cams(dict(_CAM, name="b", position=[0, -20, 5])),
    "lone-surrogate": _cams(dict(_CAM, name="a\ud83d", position=[0, -20, 5])),
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
    "duplicate-column": "t,camera,u,v,u\n0,a,100,100,5\n0,b,200,100,5\n",
    "duplicate-column-in-another-case": "t,camera,u,v,V\n0,a,100,100,5\n0,b,200,100,5\n",
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
    "duplicate-column": _grid().replace("cd,cl", "cd,cl,cd", 1).replace(",0.2\n", ",0.2,0.9\n"),
    # a column twice in another case or with spaces: one duplicate rule for every reader (it took one)
    "duplicate-column-in-another-case": _grid().replace("cd,cl", "cd,CL,cl", 1).replace(",0.2\n", ",0.2,0.9\n"),
    "duplicate-column-with-spaces": _grid().replace("cd,cl", "cd,cl, cl ", 1).replace(",0.2\n", ",0.2,0.9\n"),
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
    "duplicate-column": "load_n,deformation_m,load_n\n10,0.001,20\n",
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
    "duplicate-column": "friction_angle_deg,friction_angle_deg\n30,40\n",
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
    "duplicate-key": DRILL_OK + "name: U\n",
    "duplicate-shot": DRILL_OK.replace("program:", "  a:\n    type: lob\n    target: [9.0, 1.0]\nprogram:"),
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
    "duplicate-key": '{"name": "T", "name": "U", "shots": {"a": {"type": "drive", "target": [9, 0]}}, '
    '"program": [{"shot": "a"}]}',
    # half a UTF-16 pair is no character: the database (UTF-8) refused it as "damaged file"
    "lone-surrogate": '{"name": "T\\ud800", "shots": {"a": {"type": "drive", "target": [9, 0]}}, '
    '"program": [{"shot": "a"}]}',
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
    "duplicate-key": "e = 0.7\ne = 0.8\nmu = 0.5\n",
}
SURFACE_JSON = {
    "invalid-json": '{"e": ',
    "top-list": "[1, 2]",
    "deep-nesting-1e5": DEEP_JSON,
    "5000-digit-integer": '{"e": ' + DIGITS + ', "mu": 0.5}',
    "unknown-key": '{"e": 0.7, "mu": 0.5, "colour": 1}',
    "duplicate-key": '{"e": 0.7, "e": 0.8, "mu": 0.5}',
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
    "duplicate-key": "[physics]\ncd = 0.5\ncd = 0.6\n",
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
    "duplicate-key": "impact_height = 2.5\nimpact_height = 2.6\n",
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
    "duplicate-key": '{"format": "tennislab.batch/2", "format": "tennislab.batch/2"}',
    "part-key-not-a-number": '{"format": "tennislab.batch/2", "parts": {"x": {"rows": 1, "bytes": 1, "blake2b": "'
    + "0" * 32
    + '"}}}',
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


#: every reader once more, its file a FIFO, a socket or a link to a character device (/dev/zero, which
#: never ends): refused in one line, without blocking on the FIFO or reading the device (issue 24, point 3)
_TINY_TABLE = ["--height", "1", "--speed-kmh", "90", "90", "--spin-rpm", "0", "0", "--spin-axis-deg", "0", "0"]
SPECIAL_READERS: dict[str, tuple[list[str], dict]] = {
    **{k: (v, {}) for k, v in MISSING_OR_DIRECTORY.items()},
    "detections": (["call", "--cameras", "cams.json", "--detections", "{p}"], {"cams.json": GOOD_CAMERAS}),
    "calibrate-serves": (["calibrate", "serves", "--serves", "{p}", "--quiet"], {}),
    "calibrate-sensitivity": (["calibrate", "sensitivity", "--serves", "{p}", "--quiet"], {}),
    "calibrate-surface-track": (["calibrate", "surface", "--track", "{p}", "--quiet"], {}),
    "calibrate-surface-point": (["calibrate", "surface", "--rally", "{p}", "--quiet"], {}),
    "aero-table-call": ([*STATE, "--aero", "table", "--aero-table", "{p}"], {}),
    "aero-table-calibrate": (
        ["calibrate", "validate", "--serves", "s.csv", "--aero-table", "{p}", "--quiet"],
        {"s.csv": CV_HEAD + CV_ROW},
    ),
    "drill-json": (["launcher", "drill", "--drill", "{p}.json"], {}),
    "surface-json": ([*FLY, "--bounces", "1", "--surface", "{p}.json"], {}),
    "config-before-command": (["--config", "{p}", *FLY], {}),
    "database-play": (["launcher", "play", "--db", "{p}", "--drill", "Lobs"], {}),
    "database-drills-list": (["launcher", "drills", "list", "--db", "{p}"], {}),
    "database-drills-export": (["launcher", "drills", "export", "--db", "{p}", "Lobs", "-"], {}),
    "database-drills-import": (["launcher", "drills", "import", "--db", "{p}", "lobs"], {}),
    "database-table": (["launcher", "table", "--db", "{p}", *_TINY_TABLE, "--no-progress"], {}),
    "calibrate-tracks-holdout": (
        ["calibrate", "tracks", "t.csv", "--holdout", "{p}", "--quiet"],
        {"t.csv": TRACK_HEAD + "".join(f"{i / 100},{-10 + i * 0.3},0,{2 - 0.01 * i}\n" for i in range(30))},
    ),
    "table-drill-file": (["launcher", "table", "--db", "n.sqlite", "--drill", "{p}.yaml", "--no-progress"], {}),
    "report-player-file": (["report", "--quiet", "--out", "r.html", "--player", "{p}.toml"], {}),
    "aero-table-serve": (
        ["serve", "--impact-angle", "3", "--face-angle", "8", "--aero", "table", "--aero-table", "{p}"],
        {},
    ),
    "aero-table-drill": (["launcher", "drill", "lobs", "--aero", "table", "--aero-table", "{p}"], {}),
    "aero-table-table": (
        [
            "launcher",
            "table",
            "--db",
            "n.sqlite",
            *_TINY_TABLE,
            "--no-progress",
            "--aero",
            "table",
            "--aero-table",
            "{p}",
        ],
        {},
    ),
    "config-app": (["app", "--config", "{p}", "--port", "0"], {}),
}
SPECIALS = {"fifo": FIFO, "socket": SOCKET, "device": DEVICE}
for _key, (_argv, _extra) in SPECIAL_READERS.items():
    for _kind, _special in SPECIALS.items():
        _names = {a.format(p="sp") for a in _argv if "{p}" in a}
        CORPUS.append(
            pytest.param(
                [a.format(p="sp") for a in _argv], {**_extra, **dict.fromkeys(_names, _special)}, id=f"{_key}-{_kind}"
            )
        )
for _kind, _special in SPECIALS.items():
    CORPUS += [
        pytest.param(FLY, {"tennislab.toml": _special}, id=f"config-in-working-folder-{_kind}"),
        pytest.param(
            ["call", "--rally", "pts"],
            {"pts/a.json": '{"samples": []}', "pts/b.json": _special},
            id=f"point-dir-{_kind}",
        ),
        pytest.param(
            [*SERVE_WINDOW, "--out-dir", "out"], {"out/manifest.json": _special}, id=f"batch-manifest-{_kind}"
        ),
    ]


@pytest.fixture(autouse=True)
def _never_hangs():
    """A case that blocks (a FIFO opened for reading, a device read to its end) fails after 60 s instead
    of hanging the suite."""

    def hung(signum, frame):
        raise AssertionError("the command blocked (a FIFO or a device was opened or read)")

    old = signal.signal(signal.SIGALRM, hung)
    signal.alarm(60)
    yield
    signal.alarm(0)
    signal.signal(signal.SIGALRM, old)


@pytest.mark.parametrize("argv,files", CORPUS)
def test_malformed_input_is_refused_in_one_line(cwd, capsys, request, argv, files):
    err = assert_refused(capsys, argv, files)
    case = request.node.callspec.id
    if "duplicate" in case and "duplicate-point" not in case:  # one rule for every reader: a repeated key is refused
        assert "duplicate" in err or "a key given twice" in err, err
    if case.endswith(("-fifo", "-socket", "-device")):  # refused as what it is, not read
        assert any(w in err for w in ("FIFO", "socket", "character device")), err
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


# ------------------------------------------------ crafted databases: a file from another coach (issue 24, 1, 2, 10)
_ENDLESS = "WITH RECURSIVE r(n) AS (SELECT 1 UNION ALL SELECT n + 1 FROM r) SELECT count(*) FROM r"
_DEEP = "[" * 100_000 + "]" * 100_000
#: SQL that turns a real database (hits of a small fill, the shipped drill 'lobs') into a hostile one
CRAFTED_SCHEMA = {
    # passes the identity and quick_check tests; reading drills would never return
    "drills-a-recursive-view": "DROP TABLE drills; CREATE VIEW drills AS WITH RECURSIVE r(id) AS (SELECT 1 UNION ALL "
    "SELECT id + 1 FROM r) SELECT id, 'x' AS name, 'x.yaml' AS filename, NULL AS format_version, 1 AS revision, "
    "'' AS sha256, x'' AS source, '[]' AS sequence_json, '' AS imported_utc FROM r",
    "trigger-deletes-hits": "CREATE TRIGGER t AFTER INSERT ON drills BEGIN DELETE FROM hits; END",
    "trigger-endless-cte": f"CREATE TRIGGER t AFTER INSERT ON fills BEGIN SELECT ({_ENDLESS}); END; "
    f"CREATE TRIGGER u AFTER UPDATE ON drills BEGIN SELECT ({_ENDLESS}); END",
    "an-extra-view": "CREATE VIEW v AS SELECT 1",
    "an-extra-index": "CREATE INDEX evil ON hits (land_x)",
    "an-extra-virtual-table": "CREATE VIRTUAL TABLE evil USING rtree(id, a, b)",
    "an-extra-table": "CREATE TABLE notes (x)",
    "a-changed-table": "ALTER TABLE hits ADD COLUMN evil TEXT",
    "a-changed-index": "DROP INDEX hits_cell; CREATE INDEX hits_cell ON hits (land_x)",
}
#: stored values out of their ranges: {variant: (SQL, commands that read them and must refuse)}
_INFO = ("info", "info-check", "info-json")
_DRILLS = ("drills-list", "drills-export", "drill", "play", "drills-import", *_INFO)
CRAFTED_VALUES = {
    "deep-json-machine-spec": (f"UPDATE machine SET spec_json = '{_DEEP}'", ("lookup",)),
    "deep-json-machine-config": (f"UPDATE machine SET config_json = '{_DEEP}'", (*_INFO, "lookup", "table")),
    "duplicate-key-machine-config": (
        """UPDATE machine SET config_json = '{"machine": {}, "machine": {}, "physics": {}}'""",
        (*_INFO, "lookup", "table"),
    ),
    "deep-json-drill-sequence": (f"UPDATE drills SET sequence_json = '{_DEEP}'", _DRILLS),
    "deep-json-fill-grid": (f"UPDATE fills SET grid_json = '{_DEEP}'", (*_INFO, "lookup")),
    "drill-sequence-not-names": ("UPDATE drills SET sequence_json = '[1, 2]'", _DRILLS),
    "drill-revision-a-text": ("UPDATE drills SET revision = 'x'", _DRILLS),
    "drill-source-not-its-sha256": ("UPDATE drills SET source = x'00'", ("drills-export", "drill", "play")),
    "hits-net-clearance-minus-5": ("UPDATE hits SET net_clearance_m = -5", ("lookup",)),
    "hits-flight-time-minus-1": ("UPDATE hits SET flight_time_s = -1", ("lookup",)),
    "hits-apex-1e6-m": ("UPDATE hits SET apex_z_m = 1e6", ("lookup",)),
    "hits-bounce-speed-minus-1": ("UPDATE hits SET bounce_speed_ms = -1", ("lookup",)),
    # one hit no lookup reads (the query passes it by): `info --check` scans them all
    "hits-one-landing-a-text": (
        "UPDATE hits SET land_x = 'nan' WHERE id IN (SELECT id FROM hits LIMIT 1)",
        ("info-check",),
    ),
    "hits-one-branch-7": ("UPDATE hits SET branch = 7 WHERE id IN (SELECT max(id) FROM hits)", ("info-check",)),
}
DB_COMMANDS_W = {**DB_COMMANDS, "table": ["launcher", "table", "--db", "x.sqlite", *_TINY_TABLE, "--no-progress"]}


def _craft(base: bytes, sql: str, where) -> bytes:
    path = str(where / f"c{len(os.listdir(where))}.sqlite")
    with open(path, "wb") as fh:
        fh.write(base)
    con = sqlite3.connect(path, isolation_level=None)
    con.executescript(sql)
    con.close()  # the last connection: the log is folded into the file and removed
    with open(path, "rb") as fh:
        return fh.read()


@pytest.fixture(scope="module")
def crafted_db(tmp_path_factory) -> dict[str, bytes]:
    """The crafted databases: a real one (a small fill, 'lobs' imported) changed by each variant's SQL."""
    d = tmp_path_factory.mktemp("crafted")
    real = str(d / "hits.sqlite")
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        assert main(["launcher", "table", "--db", real, *_TINY_TABLE, "--no-progress"]) == 0
        assert main(["launcher", "drills", "import", "--db", real, "lobs"]) == 0
    base = _craft(open(real, "rb").read(), "", d)
    out = {"real": base}
    out.update({k: _craft(base, sql, d) for k, sql in CRAFTED_SCHEMA.items()})
    out.update({k: _craft(base, sql, d) for k, (sql, _) in CRAFTED_VALUES.items()})
    return out


@pytest.mark.parametrize("cmd", sorted(DB_COMMANDS_W))
@pytest.mark.parametrize("variant", sorted(CRAFTED_SCHEMA))
def test_database_with_objects_we_did_not_create_is_refused(cwd, capsys, crafted_db, variant, cmd):
    """Views, triggers, virtual tables, indexes and tables tennislab did not create, or changed
    definitions: every reader and writer refuses the file at once (nothing runs, nothing is written)."""
    err = assert_refused(capsys, DB_COMMANDS_W[cmd], {"x.sqlite": crafted_db[variant]})
    assert "as tennislab writes it" in err


def _clean_run(capsys, argv, files) -> tuple[int, str, str]:
    _write(files)
    capsys.readouterr()
    rc = _main(argv)
    out, err = capsys.readouterr()
    assert "Traceback" not in out + err and rc in (0, 2), (argv, rc, err)
    assert rc == 0 or len(err.splitlines()) == 1, (argv, err)
    return rc, out, err


@pytest.mark.parametrize("cmd", sorted(DB_COMMANDS_W))
@pytest.mark.parametrize("variant", sorted(CRAFTED_VALUES))
def test_stored_values_are_validated_on_read(cwd, capsys, crafted_db, variant, cmd):
    """Stored JSON (10^5 deep, a key twice), drills and hits out of their ranges: a command that reads
    them refuses the file in one line; the others answer as usual (never a traceback)."""
    sql, readers = CRAFTED_VALUES[variant]
    if cmd in readers:
        err = assert_refused(capsys, DB_COMMANDS_W[cmd], {"x.sqlite": crafted_db[variant]})
        assert "damaged" in err or "not a tennislab" in err, err
    elif cmd != "table":  # a fill that is not affected would fly for a second: not needed here
        _clean_run(capsys, DB_COMMANDS_W[cmd], {"x.sqlite": crafted_db[variant]})


def test_the_crafted_databases_start_from_a_working_one(cwd, capsys, crafted_db):
    """The base of the crafted files answers every reader (so each refusal above is the variant's)."""
    for cmd in ("info", "info-check", "lookup", "drills-list", "drills-export", "drill"):
        rc, out, err = _clean_run(capsys, DB_COMMANDS[cmd], {"x.sqlite": crafted_db["real"]})
        assert rc == 0, (cmd, err)


def test_a_hostile_trigger_never_runs(cwd, capsys, crafted_db):
    """Issue 24 point 1: `after insert on drills begin delete from hits` made `drills import` delete every
    hit and exit 0; now the import is refused and the hits stay."""
    _write({"x.sqlite": crafted_db["trigger-deletes-hits"]})

    def hits() -> int:
        con = sqlite3.connect("file:x.sqlite?mode=ro&immutable=1", uri=True)
        try:
            return con.execute("SELECT count(*) FROM hits").fetchone()[0]
        finally:
            con.close()

    before = hits()
    assert before > 100
    assert _main(["launcher", "drills", "import", "--db", "x.sqlite", "lobs"]) == 2
    assert sorted(os.listdir(".")) == ["x.sqlite"]  # no -wal, no -shm
    assert hits() == before


@pytest.mark.parametrize("suffix", ["-wal", "-shm", "-journal"])
def test_a_file_beside_the_database_that_is_not_a_file_is_refused(cwd, capsys, crafted_db, suffix):
    """SQLite opens the write-ahead log, the shared-memory index and a hot rollback journal itself: a FIFO
    there made `drills import` block for ever (a hot journal is read), a device or a socket gave "disk I/O
    error" after `table` had printed its plan.  Each is refused first, in one line, by every command."""
    for kind, special in SPECIALS.items():
        d = f"w-{kind}"
        os.mkdir(d)
        os.chdir(d)
        try:
            for cmd in ("info", "lookup", "drills-list", "drills-import", "table"):
                err = assert_refused(
                    capsys, DB_COMMANDS_W[cmd], {"x.sqlite": crafted_db["real"], "x.sqlite" + suffix: special}
                )
                assert "x.sqlite" + suffix in err, err
                os.unlink("x.sqlite")
                os.unlink("x.sqlite" + suffix)
            # a new database too: SQLite would write its journal into the FIFO
            err = assert_refused(capsys, DB_COMMANDS_W["drills-import"], {"x.sqlite" + suffix: special})
            os.unlink("x.sqlite" + suffix)
        finally:
            os.chdir("..")


def test_drill_names_from_a_database_are_printed_escaped(cwd, capsys, crafted_db, tmp_path):
    """Issue 24 point 11: text from a file (here a drill's name in a database) cannot drive the terminal."""
    evil = _craft(crafted_db["real"], "UPDATE drills SET name = char(27) || '[2J' || char(10) || 'Lobs'", tmp_path)
    rc, out, err = _clean_run(capsys, ["launcher", "drills", "list", "--db", "x.sqlite"], {"x.sqlite": evil})
    assert rc == 0 and "\x1b" not in out  # no raw escape character reaches the terminal
    assert r"\x1b[2J\nLobs" in out  # the name is shown, escaped, on one line


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
    # special files are never replaced (issue 24, point 9): the output would vanish into a pipe or a
    # device, or the device node would be replaced by a plain file
    "a-fifo": ("ff{ext}", {"ff{ext}": FIFO}),
    "a-socket": ("sk{ext}", {"sk{ext}": SOCKET}),
    "a-link-to-a-device": ("dev{ext}", {"dev{ext}": NULL_DEVICE}),
    "a-link-to-stdout": ("so{ext}", {"so{ext}": STDOUT}),
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


def _at(extra: dict, ext: str) -> dict:
    return {k.format(ext=ext): v for k, v in extra.items()}


OUTPUT_CASES = [
    pytest.param(argv, flag, place.format(ext=ext), {**files, **_at(extra, ext)}, id=f"{name}{flag}-{bad}")
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
    assert_refused(capsys, argv, {"real.sqlite": launcher_db["real"], **_at(extra, ".yaml")})


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


def test_every_read_has_a_step_budget(cwd, capsys, crafted_db, monkeypatch):
    """Behind the schema check: were a hostile view to get through, the read stops at its step budget
    (one line) instead of running for ever; and every connection has trusted_schema off."""
    import tennislab.launcher._dbguard as guard

    monkeypatch.setattr(guard, "check_schema", lambda *a, **k: None)
    monkeypatch.setattr(guard, "READ_STEP_BUDGET", 2_000_000)
    err = assert_refused(capsys, DB_COMMANDS["drills-list"], {"x.sqlite": crafted_db["drills-a-recursive-view"]})
    assert "ran past its budget of 2,000,000 SQLite steps" in err
    conn = guard.connect(":memory:")
    assert conn.execute("PRAGMA trusted_schema").fetchone()[0] == 0
    with pytest.raises(sqlite3.OperationalError, match="interrupted"):
        conn.execute(_ENDLESS).fetchone()
    guard.reset_budget(conn)
    assert conn.execute("SELECT 1").fetchone() == (1,)  # the next operation has its whole budget again
    conn.close()


# ---------------------------------------------------------------- an output that is also an input (issue 24, 7)

SAME_FILE = [
    pytest.param(
        ["calibrate", "validate", "--serves", "s.csv", "--csv", "s.csv", "--quiet"], _VALID_SERVES, id="validate-csv"
    ),
    pytest.param(
        ["calibrate", "validate", "--serves", "s.csv", "--csv", "./s.csv", "--quiet"],
        _VALID_SERVES,
        id="validate-csv-dot",
    ),
    pytest.param(
        ["calibrate", "serves", "--serves", "s.csv", "--out-table", "s.csv", "--quiet"],
        _VALID_SERVES,
        id="serves-out-table",
    ),
    pytest.param(["calibrate", "tracks", "t.csv", "--csv", "t.csv", "--quiet"], _VALID_TRACK, id="tracks-csv"),
    pytest.param(
        ["calibrate", "tracks", "t.csv", "--out-table", "t.csv", "--quiet"], _VALID_TRACK, id="tracks-out-table"
    ),
    pytest.param(
        ["calibrate", "surface", "--track", "t.csv", "--csv", "t.csv", "--quiet"], _VALID_TRACK, id="surface-csv"
    ),
    pytest.param(["call", "--rally", "p.csv", "--csv", "p.csv"], {"p.csv": '{"samples": []}'}, id="call-rally-csv"),
    pytest.param(["launcher", "drill", "d.csv", "--csv", "d.csv"], {"d.csv": DRILL_OK}, id="drill-csv"),
    pytest.param(
        [*SERVE_WINDOW, "--csv", "c.csv", "--config", "c.csv"], {"c.csv": "[physics]\ncd = 0.55\n"}, id="config-csv"
    ),
    pytest.param(
        ["calibrate", "validate", "--serves", "s.csv", "--csv", "h.csv", "--quiet"],
        {**_VALID_SERVES, "h.csv": Special("hardlink", "s.csv")},
        id="validate-hard-link",
    ),
    pytest.param(
        ["calibrate", "validate", "--serves", "s.csv", "--csv", "l.csv", "--quiet"],
        {**_VALID_SERVES, "l.csv": Special("link", "s.csv")},
        id="validate-symbolic-link",
    ),
]


@pytest.mark.parametrize("argv,files", SAME_FILE)
def test_an_output_that_is_an_input_is_refused_before_the_work(cwd, capsys, argv, files):
    err = assert_refused(capsys, argv, files)
    assert "is also an input of this command" in err


TWO_OUTPUTS = [
    pytest.param(
        ["calibrate", "tracks", "t.csv", "--csv", "o.csv", "--out-table", "./o.csv", "--quiet"],
        _VALID_TRACK,
        id="tracks",
    ),
    pytest.param(
        ["calibrate", "serves", "--serves", "s.csv", "--csv", "o.csv", "--out-table", "o.csv", "--quiet"],
        _VALID_SERVES,
        id="serves",
    ),
    pytest.param([*SERVE_WINDOW, "--csv", "o.csv", "--out-dir", "o.csv"], {}, id="serve-window-csv-and-out-dir"),
    pytest.param(
        ["calibrate", "tracks", "t.csv", "--csv", "o.csv", "--out-table", "h.csv", "--quiet"],
        {**_VALID_TRACK, "o.csv": "old", "h.csv": Special("hardlink", "o.csv")},
        id="tracks-hard-link",
    ),
]


@pytest.mark.parametrize("argv,files", TWO_OUTPUTS)
def test_two_outputs_in_one_file_are_refused_before_the_work(cwd, capsys, argv, files):
    """`calibrate tracks --csv o.csv --out-table o.csv` wrote the table over the rows, exit 0."""
    err = assert_refused(capsys, argv, files)
    assert "is also the output of" in err, err


def test_an_output_read_by_the_command_is_refused_when_it_would_be_written(cwd, capsys, launcher_db):
    """Outputs named at run time, and inputs read without a flag, are checked when written: the database a
    drill is exported from, and ./tennislab.toml (nothing is written, one line)."""
    err = assert_refused(
        capsys,
        ["launcher", "drills", "export", "--db", "x.sqlite", "Lobs", "x.sqlite"],
        {"x.sqlite": launcher_db["real"]},
    )
    assert "is also an input of this command" in err
    err = assert_refused(
        capsys,
        ["calibrate", "surface", "--track", "t.csv", "--out-surface", "tennislab.toml", "--quiet"],
        {**_VALID_TRACK, "tennislab.toml": "[physics]\ncd = 0.55\n"},
    )
    assert "is also an input of this command" in err


# ---------------------------------------------------------------- numbers at the edge of the floats (issue 24, 4, 5)
def _float_flags():
    """(command words, flag, nargs, argparse action) of every float flag of every command."""
    import argparse

    from tennislab.cli import build_parser

    out = []

    def walk(p, words):
        for a in p._actions:
            if isinstance(a, argparse._SubParsersAction):
                for name, sub in a.choices.items():
                    walk(sub, [*words, name])
            elif a.option_strings and (a.type is float or getattr(a.type, "__name__", "") == "float"):
                out.append((tuple(words), a.option_strings[-1], a.nargs if isinstance(a.nargs, int) else 1, a))

    walk(build_parser(), [])
    return out


FLOAT_FLAGS = _float_flags()
BAD_FLOATS = ["1e-320", "-4e-310", "5e-324", "nan", "inf", "-inf", "1e999"]


def test_every_float_flag_takes_only_finite_normal_numbers(cwd, capsys):
    """A subnormal (1e-320: dividing by it gives inf), NaN or an infinity given to any float flag of any
    command is refused when the command line is parsed (every float flag's type checks it); through the
    CLI it is one line naming the flag, before any work (a spread of flags over every command)."""
    import argparse

    assert len(FLOAT_FLAGS) > 100
    for *_, action in FLOAT_FLAGS:
        for v in BAD_FLOATS:
            with pytest.raises(argparse.ArgumentTypeError):
                action.type(v)
        assert action.type("1e-300") == 1e-300 and action.type("0") == 0.0
    per_command: dict = {}
    for words, flag, n, _ in FLOAT_FLAGS:
        per_command.setdefault(words, []).append((flag, n))
    for words, flags in per_command.items():
        for (flag, n), v in zip(flags[::4], BAD_FLOATS * 10):
            err = assert_refused(capsys, [*words, flag, *([v] * n)])
            assert flag in err, (words, flag, err)


@pytest.mark.parametrize(
    "argv",
    [
        ["impact", "--racket-speed", "40", "--impact-angle", "10", "--dt", "1e-12"],
        ["impact", "--racket-speed", "40", "--impact-angle", "10", "--integrator", "euler", "--dt", "5e-8"],
        ["serve", "--impact-angle", "3", "--face-angle", "8", "--dt", "1e-12"],
        ["serve-mc", "--impact-angle", "3", "--face-angle", "8", "--n", "100", "--dt", "1e-300"],
        [*SERVE_WINDOW, "--dt", "1e-9"],
        ["serve", "--impact-angle", "3", "--face-angle", "8", "--dt", "0.01"],
    ],
    ids=["impact", "impact-euler", "serve", "serve-mc", "serve-window", "serve-dt-too-large"],
)
def test_an_impact_step_that_would_not_end_the_contact_is_refused(cwd, capsys, argv):
    """serve and serve-mc share impact's bounds: a fixed step of at least 1e-7 s (a contact in at most
    5e4 steps), not a two-minute run that returns a ball at 2e-5 m/s."""
    err = assert_refused(capsys, argv)
    assert "--dt" in err


def test_every_impact_checks_that_its_contact_ended(monkeypatch):
    """One contact-ended check for every impact (impact, serve, serve-mc, serve-window): a kernel that
    ran out of steps is refused, never answered."""
    import tennislab.core.impact as imp

    def unfinished(vn, vt, P, steps, dt, method, out):
        out[:] = 0.0
        out[:, imp.OUT_COLUMNS.index("status")] = 1.0

    monkeypatch.setattr(imp, "_impact_serial_kernel", unfinished)
    monkeypatch.setattr(imp, "_impact_batch_kernel", unfinished)
    with pytest.raises(InputError, match="contact did not end"):
        imp.impact_batch([40.0, 41.0], [0.1, 0.2])
    with pytest.raises(InputError, match="contact did not end"):
        imp.impact_batch(40.0, 0.1, parallel=False)


def test_answers_that_are_not_finite_are_refused(cwd, capsys):
    """launcher power answered "inf rpm ... inf s" for a roller of 1e-320 kg (now refused as a subnormal);
    a normal but tiny mass whose inertia underflows is refused as an answer that is not finite."""
    err = assert_refused(capsys, ["launcher", "power", "--speed-kmh", "100", "--roller-mass", "2.3e-308"])
    assert "not finite" in err or "computed value is inf" in err


# ---------------------------------------------------------------- file names in any encoding (issue 24, 8, 13)
NOT_UTF8_NAME = os.fsdecode(b"\xff\xfe-x")  #: a file name that is not UTF-8 (as Python gets it from argv)
NAMED_WRITERS = [
    pytest.param(["calibrate", "tracks", "t.csv", "--quiet", "--csv"], ".csv", _VALID_TRACK, id="calibrate-tracks-csv"),
    pytest.param(["call", "--rally", "p.json", "--csv"], ".csv", {"p.json": '{"samples": []}'}, id="call-rally-csv"),
    pytest.param(["launcher", "drills", "import", "lobs", "--db"], ".sqlite", {}, id="drills-import-db"),
    pytest.param(["launcher", "table", *_TINY_TABLE, "--no-progress", "--db"], ".sqlite", {}, id="launcher-table-db"),
]


@pytest.mark.parametrize("argv,ext,files", NAMED_WRITERS)
def test_an_output_name_that_is_not_utf8_is_written_and_shown_escaped(cwd, capsys, argv, ext, files):
    """The file is written under its own bytes, what is printed names it escaped (``\\xff``) and encodes as
    UTF-8; a database of such a name is read back (issue 24 point 13: `launcher table --db $'\\xff.sqlite'`
    called its own file damaged)."""
    _write(files)
    name = NOT_UTF8_NAME + ext
    capsys.readouterr()
    rc = _main([*argv, name])
    out, err = capsys.readouterr()
    assert rc == 0, err
    (out + err).encode("utf-8")  # strict: no lone surrogate reaches the terminal
    assert os.path.isfile(os.fsencode(name))
    assert not [n for n in os.listdir(b".") if n.startswith(b".tmp-") or n.endswith((b"-wal", b"-shm"))]
    if ext == ".sqlite":
        rc = _main(["launcher", "info", "--db", name])
        out, err = capsys.readouterr()
        assert rc == 0, err
        assert "\\xff\\xfe-x.sqlite: tennislab launcher database" in out
        (out + err).encode("utf-8")


@pytest.mark.parametrize(
    "argv",
    [
        ["call", "--track", NOT_UTF8_NAME + ".csv"],
        ["launcher", "info", "--db", NOT_UTF8_NAME + ".sqlite"],
        [*FLY, "--plot", "nodir/" + NOT_UTF8_NAME + ".png"],
        ["call", "--rally", "p.json", "--csv", "nodir/" + NOT_UTF8_NAME + ".csv"],
    ],
    ids=["missing-input", "missing-database", "plot-in-a-missing-folder", "call-csv-in-a-missing-folder"],
)
def test_errors_naming_a_file_that_is_not_utf8_are_one_line(cwd, capsys, argv):
    err = assert_refused(capsys, argv, {"p.json": '{"samples": []}'})
    assert "\\xff\\xfe-x" in err
    err.encode("utf-8")


# ---------------------------------------------------------------- OS errors name the file (issue 24, 16)
def test_no_space_left_names_the_file_and_leaves_nothing(cwd, capsys, monkeypatch):
    """An OS error while writing (no space left) is one line naming the file; the temporary file and any
    folder made for the output are removed (a failed `drills export` left an empty folder)."""
    import errno as _errno

    real_fsync = os.fsync

    def full(fd):
        raise OSError(_errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(os, "fsync", full)
    err = assert_refused(capsys, [*SERVE_WINDOW, "--csv", "w.csv"])
    assert "w.csv" in err and "No space left on device" in err
    monkeypatch.setattr(os, "fsync", real_fsync)
    with contextlib.redirect_stdout(io.StringIO()):
        assert main(["launcher", "drills", "import", "--db", "d.sqlite", "lobs"]) == 0
    monkeypatch.setattr(os, "fsync", full)
    err = assert_refused(capsys, ["launcher", "drills", "export", "--db", "d.sqlite", "Lobs", "new/deeper/lobs.yaml"])
    assert "new/deeper/lobs.yaml" in err and "No space left on device" in err
    # a batch store's manifest said only "No space left on device"; its new folder is removed again
    err = assert_refused(capsys, [*SERVE_WINDOW, "--out-dir", "out"])
    assert "out/manifest.json: cannot be written (No space left on device)" in err, err
    monkeypatch.setattr(os, "fsync", real_fsync)
    # SQLite's own "database or disk is full" while importing into a new file: no database left behind
    import tennislab.launcher._dbdrills as _dd

    def disk_full(*a, **k):
        raise sqlite3.OperationalError("database or disk is full")

    monkeypatch.setattr(_dd, "import_drill", disk_full)
    err = assert_refused(capsys, ["launcher", "drills", "import", "--db", "e.sqlite", "lobs"])
    assert "e.sqlite" in err and "disk is full" in err and not os.path.lexists("e.sqlite")


def test_shot_names_from_a_drill_file_are_printed_escaped(cwd, capsys):
    """Issue 24 point 11: `launcher drill` printed a drill file's shot and drill names raw (a newline broke
    the line, terminal escape codes reached the terminal)."""
    evil = DRILL_OK.replace("name: T", 'name: "T\\e[2J"').replace("  a:", '  "a\\e[31mred\\nline":')
    evil = evil.replace("- shot: a", '- shot: "a\\e[31mred\\nline"')
    rc, out, err = _clean_run(capsys, ["launcher", "drill", "d.yaml"], {"d.yaml": evil})
    assert rc == 0, err
    assert "\x1b" not in out
    assert r"a\x1b[31mred\nline:" in out and r"drill 'T\x1b[2J'" in out


def test_library_parameters_read_a_subnormal_as_zero():
    """In the library a subnormal is read as 0: refused where the parameter must be positive (a division
    follows), taken as 0 where 0 is allowed."""
    from tennislab.core.impact import impact_single
    from tennislab.errors import check_finite, check_range, check_vector
    from tennislab.launcher.power import power_report

    assert check_finite("x", 5e-324) == 0.0 and check_vector("w", (0.0, -5e-324, 1.0)) == (0.0, -0.0, 1.0)
    with pytest.raises(InputError, match=r"^m: 9.99989e-321 kg \(a subnormal number, read as 0\) is outside"):
        check_range("m", 1e-320, 0.0, 10.0, "kg", lo_open=True)
    with pytest.raises(InputError, match="^speed: "):
        impact_single(1e-320, 0.1)
    with pytest.raises(InputError, match="^roller_mass: "):
        power_report(20.0, roller_mass=1e-320)


def test_a_drill_exported_under_a_name_that_is_not_utf8(cwd, capsys, launcher_db):
    _write({"d.sqlite": launcher_db["real"]})
    name = NOT_UTF8_NAME + ".yaml"
    rc = _main(["launcher", "drills", "export", "--db", "d.sqlite", "Lobs", name])
    out, err = capsys.readouterr()
    assert rc == 0, err
    assert "\\xff\\xfe-x.yaml" in out
    out.encode("utf-8")
    from tennislab.launcher.drill_schema import shipped_path

    with open(os.fsencode(name), "rb") as fh, open(shipped_path("lobs"), "rb") as gh:
        assert fh.read() == gh.read()  # byte for byte, under its own name


_NOT_A_NUMBER = re.compile(r"(?<![\w.])[-+]?(nan|inf)(?![\w])", re.I)


@pytest.mark.parametrize(
    "argv",
    [
        ["serve", "--impact-angle", "3", "--face-angle", "8", "--racket-speed", "1"],
        ["serve", "--impact-angle", "3", "--face-angle", "8", "--racket-speed", "1e-300"],
        ["serve", "--impact-angle", "3", "--face-angle", "8", "--racket-mass", "1e-300"],
        ["impact", "--racket-speed", "1e-300", "--impact-angle", "10"],
        ["launcher", "power", "--speed-kmh", "100", "--roller-mass", "1e-300"],
        ["launcher", "power", "--speed-kmh", "100", "--motor-power", "1e-300"],
        ["launcher", "power", "--speed-kmh", "100", "--throw-time", "1e300"],
    ],
    ids=["serve-1-m-s", "serve-1e-300-m-s", "serve-racket-1e-300", "impact", "power-mass", "power-motor", "power-t"],
)
def test_answers_at_the_edge_are_numbers_or_refused(cwd, capsys, argv):
    """Normal numbers at the edge of the floats: a one-line refusal, or an answer whose every number is
    finite (a serve too slow to reach the net printed "ball centre nan m")."""
    rc, out, err = _clean_run(capsys, argv, {})
    if rc == 0:
        assert not _NOT_A_NUMBER.search(out), out


# ------------------------------------------- a real process: strict stdout, a folder it may not write
_RUNNER = """
import json, sys
from tennislab.cli import main
out = []
for argv in json.loads(sys.argv[1]):
    try:
        rc = main(argv)
    except SystemExit as exc:
        rc = exc.code
    sys.stdout.flush(); sys.stderr.flush()
    sys.stderr.write("\\x00END\\x00\\n"); sys.stderr.flush()
    out.append(rc)
sys.__stdout__.write("\\x00RC" + json.dumps(out) + "\\n")
"""


def _in_a_process(argvs: list[list[str]], cwd=".", *, unprivileged: bool = False) -> list[tuple[int, str]]:
    """Run the CLI commands ``argvs`` in one real Python process with a strict UTF-8 stdout and stderr
    (``PYTHONIOENCODING=utf-8:strict``, ``LC_ALL=C``); ``unprivileged``: as the user without the power to
    write where the folder's mode forbids it (root runs it with the capabilities that override file
    permissions dropped, via ``setpriv``).  Returns (exit code, stderr) per command."""
    import shutil
    import subprocess
    import sys

    signal.alarm(360)  # one process for many commands: more than a single case's 60 s (its own timeout: 300 s)
    prefix: list[str] = []
    if unprivileged and os.geteuid() == 0:
        if shutil.which("setpriv") is None:
            pytest.skip("root, and no setpriv to drop the capability to write anywhere")
        prefix = ["setpriv", "--bounding-set=-dac_override,-dac_read_search,-fowner"]
    import tennislab

    env = dict(os.environ, PYTHONIOENCODING="utf-8:strict", LC_ALL="C", LANG="C")
    env["PYTHONPATH"] = os.path.dirname(os.path.dirname(tennislab.__file__))
    p = subprocess.run(
        [*prefix, sys.executable, "-c", _RUNNER, json.dumps(argvs)],
        capture_output=True,
        env=env,
        cwd=cwd,
        timeout=300,
    )
    assert b"Traceback" not in p.stdout + p.stderr, p.stderr.decode("utf-8", "backslashreplace")[-3000:]
    p.stdout.decode("utf-8")  # strict: nothing that is not UTF-8 reached the terminal
    p.stderr.decode("utf-8")
    rcs = json.loads(p.stdout.rsplit(b"\x00RC", 1)[1])
    errs = p.stderr.decode("utf-8").split("\x00END\x00\n")[:-1]
    return list(zip(rcs, errs, strict=True))


#: (argv, input files) writing an output into the working folder, which the user may not write
_RO_WRITERS = [
    (["call", "--rally", "p.json", "--csv", "o.csv"], {"p.json": '{"samples": []}'}),
    (["call", "--rally", "p.json", "--plot", "o.png"], {"p.json": '{"samples": []}'}),
    (["call", "--track", "t.csv", "--plot", "o.png"], _VALID_TRACK),
    ([*FLY, "--plot", "o.png"], {}),
    ([*SERVE_WINDOW, "--csv", "o.csv"], {}),
    ([*SERVE_WINDOW, "--out-dir", "out"], {}),
    (["calibrate", "validate", "--serves", "s.csv", "--csv", "o.csv", "--quiet"], _VALID_SERVES),
    (["calibrate", "tracks", "t.csv", "--out-table", "o.csv", "--quiet"], _VALID_TRACK),
    (["launcher", "drill", "lobs", "--csv", "o.csv"], {}),
    (["launcher", "drills", "import", "lobs", "--db", "o.sqlite"], {}),
    (["launcher", "table", *_TINY_TABLE, "--no-progress", "--db", "o.sqlite"], {}),
    (["report", "--quiet", "--out", "o.html"], {}),
]


@pytest.mark.slow
def test_a_folder_that_may_not_be_written_is_refused_before_the_work(tmp_path):
    """Issue 24 point 8: `call` in a read-only folder did all the work and then failed naming an internal
    `.tmp-....csv`.  Every writer checks that its folder is writable before the work: one line naming
    the output, nothing written (run as a user the folder's mode stops; root without its override)."""
    work = tmp_path / "ro"
    work.mkdir()
    for _, files in _RO_WRITERS:
        for name, content in files.items():
            (work / name).write_text(content)
    before = _snapshot(str(work))
    os.chmod(work, 0o555)
    try:
        argvs = [argv for argv, _ in _RO_WRITERS]
        results = _in_a_process(argvs, work, unprivileged=True)
    finally:
        os.chmod(work, 0o755)
    for argv, (rc, err) in zip(argvs, results, strict=True):
        assert rc == 2 and len(err.splitlines()) == 1, (argv, rc, err)
        assert "not writable" in err and ".tmp-" not in err, (argv, err)
    assert _snapshot(str(work)) == before


@pytest.mark.slow
def test_names_that_are_not_utf8_on_a_strict_utf8_terminal(cwd):
    """Issue 24 point 13: with a strict UTF-8 stdout (``PYTHONIOENCODING=utf-8:strict``, ``LC_ALL=C``) about
    ten commands wrote their file and then crashed printing its name.  In a real process: every writer
    writes its file under its own bytes and prints the name escaped; a database of such a name is read
    back; an input of such a name is read; a missing one is one line."""
    _write({**_VALID_TRACK, **_VALID_SERVES, "p.json": '{"samples": []}'})
    bad = NOT_UTF8_NAME
    _write({bad + "-in.csv": _VALID_SERVES["s.csv"], bad + "-d.yaml": DRILL_OK})
    argvs = [
        ["call", "--rally", "p.json", "--csv", bad + "-1.csv"],
        [*FLY, "--plot", bad + "-2.png"],
        [*SERVE_WINDOW, "--csv", bad + "-3.csv", "--plot", bad + "-3.png", "--out-dir", bad + "-out"],
        ["calibrate", "validate", "--serves", "s.csv", "--csv", bad + "-4.csv", "--quiet"],
        ["calibrate", "tracks", "t.csv", "--out-table", bad + "-5.csv", "--quiet"],
        ["calibrate", "tracks", "t.csv", "--out-table", "5.csv", "--out-config", bad + "-5.toml", "--quiet"],
        ["launcher", "drill", "lobs", "--csv", bad + "-6.csv", "--plot", bad + "-6.png"],
        ["launcher", "drills", "import", "lobs", "--db", bad + "-7.sqlite"],
        ["launcher", "drills", "import", "--db", "12.sqlite", bad + "-d.yaml"],  # it said "damaged file"
        ["launcher", "drills", "export", "--db", "12.sqlite", bad + "-d.yaml", "12.yaml"],
        ["launcher", "info", "--db", bad + "-7.sqlite"],
        ["launcher", "drills", "export", "--db", bad + "-7.sqlite", "Lobs", bad + "-8.yaml"],
        ["launcher", "table", *_TINY_TABLE, "--no-progress", "--db", bad + "-9.sqlite"],
        ["launcher", "lookup", "--db", bad + "-9.sqlite", "--target", "9", "0"],
        ["report", "--quiet", "--out", bad + "-10.html"],
        ["calibrate", "validate", "--serves", bad + "-in.csv", "--quiet"],
        ["call", "--track", bad + "-missing.csv"],
        # a TOML configuration cannot name a table whose name is not UTF-8: refused before the work
        ["calibrate", "tracks", "t.csv", "--out-table", bad + "-11.csv", "--out-config", "11.toml", "--quiet"],
    ]
    results = _in_a_process(argvs)
    for argv, (rc, err) in zip(argvs[:-2], results, strict=False):
        assert rc == 0, (argv, err)
    for (rc, err), what in zip(results[-2:], ("\\xff\\xfe-x-missing.csv", "\\xff\\xfe-x-11.csv"), strict=True):
        assert rc == 2 and len(err.splitlines()) == 1 and what in err, err
    made = sorted(n for n in os.listdir(b".") if n.startswith(os.fsencode(bad)))
    assert len(made) == 16, made  # the 14 outputs and the 2 inputs
    assert not os.path.exists("11.toml") and os.path.isfile("12.yaml")
    assert not [n for n in os.listdir(b".") if b".tmp-" in n or n.endswith((b"-wal", b"-shm"))]
