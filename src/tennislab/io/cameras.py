"""Camera calibrations (JSON) and 2-D ball detections (CSV) for multi-camera line calling.

Calibration JSON::

    {"cameras": [
      {"name": "cam0", "fx": 2500, "fy": 2500, "cx": 960, "cy": 540,
       "width": 1920, "height": 1080,
       "R": [[...], [...], [...]],          # world-to-camera rotation (orthonormal)
       "position": [x, y, z]}               # camera centre [m]; or "t": [tx, ty, tz] with X_c = R X + t
    ]}

Detections CSV: ``t,camera,u,v[,sigma_px]`` - time [s] (equal for synchronised
frames), camera name (or 0-based index), pixel coordinates, optional pixel
noise (default 0.5 px).

Plain data out (this module is a leaf): :func:`parse_cameras` gives one record (dict) per camera,
``{"name", "fx", "fy", "cx", "cy", "width", "height", "R" (3x3 array), "C" (3,) [m]}``;
:func:`tennislab.linecall.cameras.cameras_from_records` makes cameras of them.  :func:`parse_detections`
maps camera names (or 0-based indices) to indices into the list of cameras given (records, cameras or
plain names).  Limits: the calibration file at most 50 MB and nested at most :data:`MAX_DEPTH` levels;
every malformed field is a one-line :class:`~tennislab.errors.InputError` naming it.
"""

from __future__ import annotations

import csv
import io
import json
import math

import numpy as np

from tennislab.errors import InputError
from tennislab.io.files import read_text
from tennislab.io.formats import MAX_DEPTH, check_header, load_json_document

DEFAULT_SIGMA_PX = 0.5
MAX_CAMERAS = 1000  #: most cameras in a calibration
MAX_DETECTIONS = 10_000_000  #: most rows of a detections file


def _num(name, v, lo=None, hi=None):
    if isinstance(v, (bool, dict, list)) or v is None:
        raise InputError(f"{name}: expected a number, got {'null' if v is None else type(v).__name__}")
    try:
        f = float(v)
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"{name}: expected a number, got {str(v)[:30]!r}") from None
    if not math.isfinite(f) or (lo is not None and f <= lo) or (hi is not None and f > hi):
        raise InputError(f"{name}: {f:g} is outside the allowed range ({lo}, {hi}]")
    return f


def _vec3(name: str, v) -> np.ndarray:
    if not isinstance(v, list) or len(v) != 3:
        raise InputError(f"{name}: expected a list of 3 numbers")
    return np.array([_num(f"{name}[{i}]", x) for i, x in enumerate(v)])


def parse_cameras(text: str, name: str = "cameras") -> list[dict]:
    """Parse a calibration JSON (see the module docstring) into camera records."""
    doc = load_json_document(text, name, max_depth=MAX_DEPTH)
    lst = doc.get("cameras") if isinstance(doc, dict) else None
    if not isinstance(lst, list) or len(lst) < 2:
        raise InputError(f"{name}: need a list 'cameras' with at least 2 cameras")
    if len(lst) > MAX_CAMERAS:
        raise InputError(f"{name}: {len(lst)} cameras, more than the {MAX_CAMERAS} allowed")
    cams: list[dict] = []
    for i, c in enumerate(lst):
        if not isinstance(c, dict):
            raise InputError(f"{name}: cameras[{i}] is not an object")
        cn = str(c.get("name", f"cam{i}"))[:64]
        if any(k["name"] == cn for k in cams):  # the one duplicate rule: a detection's camera is never a guess
            raise InputError(f"{name}: duplicate camera name {cn!r} (each camera once)")
        f = {k: _num(f"{name}: {cn}.{k}", c.get(k), 0.0, 1e6) for k in ("fx", "fy")}
        cx = _num(f"{name}: {cn}.cx", c.get("cx"), None, 1e6)
        cy = _num(f"{name}: {cn}.cy", c.get("cy"), None, 1e6)
        rows = c.get("R")
        if not isinstance(rows, list) or len(rows) != 3:
            raise InputError(f"{name}: {cn}.R must be a 3x3 matrix")
        R = np.vstack([_vec3(f"{name}: {cn}.R[{k}]", row) for k, row in enumerate(rows)])
        if np.abs(R @ R.T - np.eye(3)).max() > 1e-4 or np.linalg.det(R) < 0:
            raise InputError(f"{name}: {cn}.R is not a rotation matrix (orthonormal, det +1)")
        if "position" in c:
            C = _vec3(f"{name}: {cn}.position", c["position"])
        elif "t" in c:
            C = -R.T @ _vec3(f"{name}: {cn}.t", c["t"])
        else:
            raise InputError(f"{name}: {cn} needs 'position' (camera centre) or 't'")
        if np.any(np.abs(C) > 1e4):
            raise InputError(f"{name}: {cn}.position: beyond 10 km (units must be metres)")
        w = int(_num(f"{name}: {cn}.width", c.get("width", 1920), 0, 1e5))
        h = int(_num(f"{name}: {cn}.height", c.get("height", 1080), 0, 1e5))
        cams.append(
            {"name": cn, "fx": f["fx"], "fy": f["fy"], "cx": cx, "cy": cy, "R": R, "C": C, "width": w, "height": h}
        )
    return cams


