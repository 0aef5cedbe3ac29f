"""Ball flight: one right-hand side, two integration paths.

* :func:`fly` - one trajectory with SciPy ``solve_ivp`` (DOP853 at rtol 1e-10
  by default) and dense output, for plots; at its default tolerance it is the
  accuracy reference the tests use.
* :func:`fly_batch` - N initial states integrated in parallel by the compiled
  Dormand-Prince kernel of :mod:`tennislab.core.integrators`, returning an
  event table (:class:`FlightTable`).

Both call :func:`tennislab.core.dynamics.derivative`.  Events: first net-plane
crossing, apex, first ground contact (ball centre at height r), each found by
root-finding on the step interpolant.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp

from tennislab.core.aero import DEFAULT_AERO, AeroModel, get_aero_model, inline_tag
from tennislab.core.atmosphere import Atmosphere
from tennislab.core.ball import Ball
from tennislab.core.court import ITF_COURT, Court
from tennislab.core.dynamics import derivative_call
from tennislab.core.events import COL, COLUMNS, NCOLS, NET_RESULTS, STATUS_OK, Apex, Landing, NetCrossing
from tennislab.core.integrators import NCONSTS, batch_kernel, batch_kernel_fp, serial_kernel, serial_kernel_fp
from tennislab.errors import InputError, check_range, check_vector

#: Named base sets of physics options for :meth:`FlightParams.from_options` (options not given
#: keep the dataclass defaults: ITF type-2 ball, ISA sea-level moist air, DEFAULT_AERO).
PRESETS: dict[str, dict] = {
    "standard": {},
    # seed 000 sec. 2.3: rho 1.22 kg/m^3, g 9.82 m/s^2, r 0.033 m, m 0.059 kg; Stepanek 1988 aero (eqs 3-4)
    "seed000": {"aero": "stepanek1988", "mass": 0.059, "radius": 0.033, "air_density": 1.22, "gravity": 9.82},
    # seed 002 eqs 1, 3 (Wojcicki et al. 2010): constant c_d, Magnus linear in spin
    "seed002": {"aero": "launcher2015"},
}


@dataclass(frozen=True)
class FlightParams:
    """Everything the flight physics needs besides the initial state.

    Attributes
    ----------
    ball : :class:`Ball` (mass [kg], radius [m])
    atmosphere : :class:`Atmosphere` (density [kg/m^3], gravity [m/s^2], wind [m/s])
    aero : :class:`AeroModel` (default :data:`~tennislab.core.aero.DEFAULT_AERO`)
    court : :class:`Court` (net profile for the net event)
    spin_decay : exponential spin-decay rate [1/s]; 0 = off (default)
    t_max : longest flight integrated [s]
    """

    ball: Ball = field(default_factory=Ball)
    atmosphere: Atmosphere = field(default_factory=Atmosphere)
    aero: AeroModel = field(default_factory=lambda: get_aero_model(DEFAULT_AERO))
    court: Court = ITF_COURT
    spin_decay: float = 0.0
    t_max: float = 20.0

    def __post_init__(self):
        check_range("spin_decay", self.spin_decay, 0.0, 100.0, "1/s")
        check_range("t_max", self.t_max, 0.0, 1000.0, "s", lo_open=True)

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
        preset: str = "standard",
    ) -> FlightParams:
        """The one builder of flight physics from plain options (every front-end calls it).

        ``preset`` names a base set (:data:`PRESETS`: ``standard`` = ITF ball, standard
        air, the default aero model; ``seed000`` = seed 000's constants; ``seed002`` =
        the launcher paper's aero model); every option that is not ``None`` overrides it.
        ``aero`` is a registered name, an :class:`AeroModel` or a callable
        ``f(v, w) -> (C_D, C_L)``; ``cd``/``cl`` go to its factory; ``aero_table`` is
        ``(speed [m/s], spin [rad/s], cd, cl)`` arrays for ``aero="table"`` (read from a
        CSV at the edge by :func:`tennislab.io.aero_table.read_aero_table`).
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

    def options(self) -> dict:
        """Plain (picklable) options that rebuild these parameters with :meth:`from_options`."""
        return {
            "aero": self.aero,
            "mass": self.ball.mass,
            "radius": self.ball.radius,
            "inertia_factor": self.ball.inertia_factor,
            "air_density": self.atmosphere.density,
            "gravity": self.atmosphere.gravity,
            "wind": tuple(self.atmosphere.wind),
            "spin_decay": self.spin_decay,
            "t_max": self.t_max,
            "court": self.court,
        }

    @property
    def k(self) -> float:
        """Aerodynamic constant 1/2 rho A / m [1/m]."""
        return 0.5 * self.atmosphere.density * self.ball.area / self.ball.mass

    def consts(self, rtol: float, atol: float) -> np.ndarray:
        """The constant vector of the compiled kernel (layout in :mod:`integrators`)."""
        w = self.atmosphere.wind
        c = self.court
        out = np.array(
            [
                self.k,
                self.atmosphere.gravity,
                self.ball.radius,
                w[0],
                w[1],
                w[2],
                self.spin_decay,
                c.net_center_height,
                c.net_post_height,
                c.y_post,
                self.t_max,
                rtol,
                atol,
            ],
            dtype=np.float64,
        )
        assert out.shape == (NCONSTS,)
        return out

    def rhs(self):
        """The right-hand side f(t, y) for SciPy, calling the shared compiled derivative."""
        k, g, r = self.k, self.atmosphere.gravity, self.ball.radius
        wx, wy, wz = self.atmosphere.wind
        kern, p, lam = self.aero.kernel, self.aero.params, self.spin_decay

        def f(t, y):
            out = np.empty(9)
            derivative_call(np.ascontiguousarray(y, dtype=np.float64), out, kern, p, k, g, r, wx, wy, wz, lam)
            return out

        return f


def initial_state(position, velocity, spin=(0.0, 0.0, 0.0)) -> np.ndarray:
    """State vector (9,) from position [m], velocity [m/s] and spin vector [rad/s]."""
    return np.array(
        check_vector("position", position) + check_vector("velocity", velocity) + check_vector("spin", spin),
        dtype=np.float64,
    )


@dataclass(frozen=True)
class Trajectory:
    """One integrated flight: solver steps, dense solution and events."""

    t: np.ndarray
    y: np.ndarray
    sol: object = field(repr=False)
    landing: Landing | None
    net: NetCrossing
    apex: Apex
    params: FlightParams = field(repr=False)

    def sample(self, n: int = 300, t_end: float | None = None):
        """(t, states) at n evenly spaced times from 0 to landing (or ``t_end``)."""
        te = self.t[-1] if t_end is None else t_end
        ts = np.linspace(self.t[0], te, n)
        return ts, self.sol(ts).T


def _net_crossing(t, yev, params: FlightParams) -> NetCrossing:
    if t is None:
        nan = float("nan")
        return NetCrossing(nan, nan, nan, nan, nan, "none")
    r = params.ball.radius
    hn = params.court.net_height(yev[1])
    clr = yev[2] - hn - r
    return NetCrossing(float(t), float(yev[1]), float(yev[2]), float(hn), float(clr), "net" if clr < 0 else "over")


def fly(
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
    """Integrate one flight to its first ground contact with SciPy ``solve_ivp``.

    Parameters
    ----------
    position : (x, y, z) of the ball centre [m]; z must be >= the ball radius
    velocity : (vx, vy, vz) [m/s]
    spin : spin vector omega [rad/s] (right-hand rule: topspin on a ball moving
        along +x is omega along +y, backspin along -y; see docs/conventions.md)
    params : :class:`FlightParams` (defaults if None)
    method, rtol, atol : SciPy solver settings (default DOP853, 1e-10, 1e-12)
    t0 : start time [s] (used when chaining flights after bounces)
    """
    params = params or FlightParams()
    y0 = initial_state(position, velocity, spin)
    r = params.ball.radius
    if y0[2] < r:
        raise InputError(f"position z: {y0[2]:g} m is below the ball radius {r:g} m (ball centre above ground)")
    side = -1.0 if y0[0] < 0 else (1.0 if y0[0] > 0 else -np.sign(y0[3]) or -1.0)

    def ev_ground(t, y):
        # at the start the ball may sit exactly at z = r (a flight chained after a
        # bounce): count that as "above", so that the sign change SciPy sees at the
        # end of the first step is bracketed by the real contact, not taken at t0
        return y[2] - r if t > t0 else max(y[2] - r, 1e-300)

    ev_ground.terminal = True
    ev_ground.direction = -1

    def ev_net(t, y):
        return y[0]

    ev_net.direction = -side

    def ev_apex(t, y):
        return y[5]

    ev_apex.direction = -1

    sol = solve_ivp(
        params.rhs(),
        (t0, t0 + params.t_max),
        y0,
        method=method,
        rtol=rtol,
        atol=atol,
        dense_output=True,
        events=(ev_ground, ev_net, ev_apex),
    )
    if sol.status < 0:
        raise InputError(f"flight: integration failed ({sol.message})")
    landing = None
    if len(sol.t_events[0]):
        ye = sol.y_events[0][0]
        landing = Landing(float(sol.t_events[0][0]), ye[0:3].copy(), ye[3:6].copy(), ye[6:9].copy())
    t_land = landing.t if landing else np.inf
    tn = [(t, yv) for t, yv in zip(sol.t_events[1], sol.y_events[1]) if t <= t_land]
    net = _net_crossing(tn[0][0], tn[0][1], params) if tn else _net_crossing(None, None, params)
    if y0[5] <= 0:
        apex = Apex(t0, y0[0:3].copy())
    else:
        ta = [(t, yv) for t, yv in zip(sol.t_events[2], sol.y_events[2]) if t <= t_land]
        apex = Apex(float(ta[0][0]), ta[0][1][0:3].copy()) if ta else Apex(float(sol.t[-1]), sol.y[0:3, -1].copy())
    return Trajectory(sol.t, sol.y.T, sol.sol, landing, net, apex, params)


@dataclass(frozen=True)
class FlightTable:
    """Event table of a batch: one row per initial state, columns :data:`events.COLUMNS`.

    ``table["land_x"]`` gives a column; :attr:`clearance` and :attr:`net_result` are derived.
    Rows with ``status != 0`` did not land within ``t_max`` (1) or started invalid (2).
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
    def ok(self) -> np.ndarray:
        return self["status"] == STATUS_OK

    def as_dict(self) -> dict[str, np.ndarray]:
        return {c: self.data[:, i] for i, c in enumerate(COLUMNS)}


def fly_batch(
    states, params: FlightParams | None = None, *, rtol: float = 2e-7, atol: float = 2e-7, parallel: bool = True
) -> FlightTable:
    """Integrate N flights (states (N, 9): position, velocity, spin) to first ground contact.

    Compiled with Numba (``parallel=True`` uses all cores via ``prange``).  The
    default tolerance (rtol = atol = 2e-7) keeps landing points within 0.006 mm
    of the reference :func:`fly` at rtol 1e-10 for serves, groundstrokes and
    lobs with up to 6000 rpm about any axis, for every built-in aero model
    (18,000 shots: docs/flight.md; tests/test_flight_accuracy.py).
    """
    params = params or FlightParams()
    s = np.ascontiguousarray(np.asarray(states, dtype=np.float64))
    if s.ndim == 1:
        s = s.reshape(1, -1)
    if s.ndim != 2 or s.shape[1] != 9:
        raise InputError(f"states: expected an (N, 9) array, got shape {np.shape(states)}")
    out = np.empty((s.shape[0], NCOLS))
    tag = inline_tag(params.aero.kernel)
    if tag is not None:  # one of tennislab's models: its own compiled kernel, formula inlined
        kern, aero = (batch_kernel if parallel else serial_kernel), tag
    else:  # any other kernel: the shared kernel, called through a pointer
        kern, aero = (batch_kernel_fp if parallel else serial_kernel_fp), params.aero.kernel
    kern(s, aero, params.aero.params, params.consts(rtol, atol), out)
    return FlightTable(out, params.ball.radius)
