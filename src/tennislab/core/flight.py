"""Ball flight: one right-hand side, one description of the events, two integration paths.

* :func:`fly_dense` - one trajectory with SciPy ``solve_ivp`` (DOP853 at rtol 1e-10
  by default) and dense output, for plots; at its default tolerance it is the
  accuracy reference the tests use.
* :func:`fly_batch` - N initial states integrated in parallel by the compiled
  Dormand-Prince kernel of :mod:`tennislab.core.integrators`, returning an
  event table (:class:`FlightTable`).

Both call :func:`tennislab.core.dynamics.derivative` and read the same event
descriptions (:mod:`tennislab.core.events`): first ground contact (ball centre
at height r), first net-plane crossing, apex and, with
``FlightParams(net_obstacle=True)``, the ball meeting the net.

Guard rails (issue 16): a launch faster than :data:`MAX_SPEED_MS`, spinning faster
than :data:`MAX_SPIN_RPM`, outside :data:`MAX_DISTANCE_M` or below the ground is
refused (:func:`fly_dense`: :class:`~tennislab.errors.InputError` naming the
parameter and the allowed range; :func:`fly_batch`: the row's status code,
docs/flight.md); every integration is bounded (:data:`MAX_RHS_EVALS` evaluations
of the right-hand side for SciPy, :data:`MAX_STEPS` step attempts, rejected ones
included, per compiled trajectory); a non-finite state is an error, never an
answer.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from tennislab.core._net import net_blocks
from tennislab.core.aero import DEFAULT_AERO, AeroModel, get_aero_model, inline_tag
from tennislab.core.atmosphere import Atmosphere
from tennislab.core.ball import Ball
from tennislab.core.court import ITF_COURT, Court
from tennislab.core.dynamics import derivative_call
from tennislab.core.events import (
    ALWAYS,
    COL,
    COLUMNS,
    DEFAULT_NET,
    FLIGHT_EVENTS,
    IF_NET,
    NCOLS,
    NET_MODES,
    NET_RESULTS,
    OBSTACLE_EVENTS,
    STATUS_NAMES,
    STATUS_OK,
    Apex,
    Event,
    Landing,
    NetContact,
    NetCrossing,
    event_array,
)
from tennislab.core.integrators import (
    KernelConsts,
    batch_kernel,
    batch_kernel_fp,
    serial_kernel,
    serial_kernel_fp,
)
from tennislab.core.lockstep import (
    lockstep_kernel,
    lockstep_kernel_fp,
    lockstep_serial_kernel,
    lockstep_serial_kernel_fp,
    lockstep_suits,
)
from tennislab.core.names import PRESETS  # the named base sets (plain data, for --help)
from tennislab.errors import InputError, check_range, check_vector
from tennislab.results import OldAsDict
from tennislab.units import RPM

# The guard rails of every flight (the one statement; tennislab.trajectory re-exports them):
#: Fastest launch accepted [m/s]: the fastest recorded serves are about 263 km/h = 73 m/s (ATP, 2012);
#: 100 m/s leaves room for studies beyond them and refuses numbers no racket or machine produces.
MAX_SPEED_MS = 100.0
#: Highest spin rate accepted [rpm]: the topspin of elite forehands reaches about 5,000 rpm (Kelley et
#: al. 2008, Sports Eng.; reference-data.md); 10,000 rpm is twice that.
MAX_SPIN_RPM = 10_000.0
_MAX_SPIN = MAX_SPIN_RPM * RPM  # [rad/s]
#: Relative round-off allowed at the speed and spin limits: a speed of exactly 100 m/s given as a
#: speed and an elevation comes back from its components as 100.00000000000001
_LIMIT_SLACK = 1.0 + 1e-12
#: Largest |x|, |y| and z of a launch position [m] (a court is 23.77 x 10.97 m)
MAX_DISTANCE_M = 1000.0
#: Most step attempts (accepted and rejected) of one compiled trajectory; a mixed shot takes ~8-30
MAX_STEPS = 100_000
#: Most evaluations of the right-hand side in one :func:`fly_dense` (a flight takes ~1,000-3,000 at rtol 1e-10)
MAX_RHS_EVALS = 200_000


@dataclass(frozen=True)
class FlightParams:
    """Everything the flight physics needs besides the initial state.

    Attributes
    ----------
    ball : :class:`Ball` (mass [kg], radius [m])
    atmosphere : :class:`Atmosphere` (density [kg/m^3], gravity [m/s^2], wind [m/s])
    aero : :class:`AeroModel` (default :data:`~tennislab.core.aero.DEFAULT_AERO`)
    court : :class:`Court` (net profile for the net events)
    spin_decay : exponential spin-decay rate [1/s], 0-10; 0 = off (default)
    t_max : longest flight integrated [s]
    net_obstacle : False (default): the ball passes through the net plane and the
        crossing says whether it cleared the net (``net.result``); True: a ball
        meeting the net (mesh or tape) stops there (status ``STATUS_NET``, the
        ``net_hit_*`` columns; :mod:`tennislab.core.events`)
    """

    ball: Ball = field(default_factory=Ball)
    atmosphere: Atmosphere = field(default_factory=Atmosphere)
    aero: AeroModel = field(default_factory=lambda: get_aero_model(DEFAULT_AERO))
    court: Court = ITF_COURT
    spin_decay: float = 0.0
    t_max: float = 20.0
    net_obstacle: bool = False

    def __post_init__(self):
        # measured decay is ~0.05-0.1 /s (Cross & Lindsey 2014, dynamics.py); 10 /s halves the spin in 0.07 s
        check_range("spin_decay", self.spin_decay, 0.0, 10.0, "1/s")
        check_range("t_max", self.t_max, 0.0, 1000.0, "s", lo_open=True)
        if not isinstance(self.net_obstacle, (bool, np.bool_)):
            raise InputError(f"net_obstacle: expected true or false, got {self.net_obstacle!r}")

    @classmethod
    def from_options(
        cls,
        aero=None,
        cd=None,
        cl=None,
        aero_table=None,
        mass=None,
        radius=None,
        air_density=None,
        gravity=None,
        wind=None,
        spin_decay=None,
        inertia_factor=None,
        court: Court | None = None,
        t_max=None,
        net_obstacle=None,
        preset: str = "standard",
    ) -> FlightParams:
        """The one builder of flight physics from plain options (every front-end calls it).

        ``preset`` names a base set (:data:`PRESETS`: ``standard`` = ITF ball, standard
        air, the default aero model; ``seed000`` = seed 000's constants; ``seed002`` =
        the launcher paper's aero model); every option that is not ``None`` overrides it.
        ``aero`` is a registered name, an :class:`AeroModel` or a callable
        ``f(v, w) -> (C_D, C_L)``; ``cd``/``cl`` go to its factory; ``aero_table`` is
        ``(speed [m/s], spin [rad/s], cd, cl)`` arrays for ``aero="table"`` (read from a
        CSV at the edge by :func:`tennislab.io.aero_table.read_aero_table`);
        ``net_obstacle=True`` stops a ball that meets the net (default: it passes through).
        """
        if preset not in PRESETS:
            raise InputError(f"preset: unknown physics preset {preset!r}; allowed: {', '.join(sorted(PRESETS))}")
        base = dict(PRESETS[preset])
        given = dict(
            aero=aero,
            mass=mass,
            radius=radius,
            air_density=air_density,
            gravity=gravity,
            wind=None if wind is None else tuple(wind),
            spin_decay=spin_decay,
            inertia_factor=inertia_factor,
            t_max=t_max,
            net_obstacle=net_obstacle,
        )
        base.update({k: v for k, v in given.items() if v is not None})
        model = base.pop("aero", None)
        if isinstance(model, AeroModel):
            if cd is not None or cl is not None or aero_table is not None:
                raise InputError("aero: cd, cl and aero_table cannot be applied to an already built model")
        elif model == "table" or (model is None and aero_table is not None):
            if aero_table is None:
                raise InputError("aero_table: the table model needs a table (speed, spin, cd, cl)")
            if cd is not None or cl is not None:
                raise InputError("cd: the table model takes its coefficients from the table, not cd/cl")
            sp, w, c_d, c_l = aero_table
            model = get_aero_model("table", speed=sp, spin=w, cd=c_d, cl=c_l)
        else:
            if aero_table is not None:
                raise InputError(f"aero_table: a table needs aero='table', not {model!r}")
            model = get_aero_model(model, cd=cd, cl=cl)
        ball_kw = {k: base.pop(k) for k in ("mass", "radius", "inertia_factor") if k in base}
        atm_kw = {
            k2: base.pop(k)
            for k, k2 in (("air_density", "density"), ("gravity", "gravity"), ("wind", "wind"))
            if k in base
        }
        return cls(
            ball=Ball(**ball_kw),
            atmosphere=Atmosphere(**atm_kw),
            aero=model,
            court=court or ITF_COURT,
            **base,
        )

    def to_dict(self) -> dict:
        """These parameters as JSON-ready plain data; :meth:`from_dict` rebuilds them.

        Keys are :meth:`from_options`'s (SI, docs/conventions.md): ``aero`` (the model's name) and
        ``aero_options`` (its factory's arguments, ``{}`` = the model's defaults; a non-finite number
        as the string ``"inf"``), ``mass`` [kg], ``radius`` [m], ``inertia_factor`` [-],
        ``air_density`` [kg/m^3], ``gravity`` [m/s^2], ``wind`` [m/s], ``spin_decay`` [1/s],
        ``t_max`` [s], ``net_obstacle`` and ``court`` (its dimensions [m]).  It is what every result
        reports as its ``physics`` and what a worker process is given: the dict is plain data (it
        pickles), and so is a ``FlightParams`` itself for a model built by name.  A model given as a
        Python callable has no options (``aero_options`` is ``None``) and cannot be rebuilt.
        """
        opts = self.aero.options
        return {
            "aero": self.aero.name,
            "aero_options": None if opts is None else {k: _plain_option(v) for k, v in opts.items()},
            "mass": self.ball.mass,
            "radius": self.ball.radius,
            "inertia_factor": self.ball.inertia_factor,
            "air_density": self.atmosphere.density,
            "gravity": self.atmosphere.gravity,
            "wind": list(self.atmosphere.wind),
            "spin_decay": self.spin_decay,
            "t_max": self.t_max,
            "net_obstacle": bool(self.net_obstacle),
            "court": {f.name: getattr(self.court, f.name) for f in dataclasses.fields(self.court)},
        }

    @classmethod
    def from_dict(cls, d: dict) -> FlightParams:
        """The parameters of a :meth:`to_dict` dict (missing keys keep their defaults).

        Raises :class:`InputError` naming an unknown key, a model that cannot be rebuilt from its
        name (a callable), or a value out of its range.
        """
        if not isinstance(d, dict):
            raise InputError(f"physics: expected a dict of physics settings, got {type(d).__name__}")
        unknown = sorted(set(d) - _DICT_KEYS)
        if unknown:
            raise InputError(f"{unknown[0]}: unknown physics setting; allowed: {', '.join(sorted(_DICT_KEYS))}")
        opts = d.get("aero_options", {})
        if opts is None:
            raise InputError(f"aero: model {d.get('aero')!r} was given as a callable and cannot be rebuilt by name")
        if not isinstance(opts, dict):
            raise InputError("aero_options: expected a dict of the aero model's arguments")
        aero = get_aero_model(d.get("aero"), **{k: _option_value(v) for k, v in opts.items()})
        court = d.get("court")
        if court is not None and not isinstance(court, dict):
            raise InputError("court: expected a dict of court dimensions [m]")
        bad = sorted(set(court or {}) - {f.name for f in dataclasses.fields(Court)})
        if bad:
            raise InputError(f"court: unknown dimension {bad[0]!r}")
        given = {k: d[k] for k in ("mass", "radius", "inertia_factor") if k in d}
        atm: dict = {k2: d[k] for k, k2 in (("air_density", "density"), ("gravity", "gravity")) if k in d}
        if "wind" in d:
            atm["wind"] = tuple(d["wind"])
        rest = {k: d[k] for k in ("spin_decay", "t_max", "net_obstacle") if k in d}
        return cls(
            ball=Ball(**given),
            atmosphere=Atmosphere(**atm),
            aero=aero,
            court=ITF_COURT if court is None else Court(**court),
            **rest,
        )

    @property
    def k(self) -> float:
        """Aerodynamic constant 1/2 rho A / m [1/m]."""
        return 0.5 * self.atmosphere.density * self.ball.area / self.ball.mass

    def events(self) -> tuple[Event, ...]:
        """The events of a flight with these parameters (:mod:`tennislab.core.events`)."""
        return OBSTACLE_EVENTS if self.net_obstacle else FLIGHT_EVENTS

    def consts(self, rtol: float, atol: float) -> KernelConsts:
        """The named constants of the compiled kernel (:class:`~tennislab.core.integrators.KernelConsts`)."""
        w = self.atmosphere.wind
        c = self.court
        return KernelConsts(
            k=self.k,
            gravity=self.atmosphere.gravity,
            radius=self.ball.radius,
            wind_x=float(w[0]),
            wind_y=float(w[1]),
            wind_z=float(w[2]),
            spin_decay=float(self.spin_decay),
            net_center_height=c.net_center_height,
            net_post_height=c.net_post_height,
            net_y_post=c.y_post,
            t_max=float(self.t_max),
            rtol=float(rtol),
            atol=float(atol),
            max_speed=MAX_SPEED_MS * _LIMIT_SLACK,
            max_spin=_MAX_SPIN * _LIMIT_SLACK,
            max_position=MAX_DISTANCE_M,
            max_steps=float(MAX_STEPS),
        )

    def rhs(self, max_evals: int | None = None):
        """The right-hand side f(t, y) for SciPy, calling the shared compiled derivative.

        With ``max_evals``, the call after that many raises :class:`EvaluationLimit`.
        """
        k, g, r = self.k, self.atmosphere.gravity, self.ball.radius
        wx, wy, wz = self.atmosphere.wind
        kern, p, lam = self.aero.kernel, self.aero.params, self.spin_decay
        limit = math.inf if max_evals is None else int(max_evals)
        count = [0]

        def f(t, y):
            count[0] += 1
            if count[0] > limit:
                raise EvaluationLimit(limit)
            out = np.empty(9)
            derivative_call(np.ascontiguousarray(y, dtype=np.float64), out, kern, p, k, k, g, r, wx, wy, wz, lam)
            return out

        return f


#: the keys of :meth:`FlightParams.to_dict`
_DICT_KEYS = frozenset(
    ("aero", "aero_options", "mass", "radius", "inertia_factor", "air_density", "gravity", "wind")
    + ("spin_decay", "t_max", "net_obstacle", "court")
)


def _plain_option(v):
    """An aero factory's argument as JSON: arrays as lists, a non-finite number as a string."""
    if isinstance(v, np.ndarray):
        return v.tolist()
    if isinstance(v, (float, np.floating)) and not math.isfinite(v):
        return str(float(v))
    return v


