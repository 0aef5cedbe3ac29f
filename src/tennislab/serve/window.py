"""The serve window: every (alpha, beta) on a grid, its outcome, and Table 1 of the paper (sec. 2.3).

:func:`window` is the workflow behind ``tennislab serve-window`` (and the app's heat map, the
report's Table 1); :func:`windows` runs several players; :func:`default_serve` picks the serve
deepest inside a player's window.

The impact depends on the racket speed V and the impact angle alpha only (beta
just rotates it, seed eq 21), so the impacts are computed once per alpha
(:func:`tennislab.core.impact.impact_batch`) and the flights of all
alpha x beta serves in one compiled batch (:func:`tennislab.core.flight.fly_batch`).
:func:`window_chunk` is the per-chunk worker (module level, for
``tennislab.batch.map_chunks``).

Optimum serves (seed sec. 2.3): the seed asks for "a high v while landing as
close to the service line as possible" for the flat serve and for "peak spin
rate" for the topspin serve.  Its own choices (figs 7-9) are, for all three
players, the successful flat serve with the largest X (two of them are the
*slowest* flat serves), so the flat rule we apply is: largest landing_x, ties
by higher speed.  Topspin: largest spin, ties (spin depends on alpha only) by
largest landing_x.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field

import numpy as np
from scipy.ndimage import distance_transform_cdt

from tennislab.core.flight import FlightParams
from tennislab.core.impact import ImpactParams
from tennislab.errors import InputError, check_range
from tennislab.results import Result, Table, jsonable
from tennislab.serve.pipeline import Setup, failure_counts, flights, impacts, launch_3d, make_setup
from tennislab.serve.players import SEED_PLAYERS, PlayerProfile
from tennislab.serve.published import OPTIMUM, PEAK_SPIN_ALPHA, TABLE1
from tennislab.serve.setup import CATEGORIES, SeedCriteria
from tennislab.units import RPM

__all__ = [
    "DefaultServe",
    "ServeWindow",
    "ServeWindows",
    "default_serve",
    "window",
    "window_chunk",
    "window_of_setup",
    "windows",
]

SUMMARY_KEYS = ("beta", "alpha", "spin_rpm", "speed", "landing_x", "net_height", "launch_angle")


def window_chunk(inputs: dict, *, setup: Setup) -> dict:
    """Per-chunk worker (``tennislab.batch.map_chunks``): serves of the window from their racket-frame
    impact results (``v_n``, ``v_t`` [m/s], ``omega`` [rad/s], ``beta`` [rad]) to their outcome --
    stages 2-4 of the serve pipeline (:func:`tennislab.serve.pipeline.flights`)."""
    return flights(inputs, setup=setup)


@dataclass(frozen=True)
class ServeWindow(Table):
    """Outcome of every serve on the alpha x beta grid for one player.

    Arrays are (n_beta, n_alpha); angles in degrees at this edge of the API
    (``alpha_deg``, ``beta_deg``); SI otherwise.  ``to_dict()`` is ``tennislab serve-window
    --json`` for one player; ``rows()`` / ``to_frame()`` give every serve.
    """

    COLUMNS = ("player", *SUMMARY_KEYS, "success", "category")
    #: the CSV's and the JSON's published names -> the frame's, with the unit (docs/conventions.md)
    FRAME_COLUMNS = {
        "beta": "beta_deg",
        "alpha": "alpha_deg",
        "speed": "speed_ms",
        "landing_x": "landing_x_m",
        "net_height": "net_height_m",
        "launch_angle": "launch_angle_deg",
    }

    player: PlayerProfile
    alpha_deg: np.ndarray
    beta_deg: np.ndarray
    speed: np.ndarray  #: ball speed after impact [m/s] (per alpha)
    spin_rpm: np.ndarray  #: spin [rpm] (per alpha, > 0 topspin)
    contact_time: np.ndarray  #: [s] (per alpha)
    regime: np.ndarray  #: 0 slide, 1 roll (per alpha)
    launch_angle: np.ndarray  #: gamma [deg] (n_beta, n_alpha)
    landing_x: np.ndarray  #: X from the impact point [m]
    net_height: np.ndarray  #: Y, ball centre at the net [m]
    success: np.ndarray  #: bool
    category: np.ndarray  #: 0 flat, 1 topspin, 2 other
    criteria: SeedCriteria = field(repr=False, default_factory=SeedCriteria)
    mode: str = "seed-2d"  #: success test: ``seed-2d`` or ``deuce-box`` / ``ad-box`` (3-D)
    caveats: tuple[str, ...] = ()  #: model caveats shown next to the numbers
    reason: np.ndarray | None = None  #: why each serve fails (index into REASON_CODES; 0 in)
    #: what the window was flown with (physics, criteria, 3-D options; :func:`window_of_setup` flies another)
    setup: Setup | None = field(default=None, repr=False)
    azimuth_deg: float = field(default=0.0, repr=False)  #: face azimuth of a 3-D window [deg]

    def grid(self, name: str) -> np.ndarray:
        """Any per-serve quantity broadcast to (n_beta, n_alpha)."""
        shape = self.success.shape
        if name == "alpha":
            return np.broadcast_to(self.alpha_deg[None, :], shape)
        if name == "beta":
            return np.broadcast_to(self.beta_deg[:, None], shape)
        a = getattr(self, name)
        return np.broadcast_to(a[None, :], shape) if a.ndim == 1 else a

    def mask(self, category: str) -> np.ndarray:
        return self.success & (self.grid("category") == CATEGORIES.index(category))

    def summary(self) -> dict:
        """``flat``, ``topspin`` and ``other`` (the spins between them): ``n`` and [min, max] of
        :data:`SUMMARY_KEYS` over the successes of each class."""
        out: dict[str, dict] = {}
        for cat in ("flat", "topspin", "other"):
            m = self.mask(cat)
            d: dict = {"n": int(m.sum())}
            for k in SUMMARY_KEYS:
                v = self.grid(k)[m]
                d[k] = [float(v.min()), float(v.max())] if v.size else None
            out[cat] = d
        return out

    def bands(self) -> dict:
        """The spin classes' bounds [rpm]: ``flat`` [0, flat_max), ``other`` [flat_max, topspin_min],
        ``topspin`` (topspin_min, inf)."""
        c = self.criteria
        return {
            "flat": [0.0, c.flat_max_rpm],
            "other": [c.flat_max_rpm, c.topspin_min_rpm],
            "topspin": [c.topspin_min_rpm, None],
        }

    def failures(self) -> dict[str, int]:
        """How many serves of the grid fail, by reason (``net``, ``short``, ``long``, ``wide``, ``no-landing``)."""
        return {} if self.reason is None else failure_counts(self.reason)

    def serve(self, i_beta: int, i_alpha: int) -> dict:
        """One serve of the grid as a dict of its quantities."""
        d: dict = {k: float(self.grid(k)[i_beta, i_alpha]) for k in SUMMARY_KEYS}
        d["success"] = bool(self.success[i_beta, i_alpha])
        d["category"] = CATEGORIES[int(self.grid("category")[i_beta, i_alpha])]
        return d

    def optimum(self, category: str) -> dict | None:
        """The seed's optimum serve of a category (module docstring), or None."""
        m = self.mask(category)
        if not m.any():
            return None
        X = self.landing_x
        if category == "flat":
            keys = (X, self.grid("speed"))
        else:
            keys = (self.grid("spin_rpm"), X)
        idx = np.flatnonzero(m.ravel())
        primary, secondary = (k.ravel()[idx] for k in keys)
        best = idx[np.lexsort((secondary, primary))[-1]]
        ib, ia = np.unravel_index(best, m.shape)
        return self.serve(int(ib), int(ia))

    @property
    def peak_spin_alpha(self) -> float:
        """alpha [deg] of the largest spin over the sweep (seed fig 5)."""
        return float(self.alpha_deg[int(np.argmax(self.spin_rpm))])

    def alpha_ranges(self, category: str) -> list[tuple[float, list[float]]]:
        """Per beta, the successful alphas of a category (seed fig 6)."""
        m = self.mask(category)
        return [(float(b), self.alpha_deg[m[i]].tolist()) for i, b in enumerate(self.beta_deg)]

    def widest_beta(self, category: str) -> float | None:
        """beta with the most successful alphas of a category."""
        n = self.mask(category).sum(axis=1)
        return None if n.max() == 0 else float(self.beta_deg[int(np.argmax(n))])

    def to_dict(self) -> dict:
        """The JSON object of ``tennislab serve-window`` (one player): the window, the paper's numbers
        for its players (``published``) and the model caveats."""
        out = {
            "player": {
                "name": self.player.name,
                "impact_height": self.player.impact_height,
                "racket_speed": self.player.racket_speed,
            },
            "criteria": self.mode,
            "n_serves": int(self.success.size),
            "n_success": int(self.success.sum()),
            "summary": self.summary(),
            "spin_bands_rpm": self.bands(),
            "failures": self.failures(),
            "peak_spin_alpha": self.peak_spin_alpha,
            "optimum": {"flat": self.optimum("flat"), "topspin": self.optimum("topspin")},
            "widest_beta": {"flat": self.widest_beta("flat"), "topspin": self.widest_beta("topspin")},
            "alpha_range_by_beta": {c: self.alpha_range_by_beta(c) for c in ("flat", "topspin")},
            "by_alpha": {
                "alpha": self.alpha_deg,
                "speed": self.speed,
                "spin_rpm": self.spin_rpm,
                "contact_time_ms": self.contact_time * 1e3,
                "regime": [("slide", "roll")[int(r)] for r in self.regime],
            },
            "caveats": list(self.caveats),
        }
        if self.player.name in TABLE1:
            out["published"] = {
                "summary": TABLE1[self.player.name],
                "peak_spin_alpha": PEAK_SPIN_ALPHA[self.player.name],
                "optimum": OPTIMUM[self.player.name],
            }
        return jsonable(out)

    def alpha_range_by_beta(self, category: str) -> list[list[float]]:
        """Seed fig 6 as data: [beta, min alpha, max alpha, n] for every beta with successes."""
        return [[b, min(a), max(a), len(a)] for b, a in self.alpha_ranges(category) if a]

    def rows(self) -> list[dict]:
        """One dict per serve of the grid (player, beta, alpha, spin_rpm, speed, landing_x, net_height,
        launch_angle [deg, rpm, m/s, m], success, category): ``to_frame()`` and the CSV."""
        cats = self.grid("category")
        out = []
        for ib in range(self.beta_deg.size):
            for ia in range(self.alpha_deg.size):
                d = {"player": self.player.name, **self.serve(ib, ia)}
                d["category"] = CATEGORIES[int(cats[ib, ia])]
                out.append(d)
        return out


