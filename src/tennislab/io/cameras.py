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
"""

from __future__ import annotations

import csv
import io
import json
import math

import numpy as np

from tennislab.errors import InputError
from tennislab.io.files import read_text
from tennislab.linecall.cameras import Camera

DEFAULT_SIGMA_PX = 0.5


def _num(name, v, lo=None, hi=None):
    try:
        f = float(v)
    except (TypeError, ValueError):
        raise InputError(f"{name}: expected a number, got {v!r}"[:200]) from None
    if not math.isfinite(f) or (lo is not None and f <= lo) or (hi is not None and f > hi):
        raise InputError(f"{name}: {f:g} is outside the allowed range ({lo}, {hi}]")
    return f


def parse_cameras(text: str, name: str = "cameras") -> list[Camera]:
    """Parse a calibration JSON (see the module docstring)."""
    try:
        doc = json.loads(text)
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise InputError(f"{name}: not valid JSON ({exc})") from None
    lst = doc.get("cameras") if isinstance(doc, dict) else None
    if not isinstance(lst, list) or len(lst) < 2:
        raise InputError(f"{name}: need a list 'cameras' with at least 2 cameras")
    cams = []
    for i, c in enumerate(lst):
        if not isinstance(c, dict):
            raise InputError(f"{name}: cameras[{i}] is not an object")
        cn = str(c.get("name", f"cam{i}"))
        f = {k: _num(f"{name}: {cn}.{k}", c.get(k), 0.0, 1e6) for k in ("fx", "fy")}
        cx = _num(f"{name}: {cn}.cx", c.get("cx"), None, 1e6)
        cy = _num(f"{name}: {cn}.cy", c.get("cy"), None, 1e6)
        try:
            R = np.asarray(c.get("R"), dtype=float)
        except (TypeError, ValueError):
            raise InputError(f"{name}: {cn}.R must be a 3x3 matrix") from None
        if R.shape != (3, 3) or not np.all(np.isfinite(R)):
            raise InputError(f"{name}: {cn}.R must be a 3x3 matrix of numbers")
        if np.abs(R @ R.T - np.eye(3)).max() > 1e-4 or np.linalg.det(R) < 0:
            raise InputError(f"{name}: {cn}.R is not a rotation matrix (orthonormal, det +1)")
        if "position" in c:
            C = np.array([_num(f"{name}: {cn}.position", v, None, None) for v in c["position"]])
        elif "t" in c:
            tv = np.array([_num(f"{name}: {cn}.t", v, None, None) for v in c["t"]])
            C = -R.T @ tv
        else:
            raise InputError(f"{name}: {cn} needs 'position' (camera centre) or 't'")
        if C.shape != (3,):
            raise InputError(f"{name}: {cn}.position must have 3 numbers")
        w = int(_num(f"{name}: {cn}.width", c.get("width", 1920), 0, 1e5))
        h = int(_num(f"{name}: {cn}.height", c.get("height", 1080), 0, 1e5))
        cams.append(Camera(cn, f["fx"], f["fy"], cx, cy, R, C, w, h))
    return cams


def read_cameras(path: str) -> list[Camera]:
    text = read_text(path, 50_000_000)
    return parse_cameras(text, str(path))


def cameras_to_json(cams: list[Camera]) -> str:
    return json.dumps(
        {
            "cameras": [
                {
                    "name": c.name,
                    "fx": c.fx,
                    "fy": c.fy,
                    "cx": c.cx,
                    "cy": c.cy,
                    "width": c.width,
                    "height": c.height,
                    "R": c.R.tolist(),
                    "position": c.C.tolist(),
                }
                for c in cams
            ]
        },
        indent=1,
    )


def parse_detections(text: str, cams: list[Camera], name: str = "detections") -> dict:
    """Parse a detections CSV into arrays (t, cam index, uv, sigma)."""
    lines = [ln for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")]
    if "\x00" in text or not lines:
        raise InputError(f"{name}: empty or not a CSV text file")
    try:
        rows = list(csv.reader(lines))
    except csv.Error as exc:
        raise InputError(f"{name}: malformed CSV ({exc})") from None
    header = [h.strip().lower() for h in rows[0]]
    for c in ("t", "camera", "u", "v"):
        if c not in header:
            raise InputError(f"{name}: missing column {c!r} (need t,camera,u,v[,sigma_px])")
    ix = {c: header.index(c) for c in header}
    names = {c.name: i for i, c in enumerate(cams)}
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


def read_detections(path: str, cams: list[Camera]) -> dict:
    text = read_text(path, 500_000_000)
    return parse_detections(text, cams, str(path))


def detections_to_csv(det: dict, cams: list[Camera]) -> str:
    buf = io.StringIO()
    buf.write("t,camera,u,v,sigma_px\n")
    for t, c, (u, v), s in zip(det["t"], det["cam"], det["uv"], det["sigma"]):
        buf.write(f"{t:.6f},{cams[c].name},{u:.3f},{v:.3f},{s:.3f}\n")
    return buf.getvalue()