def _option_value(v):
    """The inverse of :func:`_plain_option` for the numbers (``"inf"`` -> inf)."""
    if isinstance(v, str) and v in ("inf", "-inf"):
        return float(v)
    return v


def with_net(params: FlightParams | None, net: str = DEFAULT_NET) -> FlightParams:
    """``params`` (default :class:`FlightParams`) with the net treated as ``net`` (:data:`NET_MODES`)."""
    if net not in NET_MODES:
        raise InputError(f"net: unknown mode {net!r}; allowed: {', '.join(NET_MODES)}")
    return dataclasses.replace(params or FlightParams(), net_obstacle=(net == "obstacle"))


class EvaluationLimit(RuntimeError):
    """Raised by :meth:`FlightParams.rhs` past its evaluation budget (caught by :func:`fly_dense`)."""


def initial_state(position, velocity, spin=(0.0, 0.0, 0.0)) -> np.ndarray:
    """State vector (9,) from position [m], velocity [m/s] and spin vector [rad/s]."""
    return np.array(
        check_vector("position", position) + check_vector("velocity", velocity) + check_vector("spin", spin),
        dtype=np.float64,
    )


def start_side(y0) -> float:
    """The half a ball starts in: -1 (x < 0), +1 (x > 0); on the net plane, the half it moves away from."""
    if y0[0] < 0:
        return -1.0
    if y0[0] > 0:
        return 1.0
    return -math.copysign(1.0, y0[3])


