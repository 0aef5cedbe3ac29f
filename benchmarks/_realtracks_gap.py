"""What the gap of ``realtracks_floor.py`` is: hypotheses tested on the real flights (``--hypotheses``).

The gap (a fitted flight's best cubic against the track's cubic) is mostly the cubic Legendre term, the
jerk.  Three kinds of explanation are tested, each as parameters added to the free-flight model of the
fit (core's right-hand side, ``tennislab.linecall.model.free_positions``; the aero model's knots and the
flight constants changed, never the equations):

* physical, free per shot: the spin-decay rate; a slope dC_D/dv added to the drag curve (about 30 m/s);
  an exponent e on the lift curve, C_L(S) (S / 0.3)^e; a growth of drag with the spin parameter (the
  curves' ``cd_s``).  Already free in every fit: the launch state, the whole spin vector (its axis, the
  spin about the path included), the drag and lift scales.
* the tracker's frame and clock, global over the match: horizontal gravity components g_x, g_y (a tilt of
  the court frame: 0.1 deg is 0.017 m/s^2), |g|, a time scale (t -> (1 + eps) t), per-axis scales of the
  coordinates, a steady wind; and, global too, dC_D/dv.  Each is profiled over five values (every flight
  refitted at each); its estimate minimises the flights' summed relative misfit sum_i SSE_i / SSE_i(0)
  (each flight weighted by its own misfit, so that a few long flights do not decide), its sigma is the
  bootstrap over flights (each resample's estimate clipped to twice the grid: a sigma near that says
  "not determined"); the medians are then those of a refit at the estimate (clipped to the grid).
* the tracker's own cubic: at mid-flight the track's cubic gives v, a and the (constant) jerk j = 6 c3;
  drag along -v and lift across it follow from a - g, and with them the jerk a drag + Magnus ball has
  there (drag with the base model's C_D(v) slope, lift ~ S, the spin decay, the spin about the path free):
  the difference, in the frame (path, lift, spin axis), against the same check on the fitted flight's
  own cubic (the check's own error).
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import least_squares
from scipy.spatial.transform import Rotation
from scipy.stats import spearmanr

from tennislab.core.surfaces import get_surface
from tennislab.linecall import model as M

#: per-shot parameters: start, x_scale, printed name, unit, print factor
EXTRA = {
    "decay": (0.174, 0.5, "decay", "/s", 1.0),
    "cd_slope": (0.0, 0.005, "dC_D/dv", "per m/s", 1.0),
    "cl_exp": (0.0, 0.3, "e", "", 1.0),
    "cd_s": (0.0, 0.3, "cd_s", "", 1.0),
    "eps": (0.0, 0.01, "eps", "%", 100.0),
}
PER_SHOT = (
    ("spin decay", ("decay",)),
    ("C_D slope in speed", ("cd_slope",)),
    ("C_L(S) exponent", ("cl_exp",)),
    ("C_D against S", ("cd_s",)),
    ("time scale", ("eps",)),
    ("decay + C_D slope", ("decay", "cd_slope")),
)
#: global parameters: grid step, printed name, unit, print factor
GLOBAL = {
    "gx": (0.05, "gravity g_x", "m/s^2", 1.0),
    "gy": (0.05, "gravity g_y", "m/s^2", 1.0),
    "g": (0.1, "|g| - 9.80665", "m/s^2", 1.0),
    "eps": (0.01, "time scale", "%", 100.0),
    "sx": (0.01, "scale of x", "%", 100.0),
    "sy": (0.01, "scale of y", "%", 100.0),
    "sz": (0.01, "scale of z", "%", 100.0),
    "wx": (1.0, "wind along x", "m/s", 1.0),
    "wy": (1.0, "wind along y", "m/s", 1.0),
    "cd_slope": (0.003, "C_D slope in speed", "per m/s", 1.0),
}
P3_RMS = 1.0 / (120.0 * np.sqrt(7.0))  #: RMS of the P3 part of j t^3 / 6 over a flight of duration 1


def _rms_mm(r: np.ndarray) -> float:
    return float(np.sqrt(np.mean(np.sum(r.reshape(-1, 3) ** 2, axis=1))) * 1000.0)


class Model:
    """The free-flight model of the fit with the hypotheses' parameters (the base aero model: curves)."""

    def __init__(self, params, scale, spin_starts):
        self.consts = M.make_consts(params, get_surface("hard"), 0.0045, 16e-3)
        self.kern, self.ap = M.kernel_arg(params), params.aero.params
        nv, ns = int(self.ap[0]), int(self.ap[1])
        self.ov, self.ocd, self.osk, self.ocl, self.ns = 2, 2 + nv, 2 + 2 * nv, 2 + 2 * nv + ns, ns
        self.nv, self.scale, self.spin_starts = nv, scale, spin_starts
        self.g = float(self.consts[M.C_G])

    def positions(self, q, t, names, glob, pos):
        c, a, tt = self.consts.copy(), self.ap.copy(), t
        vals = dict(glob)
        vals.update(zip(names, q[11:], strict=True))
        c[M.C_DECAY] = vals.get("decay", c[M.C_DECAY])
        c[M.C_G] = self.g + vals.get("g", 0.0)
        c[M.C_WX], c[M.C_WY] = vals.get("wx", 0.0), vals.get("wy", 0.0)
        cd, vk = slice(self.ocd, self.ocd + self.nv), a[self.ov : self.ov + self.nv]
        a[cd] = np.maximum(a[cd] + vals.get("cd_slope", 0.0) * (vk - 30.0), 0.05)
        sk = a[self.osk : self.osk + self.ns]
        a[self.ocl : self.ocl + self.ns] *= (sk / 0.3) ** vals.get("cl_exp", 0.0)
        a[self.ocl + self.ns] = vals.get("cd_s", a[self.ocl + self.ns])
        tt = t * (1.0 + vals.get("eps", 0.0))
        M.free_positions(np.ascontiguousarray(q[:11]), 0.0, tt, self.kern, a, c, pos)
        out = pos
        if "gx" in vals or "gy" in vals:  # the physics frame (vertical g) rotated into the tracker's
            rot = Rotation.from_rotvec([vals.get("gy", 0.0) / self.g, -vals.get("gx", 0.0) / self.g, 0.0])
            out = out @ rot.as_matrix().T
        return out * (1.0 + np.array([vals.get("sx", 0.0), vals.get("sy", 0.0), vals.get("sz", 0.0)]))

    def fit(self, t, xyz, names=(), glob=None, x0=None, best_gap=True) -> dict:
        """Residual, floor, gap, best gap [mm] of one flight with the parameters ``names`` free."""
        glob = glob or {}
        t = t - t[0]
        pos = np.empty((t.size, 3))
        extra = [EXTRA[n][0] for n in names]
        scale = np.r_[self.scale, [EXTRA[n][1] for n in names]]

        def fun(q):
            return (self.positions(q, t, names, glob, pos) - xyz).ravel()

        if x0 is None:
            v0 = (xyz[2] - xyz[0]) / (t[2] - t[0])
            starts = [np.r_[xyz[0], v0, s, 1.0, 1.0, extra] for s in self.spin_starts]
        else:
            starts = [np.r_[x0[:11], extra]]
        best = min((least_squares(fun, s, x_scale=scale, max_nfev=600) for s in starts), key=lambda r: r.cost)
        vander = np.vander((t - t.mean()) / (t[-1] - t[0]), 4)
        proj = vander @ np.linalg.pinv(vander)
        P = self.positions(best.x, t, names, glob, pos).copy()
        out = {"residual": _rms_mm(best.fun), "floor": _rms_mm(P - proj @ P), "x": best.x, "sse": 2 * best.cost}
        out.update(P=P, PP=proj @ P)
        if best_gap:
            g = least_squares(
                lambda q: (proj @ self.positions(q, t, names, glob, pos) - xyz).ravel(),
                best.x,
                x_scale=scale,
                max_nfev=600,
            )
            out["best_gap"] = _rms_mm(g.fun)
        return out

    def jerk_check(self, t, xyz):
        """(|dj|, dj in (path, lift, spin axis), as a P3 gap [mm]) at mid-flight of the cubic of ``xyz``."""
        tau = t - 0.5 * (t[0] + t[-1])
        c = np.array([np.polyfit(tau, xyz[:, i], 3) for i in range(3)])
        v, a, j = c[:, 2], 2.0 * c[:, 1], 6.0 * c[:, 0]
        sp = np.linalg.norm(v)
        vh = v / sp
        aero = a + np.array([0.0, 0.0, self.g])
        drag = -aero @ vh
        lift = aero + drag * vh
        lm = np.linalg.norm(lift)
        lh = lift / lm
        n = np.cross(vh, lh)
        vk, cdk = self.ap[self.ov : self.ov + self.nv], self.ap[self.ocd : self.ocd + self.nv]
        beta = (np.interp(sp + 0.5, vk, cdk) - np.interp(sp - 0.5, vk, cdk)) * sp / np.interp(sp, vk, cdk)
        lam = self.consts[M.C_DECAY]
        j_drag = -(drag / sp**2) * ((beta + 1.0) * (vh @ a) * v + sp * a)
        j_lift = -lam * lift + (lm / sp) * np.cross(n, a)  # C_L ~ S: lift ~ w x v, |w| decaying
        gyro = (lm / sp) * np.cross(vh, a)  # per unit spin about the path / across it
        dj = j - j_drag - j_lift
        dj = dj - (gyro @ dj) / (gyro @ gyro) * gyro
        comp = np.array([vh @ dj, lh @ dj, n @ dj])
        return np.linalg.norm(dj), comp, np.linalg.norm(dj) * (t[-1] - t[0]) ** 3 * P3_RMS * 1000.0