@dataclass(frozen=True)
class ServeWindows(Table):
    """Windows of several players; ``to_dict()`` is ``{"players": {name: window}}`` (``serve-window
    --player all --json``), ``rows()`` every serve of every window."""

    COLUMNS = ServeWindow.COLUMNS
    FRAME_COLUMNS = ServeWindow.FRAME_COLUMNS

    windows: tuple[ServeWindow, ...]

    def to_dict(self) -> dict:
        return {"players": {w.player.name: w.to_dict() for w in self.windows}}

    def rows(self) -> list[dict]:
        return [r for w in self.windows for r in w.rows()]


def angle_grid(step: float, lo: float = 0.0, hi: float = 90.0) -> np.ndarray:
    """Angles lo..hi [deg] inclusive at ``step`` [deg]."""
    step = check_range("step", step, 0.01, 90.0, "deg")
    n = int(np.floor((hi - lo) / step + 1e-9)) + 1
    return lo + step * np.arange(n)


def window(
    player,
    *,
    step: float = 1.0,
    alpha_deg=None,
    beta_deg=None,
    flight: FlightParams | None = None,
    preset: str | None = None,
    impact_params: ImpactParams | None = None,
    criteria: SeedCriteria | None = None,
    steps: int = 400,
    dt: float = 0.0,
    method: str = "rk4",
    target: str | None = None,
    server_y: float = 0.0,
    azimuth_deg: float = 0.0,
    brush_deg: float = 0.0,
    mapper=None,
) -> ServeWindow:
    """Simulate every serve of the alpha x beta grid (default 0-90 deg at ``step``) for ``player``.

    ``target`` None: the seed's 2-D criteria.  ``target="deuce"|"ad"``: 3-D serves from
    (baseline, ``server_y``) with the face azimuth and brush angle [deg], judged by the real
    net and service box (:mod:`tennislab.serve.single`).

    ``flight``/``impact_params`` default to the ``standard`` physics of every command (``preset="seed000"``:
    the paper's constants) and the converged impact scheme; ``steps``/``dt``/``method`` set the impact
    integration (:func:`impact_batch`).
    ``mapper(fn, inputs) -> outputs`` runs :func:`window_chunk` (default: in process);
    pass e.g. ``functools.partial(tennislab.batch.map_chunks, scheduler="processes")``.
    """
    setup = make_setup(
        player,
        flight=flight,
        preset=preset,
        impact_params=impact_params,
        criteria=criteria,
        target=target,
        azimuth_deg=azimuth_deg,
        brush_deg=brush_deg,
        server_y=server_y,
        dt=dt,
        method=method,
        steps=steps,
    )
    a = angle_grid(step) if alpha_deg is None else alpha_deg
    b = angle_grid(step) if beta_deg is None else beta_deg
    return window_of_setup(setup, a, b, azimuth_deg, mapper)