def check_start(y0: np.ndarray, params: FlightParams) -> None:
    """Refuse a launch outside the physical range (:class:`InputError` naming the parameter and the range).

    The same limits mark rows of :func:`fly_batch` (status codes) instead of raising.
    """
    r = params.ball.radius
    lim = MAX_DISTANCE_M
    for i, name in ((0, "x"), (1, "y")):
        if abs(y0[i]) > lim:
            raise InputError(f"position: {name} = {y0[i]:g} m is outside the allowed range [-{lim:g}, {lim:g}] m")
    if not r <= y0[2] <= lim:
        raise InputError(
            f"position: z = {y0[2]:g} m is outside the allowed range [{r:g}, {lim:g}] m "
            "(the ball centre at least one radius above the ground)"
        )
    speed = math.hypot(*y0[3:6])  # (no overflow for huge components)
    if speed > MAX_SPEED_MS * _LIMIT_SLACK:
        raise InputError(f"velocity: speed {speed:g} m/s is outside the allowed range [0, {MAX_SPEED_MS:g}] m/s")
    spin = math.hypot(*y0[6:9])
    if spin > _MAX_SPIN * _LIMIT_SLACK:
        raise InputError(f"spin: {spin / RPM:g} rpm is outside the allowed range [0, {MAX_SPIN_RPM:g}] rpm")
    # (the events' own rule: past the mesh event, or on the plane within r of the cord)
    inside = (abs(y0[0]) < r and _blocks(y0, params)) or (y0[0] == 0 and _blocks(y0, params, 1.0))
    if params.net_obstacle and inside:
        raise InputError(
            f"position: a ball at x = {y0[0]:g} m, z = {y0[2]:g} m overlaps the net "
            f"(|x| < r = {r:g} m at or below the net's top); start it clear of the net"
        )


