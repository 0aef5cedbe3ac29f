"""Calibrated pinhole cameras: projection, triangulation and a synthetic rig.

Camera model (no lens distortion; undistort detections first):

    X_c = R (X - C),   u = f_x X_c,x / X_c,z + c_x,   v = f_y X_c,y / X_c,z + c_y

with R the world-to-camera rotation (rows: image right, image down, optical
axis) and C the camera centre in the court frame [m]; (u, v) in pixels.

Triangulation of one time stamp seen by >= 2 cameras: the linear DLT
solution (Hartley & Zisserman, Multiple View Geometry, 2nd ed., sec. 12.2)
refined by Gauss-Newton on the reprojection error; its 3-D covariance is
sigma_px^2 (J^T J)^-1, and the per-axis sigma handed to the track fit is
sqrt(trace / 3) (the fit takes an isotropic sigma per point).

References
----------
.. [1] Hartley & Zisserman, Multiple View Geometry in Computer Vision, 2nd ed., sec. 12.2 (linear triangulation)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from tennislab.core.court import ITF_COURT
from tennislab.errors import InputError


@dataclass(frozen=True)
class Camera:
    """A pinhole camera: name, focal lengths and principal point [px], rotation R (3x3), centre C [m]."""

    name: str
    fx: float
    fy: float
    cx: float
    cy: float
    R: np.ndarray
    C: np.ndarray
    width: int = 1920
    height: int = 1080

    def project(self, X) -> np.ndarray:
        """Pixel coordinates (N, 2) of world points X (N, 3); NaN behind the camera."""
        X = np.atleast_2d(np.asarray(X, dtype=float))
        Xc = (X - self.C) @ self.R.T
        z = Xc[:, 2]
        with np.errstate(divide="ignore", invalid="ignore"):
            u = np.where(z > 0, self.fx * Xc[:, 0] / z + self.cx, np.nan)
            v = np.where(z > 0, self.fy * Xc[:, 1] / z + self.cy, np.nan)
        return np.column_stack([u, v])

    @property
    def P(self) -> np.ndarray:
        """3x4 projection matrix K [R | -R C]."""
        K = np.array([[self.fx, 0, self.cx], [0, self.fy, self.cy], [0, 0, 1.0]])
        return K @ np.hstack([self.R, (-self.R @ self.C)[:, None]])


def cameras_from_records(records) -> list[Camera]:
    """Cameras from the plain records of :func:`tennislab.io.cameras.parse_cameras` (dicts with
    ``name, fx, fy, cx, cy, R, C, width, height``); :class:`Camera` objects pass through."""
    out = []
    for c in records:
        if isinstance(c, Camera):
            out.append(c)
            continue
        out.append(
            Camera(
                str(c["name"]),
                float(c["fx"]),
                float(c["fy"]),
                float(c["cx"]),
                float(c["cy"]),
                np.asarray(c["R"], dtype=float),
                np.asarray(c["C"], dtype=float),
                int(c.get("width", 1920)),
                int(c.get("height", 1080)),
            )
        )
    return out


def look_at(name: str, centre, target, f: float = 2000.0, width: int = 1920, height: int = 1080) -> Camera:
    """A camera at ``centre`` [m] looking at ``target`` [m] with image rows horizontal."""
    C = np.asarray(centre, dtype=float)
    z = np.asarray(target, dtype=float) - C
    z /= np.linalg.norm(z)
    x = np.cross(z, [0.0, 0.0, 1.0])
    if np.linalg.norm(x) < 1e-9:
        raise InputError(f"camera {name}: looking straight up or down; give a tilted target")
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    return Camera(name, f, f, width / 2, height / 2, np.vstack([x, y, z]), C, width, height)


def synthetic_rig(n: int = 8, court=None, f: float = 2500.0) -> list[Camera]:
    """``n`` cameras around the court (as broadcast line-calling rigs are: high in the stands,
    each aimed at a line region), 1920x1080 px."""
    court = court or ITF_COURT
    L, d = court.half_length, court.doubles_width / 2
    cams = []
    for i in range(n):
        side = 1.0 if i % 2 == 0 else -1.0
        xs = np.linspace(-L - 4, L + 4, (n + 1) // 2)[i // 2]
        centre = (xs, side * (d + 9.0), 9.0 + 2.0 * (i % 3))
        aim = (0.55 * xs, -0.2 * side * d, 0.0)
        cams.append(look_at(f"cam{i}", centre, aim, f))
    return cams


def triangulate(cams: list[Camera], uv: np.ndarray, sigma_px: np.ndarray, iters: int = 3):
    """One point from its pixels uv (k, 2) in cameras ``cams`` (k >= 2): (X (3,), cov (3, 3))."""
    rows = []
    for cam, (u, v) in zip(cams, uv):
        P = cam.P
        rows.append(u * P[2] - P[0])
        rows.append(v * P[2] - P[1])
    _, _, vt = np.linalg.svd(np.asarray(rows))
    Xh = vt[-1]
    if abs(Xh[3]) < 1e-12:
        raise InputError("detections: triangulation failed (point at infinity)")
    X = Xh[:3] / Xh[3]
    J = np.zeros((2 * len(cams), 3))
    for _ in range(iters):
        res_l: list[float] = []
        jac_l: list[np.ndarray] = []
        for cam, (u, v), s in zip(cams, uv, sigma_px):
            Xc = cam.R @ (X - cam.C)
            z = Xc[2]
            pu = cam.fx * Xc[0] / z + cam.cx
            pv = cam.fy * Xc[1] / z + cam.cy
            du = cam.fx * (cam.R[0] / z - Xc[0] * cam.R[2] / z**2)
            dv = cam.fy * (cam.R[1] / z - Xc[1] * cam.R[2] / z**2)
            res_l += [(pu - u) / s, (pv - v) / s]
            jac_l += [du / s, dv / s]
        J = np.asarray(jac_l)
        step = np.linalg.lstsq(J, -np.asarray(res_l), rcond=None)[0]
        X = X + step
        if np.linalg.norm(step) < 1e-9:
            break
    cov = np.linalg.pinv(J.T @ J)
    return X, cov


def triangulate_detections(cams: list[Camera], det: dict):
    """Triangulate every time stamp seen by >= 2 cameras.

    det : {"t": (M,), "cam": (M,) camera indices, "uv": (M, 2), "sigma": (M,) px}
    (from :func:`tennislab.io.cameras.read_detections`).  Returns (t (N,), xyz (N, 3),
    sigma (N,) [m]) sorted by time.
    """
    t = np.asarray(det["t"], dtype=float)
    order = np.argsort(t, kind="stable")
    t = t[order]
    cam = np.asarray(det["cam"])[order]
    uv = np.asarray(det["uv"], dtype=float)[order]
    sg = np.asarray(det["sigma"], dtype=float)[order]
    # group time stamps equal within 1 us (synchronised cameras)
    brk = np.nonzero(np.diff(t) > 1e-6)[0] + 1
    ts, xs, ss = [], [], []
    for grp in np.split(np.arange(t.size), brk):
        cams_g = cam[grp]
        if np.unique(cams_g).size < 2:
            continue
        X, cov = triangulate([cams[c] for c in cams_g], uv[grp], sg[grp])
        ts.append(t[grp].mean())
        xs.append(X)
        ss.append(np.sqrt(max(np.trace(cov), 0.0) / 3.0))
    if len(ts) < 2:
        raise InputError("detections: fewer than 2 time stamps seen by at least 2 cameras")
    return np.asarray(ts), np.asarray(xs), np.asarray(ss)


def synthetic_detections(cams: list[Camera], t, xyz, sigma_px: float = 0.5, seed=None) -> dict:
    """Project a true track into every camera that sees it and add pixel noise."""
    rng = np.random.default_rng(seed)
    T, C, UV = [], [], []
    for ci, cam in enumerate(cams):
        uv = cam.project(xyz)
        ok = (
            np.isfinite(uv).all(axis=1)
            & (uv[:, 0] >= 0)
            & (uv[:, 0] <= cam.width)
            & (uv[:, 1] >= 0)
            & (uv[:, 1] <= cam.height)
        )
        T.append(np.asarray(t)[ok])
        C.append(np.full(ok.sum(), ci))
        UV.append(uv[ok] + rng.normal(0, sigma_px, (ok.sum(), 2)))
    t_all = np.concatenate(T)
    return {"t": t_all, "cam": np.concatenate(C), "uv": np.vstack(UV), "sigma": np.full(t_all.size, sigma_px)}