def window_of_setup(setup: Setup, alpha_deg, beta_deg, azimuth_deg: float = 0.0, mapper=None) -> ServeWindow:
    """:func:`window` of a :class:`~tennislab.serve.pipeline.Setup` (checked by ``make_setup``; a window's
    own is ``ServeWindow.setup``) over the angles ``alpha_deg`` x ``beta_deg`` [deg] at the face azimuth
    ``azimuth_deg`` [deg]."""
    a = np.asarray(alpha_deg, float)
    b = np.asarray(beta_deg, float)
    if a.size == 0 or b.size == 0:
        raise InputError("alpha, beta: empty grid")
    if np.any(np.abs(a) > 90):
        raise InputError("alpha: outside the allowed range [-90, 90] deg")
    A = np.radians(np.clip(a, -89.999, 89.999))  # alpha = 90 deg: no normal approach; use 89.999
    imp = impacts(setup, A)  # stage 1 once per alpha: without a toss the impact does not depend on beta
    B = np.radians(b)
    BB, _ = np.meshgrid(B, A, indexing="ij")
    psi = float(np.radians(azimuth_deg))
    inputs = {
        "v_n": np.broadcast_to(imp["v_n"][None, :], BB.shape).ravel().copy(),
        "v_t": np.broadcast_to(imp["v_t"][None, :], BB.shape).ravel().copy(),
        "omega": np.broadcast_to(imp["omega"][None, :], BB.shape).ravel().copy(),
        "beta": BB.ravel().copy(),
        "azimuth": np.full(BB.size, psi),
    }
    fn = functools.partial(window_chunk, setup=setup)
    out = fn(inputs) if mapper is None else mapper(fn, inputs)
    shape = BB.shape
    spin = imp["omega"] / RPM
    vel, _ = launch_3d(imp["v_n"][None, :], imp["v_t"][None, :], imp["omega"][None, :], B[:, None], psi, setup.brush)
    gamma = np.degrees(np.arctan2(vel[..., 2], np.hypot(vel[..., 0], vel[..., 1])))
    return ServeWindow(
        setup.player,
        a,
        b,
        imp["speed"],
        spin,
        imp["contact_time"],
        imp["regime"].astype(int),
        gamma,
        np.asarray(out["landing_x"]).reshape(shape),
        np.asarray(out["net_height"]).reshape(shape),
        np.asarray(out["success"]).astype(bool).reshape(shape),
        np.broadcast_to(setup.criteria.category(spin)[None, :], shape).copy(),
        setup.criteria,
        setup.mode,
        setup.caveats(),
        np.asarray(out["reason"]).astype(np.int8).reshape(shape),
        setup,
        float(azimuth_deg),
    )