def _blocks(y, params: FlightParams, margin: float = 0.0) -> bool:
    """Whether a ball centred at ``y`` is at most ``margin`` radii above the net's top, between the posts."""
    c = params.court
    z = float(y[2]) - margin * params.ball.radius
    return bool(net_blocks(float(y[1]), z, c.net_center_height, c.net_post_height, c.y_post))


def _stops(ev: Event, y, params: FlightParams) -> bool:
    """Whether ``ev`` ends the flight when it happens at state ``y`` (as the kernel's ``_stops_at``)."""
    if ev.stop == ALWAYS:
        return True
    return ev.stop == IF_NET and _blocks(y, params, ev.net_margin)


def _scipy_event(index: int, target: float, direction: float, terminal: bool, t0: float, armed: bool):
    """A :class:`~tennislab.core.events.Event` as a ``solve_ivp`` event function.

    ``armed``: the component starts on its target moving away (a flight starting
    on the ground going up); while it is still exactly on the target (at t0, and
    after a first step too short to move it by one ulp) the function reports a
    value just on the near side, so that SciPy brackets the real crossing, not
    the start.  (A closure, not a callable object: SciPy calls it at every step.)
    """
    if armed:
        start = -direction * 1e-300

        def g(t, y):
            v = y[index] - target
            return v if (t > t0 and v != 0.0) else start

    else:

        def g(t, y):
            return y[index] - target

    setattr(g, "terminal", terminal)  # noqa: B010 - the attributes solve_ivp reads
    setattr(g, "direction", direction)  # noqa: B010
    return g