def _med3(x, s) -> str:
    x = np.asarray(x)
    return f"{np.median(x):.2f} / {np.median(x[s]):.2f} / {np.median(x[~s]):.2f}"


def _row(label, free, rows, s, fitted) -> str:
    r = [x["residual"] for x in rows]
    bg = [x["best_gap"] for x in rows]
    fl = np.median([x["floor"] for x in rows])
    return f"{label:24s} | {free:8s} | {_med3(r, s)} | {_med3(bg, s)} | {fl:.2f} | {fitted}"


def _spread(x, unit, fac) -> str:
    x = np.asarray(x) * fac
    return f"{np.median(x):.3g} {unit} [{np.percentile(x, 10):.3g}, {np.percentile(x, 90):.3g}]".replace(" ]", "]")


def _vertex(vals, total):
    """The minimum of a parabola through (vals, total) (the grid's end on the falling side when it has none)."""
    p = np.polyfit(vals, total, 2)
    if p[0] > 0:
        return -p[1] / (2 * p[0])
    return vals[-1] if np.polyval(p, vals[-1]) < np.polyval(p, vals[0]) else vals[0]


def report(flights, params, scale, spin_starts, label) -> None:
    """Print the hypotheses' table and the checks of the tracker's cubic (module docstring)."""
    mod = Model(params, scale, spin_starts)
    s = np.array([f.kind == "serve" for f in flights])
    base = [mod.fit(f.t, f.xyz) for f in flights]
    x0s = [r["x"] for r in base]
    gyro = [abs(r["x"][6:9] @ r["x"][3:6]) / np.linalg.norm(r["x"][6:9]) / np.linalg.norm(r["x"][3:6]) for r in base]
    print(f"\nthe gap against hypotheses ({label}; {len(flights)} flights, {s.sum()} serves): medians, mm;")
    print("fitted values: median [p10, p90] over flights (per shot), estimate +- bootstrap sigma (global)")
    head = "residual: all / serve / rally | best gap: all / serve / rally | floor | fitted"
    print(f"{'hypothesis':24s} | free     | {head}")
    print(_row("none added", "-", base, s, f"spin about the path {_spread(gyro, '%', 100.0)} of the spin"))
    for lab, names in PER_SHOT:
        rows = [mod.fit(f.t, f.xyz, names, x0=x0) for f, x0 in zip(flights, x0s, strict=True)]
        X = np.array([r["x"][11:] for r in rows])
        fitted = "; ".join(f"{EXTRA[n][2]} {_spread(X[:, i], EXTRA[n][3], EXTRA[n][4])}" for i, n in enumerate(names))
        print(_row(lab, "per shot", rows, s, fitted))
        if names == ("cd_slope",):
            slope_rows = rows
    for key, (h, lab, unit, fac) in GLOBAL.items():
        vals = np.arange(-2, 3) * h
        sse = np.array(
            [[mod.fit(f.t, f.xyz, (), {key: v}, x0, False)["sse"] for f, x0 in zip(flights, x0s)] for v in vals]
        )
        rel = sse / sse[2]
        est = _vertex(vals, rel.sum(axis=1))
        rng = np.random.default_rng(0)
        boot = [rng.integers(0, len(flights), len(flights)) for _ in range(200)]
        sd = np.std([np.clip(_vertex(vals, rel[:, i].sum(axis=1)), 2 * vals[0], 2 * vals[-1]) for i in boot])
        at = float(np.clip(est, vals[0], vals[-1]))
        rows = [mod.fit(f.t, f.xyz, (), {key: at}, x0) for f, x0 in zip(flights, x0s, strict=True)]
        edge = "" if vals[0] < est < vals[-1] else " (grid edge)"
        print(_row(lab, "global", rows, s, f"{est * fac:.3g} +- {sd * fac:.2g} {unit}{edge}".replace("  ", " ")))

    long = [(f, r) for f, r in zip(flights, base, strict=True) if f.duration >= 0.3]
    chk = [(mod.jerk_check(f.t, f.xyz), mod.jerk_check(f.t, r["PP"])) for f, r in long]
    print(f"\nthe track's cubic against drag + Magnus at its own mid-flight v and a ({len(chk)} flights >= 0.3 s):")
    for i, lab in ((0, "the track's cubic"), (1, "the fitted flight's own cubic (the check's own error)")):
        dj = np.array([c[i][0] for c in chk])
        comp = np.array([c[i][1] for c in chk])
        sd = (np.percentile(comp, 75, axis=0) - np.percentile(comp, 25, axis=0)) / 1.349
        med = np.median(comp, axis=0)
        print(
            f"  {lab}: jerk off by {np.median(dj):.2f} m/s^3 (median); along the path / the lift / the spin axis "
            f"median {med[0]:.2f} / {med[1]:.2f} / {med[2]:.2f}, robust sd {sd[0]:.2f} / {sd[1]:.2f} / {sd[2]:.2f}"
            " m/s^3;"
            f" as a cubic-term gap {np.median([c[i][2] for c in chk]):.2f} mm"
        )
    along, across, g3, f4 = [], [], [], []
    for f, r in zip(flights, base, strict=True):
        P, PP = r["P"], r["PP"]
        vh = np.gradient(P, f.t, axis=0)
        vh /= np.linalg.norm(vh, axis=1)[:, None]
        e = P - f.xyz
        ea = np.sum(e * vh, axis=1)
        along.append(np.sqrt(np.mean(ea**2)) * 1e3)
        across.append(np.sqrt(np.mean(np.sum((e - ea[:, None] * vh) ** 2, axis=1))) * 1e3)
        leg = np.polynomial.legendre.legvander(2 * (f.t - f.t[0]) / f.duration - 1, 6)
        g3.append(np.linalg.lstsq(leg, np.sum((PP - f.xyz) * vh, axis=1), rcond=None)[0][3] * 1e3)
        f4.append(np.linalg.lstsq(leg, np.sum((P - PP) * vh, axis=1), rcond=None)[0][4] * 1e3)
    g3, f4 = np.array(g3), np.array(f4)
    print(
        f"  the residual (none added) along the path / across it: {np.median(along):.2f} / {np.median(across):.2f} mm"
    )
    print(
        f"  the gap's cubic term along the path: positive in {(g3 > 0).sum()} of {g3.size} flights, median size "
        f"{np.median(np.abs(g3)):.2f} mm; rank correlation with the flight's own quartic term (floor; negative in "
        f"{(f4 < 0).sum()}) {spearmanr(g3, f4)[0]:.2f}"
    )
    cs = np.array([r["x"][11] for r in slope_rows])
    speed = np.array([np.linalg.norm(x[3:6]) for x in x0s])
    spin = np.array([np.linalg.norm(x[6:9]) for x in x0s])
    dur = np.array([f.duration for f in flights])
    print(
        f"  the per-shot C_D slope against the shot (rank correlation): speed {spearmanr(cs, speed)[0]:.2f}, "
        f"spin {spearmanr(cs, spin)[0]:.2f}, duration {spearmanr(cs, dur)[0]:.2f}; serves "
        f"{_spread(cs[s], 'per m/s', 1.0)}, rally shots {_spread(cs[~s], 'per m/s', 1.0)}"
    )