def windows(players, **kw) -> ServeWindows:
    """:func:`window` of each of ``players`` (names or profiles; ``"all"`` = the paper's three), same options."""
    names = list(SEED_PLAYERS) if players == "all" else list(players)
    if not names:
        raise InputError("players: give at least one player")
    return ServeWindows(tuple(window(p, **kw) for p in names))


def deepest_serve(win: ServeWindow, category: str = "topspin") -> dict | None:
    """The successful serve of ``category`` deepest inside the window: the most grid steps (in alpha
    or beta, chessboard distance) from any serve that fails; ties by spin, then speed.  None if none."""
    m = win.mask(category)
    if not m.any():
        return None
    depth = distance_transform_cdt(np.pad(win.success, 1), metric="chessboard")[1:-1, 1:-1]
    idx = np.flatnonzero(m.ravel())
    keys = (win.grid("speed").ravel()[idx], win.grid("spin_rpm").ravel()[idx], depth.ravel()[idx])
    best = idx[np.lexsort(keys)[-1]]
    ib, ia = np.unravel_index(best, m.shape)
    d = win.serve(int(ib), int(ia))
    step = float(np.min(np.diff(win.alpha_deg))) if win.alpha_deg.size > 1 else 0.0
    d["margin_deg"] = float(depth[ib, ia] - 1) * step
    return d