class _Constant:
    """Dense output of a flight that ends where it starts."""

    def __init__(self, y0):
        self.y0 = np.asarray(y0, dtype=float)

    def __call__(self, t):
        t = np.asarray(t, dtype=float)
        if t.ndim == 0:
            return self.y0.copy()
        return np.repeat(self.y0[:, None], t.size, axis=1)


@dataclass(frozen=True)
class Trajectory:
    """One integrated flight: solver steps, dense solution and events.

    ``net_contact`` is where the ball met the net (``net_obstacle=True`` only;
    the flight ends there and ``landing`` is None).
    """

    t: np.ndarray
    y: np.ndarray
    sol: object = field(repr=False)
    landing: Landing | None
    net: NetCrossing
    apex: Apex
    params: FlightParams = field(repr=False)
    net_contact: NetContact | None = None

    def sample(self, n: int = 300, t_end: float | None = None):
        """(t, states) at n evenly spaced times from 0 to landing (or ``t_end``)."""
        te = self.t[-1] if t_end is None else t_end
        ts = np.linspace(self.t[0], te, n)
        return ts, self.sol(ts).T  # type: ignore[operator]


def _net_crossing(t: float | None, yev, params: FlightParams) -> NetCrossing:
    if t is None:
        nan = float("nan")
        return NetCrossing(nan, nan, nan, nan, nan, "none")
    r = params.ball.radius
    hn = params.court.net_height(yev[1])
    clr = yev[2] - hn - r
    return NetCrossing(float(t), float(yev[1]), float(yev[2]), float(hn), float(clr), "net" if clr < 0 else "over")