def read_cameras(path: str) -> list[dict]:
    """Read a calibration JSON file into camera records (see :func:`parse_cameras`)."""
    text = read_text(path, 50_000_000)
    return parse_cameras(text, str(path))


def _name_of(c) -> str:
    return str(c["name"] if isinstance(c, dict) else getattr(c, "name", c))


def cameras_to_json(cams) -> str:
    """Calibration JSON of cameras (objects with the record's attributes, or records)."""

    def get(c, k):
        return c[k] if isinstance(c, dict) else getattr(c, k)

    return json.dumps(
        {
            "cameras": [
                {
                    "name": get(c, "name"),
                    "fx": get(c, "fx"),
                    "fy": get(c, "fy"),
                    "cx": get(c, "cx"),
                    "cy": get(c, "cy"),
                    "width": get(c, "width"),
                    "height": get(c, "height"),
                    "R": np.asarray(get(c, "R")).tolist(),
                    "position": np.asarray(get(c, "C")).tolist(),
                }
                for c in cams
            ]
        },
        indent=1,
    )


def parse_detections(text: str, cams: list, name: str = "detections") -> dict:
    """Parse a detections CSV into arrays (t, cam index, uv, sigma); ``cams`` gives the camera names in
    order (records, cameras or names)."""
    lines = [ln for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")]
    if "\x00" in text or not lines:
        raise InputError(f"{name}: empty or not a CSV text file")
    try:
        rows = list(csv.reader(lines))
    except csv.Error as exc:
        raise InputError(f"{name}: malformed CSV ({exc})") from None
    header = [h.strip().lower() for h in rows[0]]
    check_header(name, header)
    for c in ("t", "camera", "u", "v"):
        if c not in header:
            raise InputError(f"{name}: missing column {c!r} (need t,camera,u,v[,sigma_px])")
    ix = {c: header.index(c) for c in header}
    if len(rows) - 1 > MAX_DETECTIONS:
        raise InputError(f"{name}: {len(rows) - 1} rows, more than the {MAX_DETECTIONS} allowed")
    names = {_name_of(c): i for i, c in enumerate(cams)}
    T, C, UV, S = [], [], [], []
    for r, row in enumerate(rows[1:], 2):
        if len(row) < len(header):
            raise InputError(f"{name}: row {r}: {len(row)} field(s), expected {len(header)}")
        cam = row[ix["camera"]].strip()
        if cam in names:
            ci = names[cam]
        else:
            try:
                ci = int(cam)
            except ValueError:
                raise InputError(f"{name}: row {r}: unknown camera {cam[:30]!r}") from None
            if not 0 <= ci < len(cams):
                raise InputError(f"{name}: row {r}: camera index {ci} outside 0..{len(cams) - 1}")
        T.append(_num(f"{name}: row {r}, t", row[ix["t"]]))
        UV.append((_num(f"{name}: row {r}, u", row[ix["u"]]), _num(f"{name}: row {r}, v", row[ix["v"]])))
        S.append(
            _num(f"{name}: row {r}, sigma_px", row[ix["sigma_px"]], 0.0, 1e3) if "sigma_px" in ix else DEFAULT_SIGMA_PX
        )
        C.append(ci)
    if not T:
        raise InputError(f"{name}: no detections")
    return {"t": np.array(T), "cam": np.array(C, dtype=int), "uv": np.array(UV), "sigma": np.array(S)}


def read_detections(path: str, cams: list) -> dict:
    """Read a detections CSV file (see :func:`parse_detections`)."""
    text = read_text(path, 500_000_000)
    return parse_detections(text, cams, str(path))


def detections_to_csv(det: dict, cams: list) -> str:
    """CSV text of detections (the format :func:`parse_detections` reads)."""
    buf = io.StringIO()
    buf.write("t,camera,u,v,sigma_px\n")
    for t, c, (u, v), s in zip(det["t"], det["cam"], det["uv"], det["sigma"]):
        buf.write(f"{t:.6f},{_name_of(cams[c])},{u:.3f},{v:.3f},{s:.3f}\n")
    return buf.getvalue()