@dataclass(frozen=True)
class DefaultServe(Result):
    """A serve that goes in for a player with the most room for error (:func:`default_serve`).

    Angles [deg], SI otherwise.  Read as attributes or, as before, by key (``d["impact_angle"]``);
    ``to_dict()`` is the dict :func:`default_serve` used to return.
    """

    player: PlayerProfile
    impact_angle: float  #: alpha [deg]
    face_angle: float  #: beta [deg]
    category: str  #: flat, topspin or other
    margin_deg: float  #: every serve within this many degrees of alpha and beta also goes in [deg]
    speed: float  #: ball speed after impact [m/s]
    spin_rpm: float  #: [rpm]

    _KEYS = ("impact_angle", "face_angle", "category", "margin_deg", "speed", "spin_rpm")

    def to_dict(self) -> dict:
        return jsonable({k: getattr(self, k) for k in self._KEYS})

    def __getitem__(self, key: str):
        if key not in self._KEYS:
            raise KeyError(key)
        return getattr(self, key)

    def keys(self):
        return self._KEYS


@functools.lru_cache(maxsize=32)
def _default_serve(player: PlayerProfile) -> DefaultServe:
    w = window(player, step=1.0)
    best = deepest_serve(w, "topspin") or deepest_serve(w, "flat") or deepest_serve(w, "other")
    if best is None:
        raise InputError(f"player: no serve of {player.name} goes in (impact height or racket speed too small)")
    return DefaultServe(
        player=w.player,
        impact_angle=best["alpha"],
        face_angle=best["beta"],
        category=best["category"],
        margin_deg=best["margin_deg"],
        speed=best["speed"],
        spin_rpm=best["spin_rpm"],
    )


def default_serve(player) -> DefaultServe:
    """A serve that goes in for ``player`` with the most room for error: the topspin serve deepest
    inside the player's window (the serve workflows' default physics and the paper's criteria, 1 deg
    grid; :func:`deepest_serve`).  A :class:`DefaultServe`: ``impact_angle``, ``face_angle`` [deg],
    ``category``, ``margin_deg`` (every serve within that many degrees of alpha and beta also goes in),
    ``speed`` [m/s], ``spin_rpm``."""
    return _default_serve(make_setup(player).player)