def fly_dense(
    position,
    velocity,
    spin=(0.0, 0.0, 0.0),
    params: FlightParams | None = None,
    *,
    method: str = "DOP853",
    rtol: float = 1e-10,
    atol: float = 1e-12,
    t0: float = 0.0,
) -> Trajectory:
    """Integrate one flight to its first ground contact (or the net, as an obstacle) with SciPy ``solve_ivp``.

    Parameters
    ----------
    position : (x, y, z) of the ball centre [m]; r <= z <= 1000 m, |x|, |y| <= 1000 m
    velocity : (vx, vy, vz) [m/s]; speed <= :data:`MAX_SPEED_MS`
    spin : spin vector omega [rad/s] (right-hand rule: topspin on a ball moving
        along +x is omega along +y, backspin along -y; see docs/conventions.md);
        rate <= :data:`MAX_SPIN_RPM`
    params : :class:`FlightParams` (defaults if None)
    method, rtol, atol : SciPy solver settings (default DOP853, 1e-10, 1e-12)
    t0 : start time [s] (used when chaining flights after bounces)

    Raises :class:`InputError` for a launch outside those ranges, and when the
    integration fails or does not finish within :data:`MAX_RHS_EVALS` evaluations.
    """
    params = params or FlightParams()
    y0 = initial_state(position, velocity, spin)
    check_start(y0, params)
    r = params.ball.radius
    side = start_side(y0)
    f = params.rhs(MAX_RHS_EVALS)
    slope = f(t0, y0)
    # the events at the start (events.py): past -> at the start; on the target moving away -> armed
    occ: dict[str, tuple[float, np.ndarray]] = {}
    watched: list[tuple[Event, Callable]] = []
    stop_ev: Event | None = None
    for ev in params.events():
        tg, d, i = ev.target_value(r, side), ev.direction_value(side), ev.index
        f0 = y0[i] - tg
        if d * f0 < 0 or (f0 == 0 and d * slope[i] < 0):
            watched.append((ev, _scipy_event(i, tg, d, ev.stop == ALWAYS, t0, armed=d * f0 >= 0)))
        elif _stops(ev, y0, params):
            if d * f0 > 0:  # (check_start refuses these with a clearer message)
                raise InputError(f"position: the launch is beyond the {ev.name} event")
            stop_ev = stop_ev or ev
            occ[ev.prefix] = (t0, y0.copy())
        elif ev.stop != IF_NET:
            occ[ev.prefix] = (t0, y0.copy())
    if stop_ev is not None:  # ends where it starts (a ball on the ground, not going up)
        ts, ys, sol = np.array([t0]), y0[None, :].copy(), _Constant(y0)
    else:
        try:
            from scipy.integrate import solve_ivp  # (here: SciPy loads only for a dense flight)

            res = solve_ivp(
                f,
                (t0, t0 + params.t_max),
                y0,
                method=method,
                rtol=rtol,
                atol=atol,
                dense_output=True,
                events=[se for _, se in watched],
            )
        except EvaluationLimit:
            raise InputError(
                f"flight: no result within {MAX_RHS_EVALS:,} evaluations of the equations of motion "
                "(inputs too extreme for the integrator)"
            ) from None
        if res.status < 0:
            raise InputError(f"flight: integration failed ({res.message})")
        ts, ys, sol = res.t, res.y.T, res.sol
        first = [
            (ev, float(res.t_events[k][0]), res.y_events[k][0]) if len(res.t_events[k]) else (ev, math.inf, None)
            for k, (ev, _) in enumerate(watched)
        ]
        t_stop = math.inf
        for ev, te, ye in first:
            if ye is not None and te < t_stop and _stops(ev, ye, params):
                t_stop, stop_ev = te, ev
        for ev, te, ye in first:
            if ye is not None and te <= t_stop and (ev.stop != IF_NET or ev is stop_ev):
                occ[ev.prefix] = (te, np.asarray(ye, dtype=float).copy())
        if stop_ev is not None and stop_ev.stop == IF_NET:  # the flight ends at the net: cut the steps there
            keep = ts < t_stop
            ts = np.append(ts[keep], t_stop)
            ys = np.vstack([ys[keep], occ[stop_ev.prefix][1]])
    if not (np.all(np.isfinite(ys)) and all(np.all(np.isfinite(v)) for _, v in occ.values())):
        raise InputError("flight: the integration produced a non-finite state (inputs too extreme)")
    return _trajectory(ts, ys, sol, occ, params)


def _trajectory(ts, ys, sol, occ: dict, params: FlightParams) -> Trajectory:
    """The :class:`Trajectory` of recorded events ``occ`` (event column prefix -> (t, state))."""
    landing = None
    if "land" in occ:
        t, s = occ["land"]
        landing = Landing(t, s[0:3].copy(), s[3:6].copy(), s[6:9].copy())
    contact = None
    if "net_hit" in occ:
        t, s = occ["net_hit"]
        part = "tape" if abs(s[0]) < 0.5 * params.ball.radius else "mesh"
        contact = NetContact(t, s[0:3].copy(), s[3:6].copy(), s[6:9].copy(), part)
        net = _net_crossing(t, s, params)
    elif "net" in occ:
        t, s = occ["net"]
        net = _net_crossing(t, s, params)
    else:
        net = _net_crossing(None, None, params)
    if "apex" in occ:
        t, s = occ["apex"]
        apex = Apex(t, s[0:3].copy())
    else:  # no apex before the end: the highest point is the end (still rising)
        apex = Apex(float(ts[-1]), ys[-1, 0:3].copy())
    return Trajectory(ts, ys, sol, landing, net, apex, params, contact)


@dataclass(frozen=True)
class FlightTable(OldAsDict):
    """Event table of a batch: one row per initial state, columns :data:`events.COLUMNS`.

    ``table["land_x"]`` gives a column; :attr:`clearance`, :attr:`net_result` and
    :attr:`status_name` are derived.  ``status`` (:mod:`tennislab.core.events`):
    0 landed, 1 no landing within ``t_max``, 2 bad start (non-finite, below the
    ground, inside the net), 3 stopped by the net (``net_obstacle=True``),
    4 launch out of range (speed > :data:`MAX_SPEED_MS`, spin > :data:`MAX_SPIN_RPM`,
    position beyond :data:`MAX_DISTANCE_M`), 5 integration failed (step limit,
    non-finite state).
    """

    data: np.ndarray
    radius: float

    def __getitem__(self, name: str) -> np.ndarray:
        return self.data[:, COL[name]]

    def __len__(self) -> int:
        return self.data.shape[0]

    @property
    def clearance(self) -> np.ndarray:
        """Net clearance z - h_net - r [m] (NaN where the ball never reaches x = 0)."""
        return self["net_z"] - self["net_h"] - self.radius

    @property
    def net_result(self) -> np.ndarray:
        """``none``, ``over`` or ``net`` per row."""
        return np.array(NET_RESULTS)[self["net_status"].astype(int)]

    @property
    def status_name(self) -> np.ndarray:
        """The status of each row in words (``landed``, ``net``, ``out of range``, ...)."""
        return np.array(STATUS_NAMES)[self["status"].astype(int)]

    @property
    def ok(self) -> np.ndarray:
        return self["status"] == STATUS_OK

    def to_dict(self) -> dict[str, np.ndarray]:
        return {c: self.data[:, i] for i, c in enumerate(COLUMNS)}


#: the flight kernels of :func:`fly_batch`
KERNELS = ("auto", "lockstep", "per-shot")
_KERNELS = {
    (True, True): lockstep_kernel,
    (True, False): lockstep_serial_kernel,
    (False, True): batch_kernel,
    (False, False): serial_kernel,
}
_KERNELS_FP = {
    (True, True): lockstep_kernel_fp,
    (True, False): lockstep_serial_kernel_fp,
    (False, True): batch_kernel_fp,
    (False, False): serial_kernel_fp,
}


def fly_batch(
    states,
    params: FlightParams | None = None,
    *,
    rtol: float | None = None,
    atol: float | None = None,
    parallel: bool = True,
    kernel: str = "auto",
) -> FlightTable:
    """Integrate N flights (states (N, 9): position, velocity, spin) to first ground contact.

    Compiled with Numba (``parallel=True`` uses all cores via ``prange``).  The
    default tolerance (rtol = atol = the aero model's ``batch_tol``: 2e-7, or 2e-8 for the
    piecewise-linear curves of ``tennislab2026``; the steps in the blend zone of a capped lift such as
    ``choppin2018``'s are held to a tighter error, :data:`~tennislab.core.aero.CAP_ZONE`) keeps landing points within
    0.01 mm of the reference :func:`fly_dense` at rtol 1e-10 for serves, groundstrokes
    and lobs with up to 6000 rpm about any axis, for every built-in aero model
    (docs/flight.md; benchmarks/bench_flight_accuracy.py; tests/core/test_flight_accuracy.py).

    ``kernel``: ``"lockstep"`` advances the shots :data:`~tennislab.core.lockstep.LANES` at a time
    in SIMD lanes (:mod:`tennislab.core.lockstep`), ``"per-shot"`` one after the other
    (:func:`~tennislab.core.integrators.integrate_one`, its reference); both give the same table to
    round-off (1e-9 m for the smooth models).  ``"auto"`` (default) takes the lockstep kernel where it
    is faster (:func:`~tennislab.core.lockstep.lockstep_suits`: ``constant``, ``stepanek1988`` and the
    linear-lift models such as the default; docs/benchmarks.md) and the per-shot one otherwise (a
    user's kernel, called through a pointer no SIMD lane can share; the table and
    curve models, whose cell search is a loop).

    Rows outside the physical range are not refused but marked (``status``, see
    :class:`FlightTable`), so that one bad row never stops millions of good ones;
    a malformed ``states`` array or bad parameters raise :class:`InputError`.
    """
    params = params or FlightParams()
    rtol = params.aero.batch_tol if rtol is None else rtol
    atol = params.aero.batch_tol if atol is None else atol
    check_range("rtol", rtol, 1e-14, 1e-2)
    check_range("atol", atol, 1e-16, 1e-2)
    try:
        s = np.ascontiguousarray(np.asarray(states, dtype=np.float64))
    except (TypeError, ValueError):
        raise InputError("states: expected an (N, 9) array of numbers") from None
    if s.ndim == 1:
        s = s.reshape(1, -1)
    if s.ndim != 2 or s.shape[1] != 9:
        raise InputError(f"states: expected an (N, 9) array, got shape {np.shape(states)}")
    out = np.empty((s.shape[0], NCOLS))
    if kernel not in KERNELS:
        raise InputError(f"kernel: unknown flight kernel {kernel!r}; allowed: {', '.join(KERNELS)}")
    tag = inline_tag(params.aero.kernel)
    lockstep = kernel == "lockstep" or (kernel == "auto" and lockstep_suits(params.aero.kernel))
    if tag is not None:  # one of tennislab's models: its own compiled kernel, formula inlined
        aero = tag
        kern = _KERNELS[lockstep, bool(parallel)]
    else:  # any other kernel: the shared kernel, called through a pointer
        aero = params.aero.kernel
        kern = _KERNELS_FP[lockstep, bool(parallel)]
    kern(s, aero, params.aero.params, params.consts(rtol, atol), event_array(params.events()), out)
    return FlightTable(out, params.ball.radius)


def __getattr__(name: str):
    """``fly``: the old name of :func:`fly_dense`, kept working with a :class:`DeprecationWarning`
    (tennislab.trajectory.fly is the flight workflow: two public functions of one name must not do different things)."""
    if name == "fly":
        warnings.warn(
            "tennislab.core.flight.fly is now fly_dense (tennislab.trajectory.fly is the flight workflow)",
            DeprecationWarning,
            stacklevel=2,
        )
        return fly_dense
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
