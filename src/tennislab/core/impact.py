"""Racket-ball impact: seed 000's perpendicular and tangential spring-damper model (2-D).

Local (racket) frame, seed 000 figs 1-4: ``n`` is the face normal pointing from
the strings into the ball, ``t`` the tangent in the plane of the stroke.  The
racket (free rigid body of mass m_k at the impact point) moves at speed V at
the *impact angle* alpha to the face normal: V_n = V cos(alpha),
V_t = V sin(alpha).  The ball starts at rest (a toss velocity is handled by a
Galilean shift: the impact is computed in the frame of the ball).

Perpendicular (seed eqs 7-12): string-bed spring k_k between racket x1 and a
massless node x3, ball spring k_b in parallel with damper c_b between the node
and the ball x2::

    m_k x1'' = -k_k (x1 - x3)                       (7)
    m_b x2'' =  k_b (x3 - x2) + c_b (x3' - x2')     (8)
    k_k (x1 - x3) = k_b (x3 - x2) + c_b (x3' - x2') (node, equivalent to eq 9)

so x3' = x2' + [k_k (x1 - x3) - k_b (x3 - x2)] / c_b (worksheet eq 2.5, whose
printed ``k_k/c_b x2`` is a typo for ``k_b/c_b x2``).  F_N = k_k (x1 - x3).
k_b, c_b come from the contact time and COR at the normal impact speed
(seed eqs 5-6, :mod:`tennislab.core.haake2003`).

Tangential (seed eqs 13-19): spring k = ``tangential_stiffness_ratio`` * k_b
(0.5, seed sec. 2.2) and damper c between the racket and the ball's contact
point, which sits at -r n, so its tangential velocity is v_t + r omega (seed
eq 13; eq 19's printed matrix has typos -- we use eqs 13-15, which agree with
worksheet eqs 2.10-2.12).  c is chosen so that the tangential oscillator
restitutes ``oblique_cor_factor`` = 1.04 times the COR ("COR is 4 % higher for
oblique impacts", seed sec. 2.2 after Goodwill et al. 2005); the rule is
``tangential_damping`` (:data:`TANGENTIAL_DAMPING`):

* ``oscillator`` (default): seed eq 6 applied to the tangential oscillator of
  the ball on a rigid surface -- mass m_t = m_b I / (I + m_b r^2) (the contact
  point's effective mass, 0.4 m_b for a thin shell) on the spring k, half period
  T_t = pi sqrt(m_t / k):  c = -(2 m_t / T_t) ln(1.04 COR) = -(2/pi) sqrt(k m_t) ln(1.04 COR).
  This is the damper whose oscillator restitutes 1.04 COR, as the seed states.
* ``ball``: eq 6 with the ball's mass and normal contact time, c = -(2 m_b / T_c)
  ln(1.04 COR) (the reading before 2026-12; the seed's own, judging by its fig 5,
  docs/serve.md).  It gives the tangential oscillator a restitution of only
  (1.04 COR)^2.24 ~ 0.39 at 20 m/s, *lower* than the normal COR.

::

    m_k y1'' = -F_t,   m_b y2'' = F_t,   I omega' = r F_t,   I = i_f m_b r^2 (eq 15; 2/3)

Stick-slip (seed eq 20): |F_t| <= mu F_N.  The seed clamps the force but does
not say what happens to the spring's stretch while sliding; we use the
elasto-plastic ("bristle") rule: the stretch e obeys e' = slip velocity while
|k e + c e'| < mu F_N and is limited so that k e + c e' = +-mu F_N while
sliding.  The force is then continuous and every sliding or damped motion
dissipates energy (no energy is created, tests/core/test_impact.py).  The
*regime* is ``slide`` when the slip velocity s = y1' - y2' - r omega never
reached zero during contact (the ball slid throughout) and ``roll`` when the
contact point caught up with the strings (it gripped and rolled off) -- the
classical criterion (Brody 1984; seed worksheet sec. 3.2).

Contact starts at x1 = x2 with the springs unloaded and ends when the string
force F_N returns to zero (the damper would otherwise pull).  ``approach_gap``
g > 0 reproduces the seed's start instead (worksheet sec. 2.2: the racket
starts 0.02 m behind the ball; eq 13's spring acts on the positions y1 - y2 -
r y3 measured from that start): the racket's tangential travel during the
approach, g V_t / V_n, is already in the tangential spring at first touch.  A
spring loaded before the bodies touch is not physical (it adds energy); it is
the main reason for the seed's peak-spin angle (docs/serve.md).  Integration:
classical RK4 with a fixed step h = T/``steps`` (T = the undamped half period
of the series system) and the end of contact located to ~1e-12 s by regula
falsi on the RK4 step length; ``method="euler"`` reproduces the seed's explicit
Euler scheme for the convergence study (docs/impact.md).  :func:`impact_reference`
integrates the same ODE with SciPy DOP853 as the independent reference.

Sign conventions (court frame, seed eq 21, fig 4): the face normal is tilted
down by the *face angle* beta, n = (cos b, 0, -sin b), t = (sin b, 0, cos b)
(x toward the far baseline, z up); the racket brushes up the back of the ball,
so omega > 0 is topspin (spin vector +y).  Launch angle gamma = atan2(v_z, v_x)
= -beta + atan2(v_t, v_n): a flat serve (alpha ~ 0) leaves at gamma ~ -beta
(below the horizontal), a higher alpha raises it.

References
----------
.. [1] Grosen, Kousted & Treichel (2021), 2-dimensional tennis serves show similar successful mechanical
    parameter across physiological differences, Aalborg University (seed 000), sec. 2.2, eqs 5-20 and its
    worksheet
.. [2] Brody (1984), Phys. Teach. 22:494 (slide or roll)
.. [3] Goodwill et al. (2005), as quoted by seed 000 (oblique COR 4 % higher)
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field

import numba as nb
import numpy as np

from tennislab.core.ball import Ball
from tennislab.core.haake2003 import BallImpactModel, get_ball_model
from tennislab.errors import TINY, InputError, check_answer, check_range

# parameter vector layout of the compiled kernel
P_MK, P_MB, P_I, P_R, P_KK, P_KB, P_CB, P_KT, P_CT, P_MU, P_FM, P_GAP = range(12)
NP = 12
NS = 9  # state: x1, x2, x3, v1, v2, e, w1, w2, w3

METHODS = {"rk4": 0, "euler": 1}
#: friction models: 0 = elasto-plastic (default), 1 = the seed's clamp (stretch not reset)
FRICTION_MODELS = {"elastoplastic": 0, "seed-clamp": 1}
REGIMES = ("slide", "roll")
#: Shortest fixed impact step accepted [s]: a 5 ms contact in at most 5e4 steps (the converged RK4's
#: automatic step is ~1e-5 s); smaller steps only make the work unbounded (each impact stops after
#: ``200 steps + 10^6`` steps, unfinished).
DT_MIN = 1e-7
#: Longest fixed impact step accepted [s] (the seed's explicit Euler uses 1e-4 s).
DT_MAX = 1e-3


def check_dt(dt: float) -> float:
    """A fixed impact step [s]: 0 (automatic: ``steps`` per contact half period) or within
    [:data:`DT_MIN`, :data:`DT_MAX`], so that every impact's work is bounded; else InputError."""
    v = check_range("dt", dt, 0.0, DT_MAX, "s")
    if 0.0 < v < DT_MIN:
        raise InputError(
            f"dt: {v:g} s is outside the allowed range: 0 (automatic) or [{DT_MIN:g}, {DT_MAX:g}] s "
            f"(a smaller step would take more than {0.005 / DT_MIN:.0e} steps per contact)"
        )
    return v


def check_contact_ended(status) -> None:
    """Every impact's contact must have ended (``status`` 0, :data:`OUT_COLUMNS`); an impact that ran out
    of steps has no answer (the ball would leave with the speed it had then)."""
    if np.any(np.asarray(status) != 0):
        raise InputError("impact: contact did not end (check the stiffness and masses, and the time step dt)")


def _damping_oscillator(kt, tc, e_t, mass, inertia, radius):
    """c = -(2/pi) sqrt(k m_t) ln(e_t), m_t = m I / (I + m r^2): seed eq 6 applied to the tangential
    oscillator of the ball on a rigid surface (half period pi sqrt(m_t/k)), so that it restitutes e_t."""
    m_t = mass * inertia / (inertia + mass * radius**2)
    return -2.0 / math.pi * np.sqrt(kt * m_t) * np.log(e_t)


def _damping_ball(kt, tc, e_t, mass, inertia, radius):
    """c = -(2 m_b / T_c) ln(e_t): seed eq 6 with the ball's mass and normal contact time T_c."""
    return -2.0 * mass / tc * np.log(e_t)


#: Rules for the tangential damper c [N s/m] (module docstring): name -> f(k [N/m], T_c [s], e_t [-],
#: m_b [kg], I [kg m^2], r [m]).
TANGENTIAL_DAMPING = {"oscillator": _damping_oscillator, "ball": _damping_ball}

#: Output columns of :func:`impact_batch`.
OUT_COLUMNS = (
    "v_n",
    "v_t",
    "omega",
    "contact_time",
    "regime",
    "racket_v_n",
    "racket_v_t",
    "peak_force",
    "grip_time",
    "n_steps",
    "status",
)
NOUT = len(OUT_COLUMNS)
_O = {n: i for i, n in enumerate(OUT_COLUMNS)}


@dataclass(frozen=True)
class ImpactParams:
    """Racket and ball constants of the impact (defaults: seed 000 sec. 2.3).

    Attributes
    ----------
    ball : :class:`Ball` (mass [kg], radius [m], inertia factor [-]; seed: 0.059, 0.033, 2/3)
    racket_mass : racket mass m_k [kg] (seed: 0.2)
    string_stiffness : string-bed stiffness k_k [N/m] (seed: 50e3; Goodwill & Haake
        2001 give 40-60 kN/m)
    friction : string-ball friction coefficient mu [-] (seed: 0.35)
    tangential_stiffness_ratio : k / k_b [-] (seed sec. 2.2: 0.5)
    oblique_cor_factor : tangential COR = factor * normal COR for the damper c [-]
        (seed sec. 2.2: "COR is 4 % higher for oblique impacts", Goodwill et al. 2005)
    tangential_damping : rule for the damper c: ``oscillator`` (default) or ``ball``
        (:data:`TANGENTIAL_DAMPING`, module docstring)
    approach_gap : distance [m] the racket starts behind the ball with the tangential spring
        measured from there (seed worksheet sec. 2.2: 0.02 m); 0 (default) = springs unloaded at
        first touch, the physical start (module docstring)
    ball_model : :class:`BallImpactModel` giving T_c(v), COR(v) (default ``haake2003``)
    max_cor : cap of the tangential COR so that c > 0 [-]
    friction_model : ``elastoplastic`` (default: the spring stretch slides with the ball,
        |k e + c e'| <= mu F_N) or ``seed-clamp`` (seed eq 20 read literally: F_t =
        clip(k e + c s, +-mu F_N) with e' = s always; it can create energy, docs/impact.md)
    """

    ball: Ball = field(default_factory=lambda: Ball(mass=0.059, radius=0.033))
    racket_mass: float = 0.2
    string_stiffness: float = 50e3
    friction: float = 0.35
    tangential_stiffness_ratio: float = 0.5
    oblique_cor_factor: float = 1.04
    ball_model: BallImpactModel = field(default_factory=lambda: get_ball_model("haake2003"))
    max_cor: float = 0.99
    friction_model: str = "elastoplastic"
    tangential_damping: str = "oscillator"
    approach_gap: float = 0.0

    def __post_init__(self):
        if self.friction_model not in FRICTION_MODELS:
            raise InputError(
                f"friction_model: unknown {self.friction_model!r}; choose from {', '.join(FRICTION_MODELS)}"
            )
        if self.tangential_damping not in TANGENTIAL_DAMPING:
            raise InputError(
                f"tangential_damping: unknown {self.tangential_damping!r}; choose from {', '.join(TANGENTIAL_DAMPING)}"
            )
        check_range("approach_gap", self.approach_gap, 0.0, 0.1, "m")
        check_range("racket_mass", self.racket_mass, 0.0, 10.0, "kg", lo_open=True)
        check_range("string_stiffness", self.string_stiffness, 1e2, 1e7, "N/m")
        check_range("friction", self.friction, 0.0, 5.0)
        check_range("tangential_stiffness_ratio", self.tangential_stiffness_ratio, 0.0, 10.0, lo_open=True)
        check_range("oblique_cor_factor", self.oblique_cor_factor, 0.5, 2.0)

    @classmethod
    def from_options(
        cls, racket_mass=None, string_stiffness=None, friction=None, ball=None, ball_model=None, **kw
    ) -> ImpactParams:
        """Build from CLI-style options; ``None`` keeps each default."""
        opts = {
            k: v
            for k, v in (
                ("racket_mass", racket_mass),
                ("string_stiffness", string_stiffness),
                ("friction", friction),
                ("ball", ball),
            )
            if v is not None
        }
        if ball_model is not None:
            opts["ball_model"] = get_ball_model(ball_model)
        opts.update({k: v for k, v in kw.items() if v is not None})
        return cls(**opts)

    def vectors(self, vn_rel) -> np.ndarray:
        """Kernel parameter rows (N, NP) for normal approach speeds ``vn_rel`` [m/s]."""
        vn = np.atleast_1d(np.asarray(vn_rel, float))
        b = self.ball
        kb, cb = self.ball_model.spring_damper(vn, b.mass)
        tc = self.ball_model.contact_time(vn)
        e_t = np.minimum(self.oblique_cor_factor * self.ball_model.cor(vn), self.max_cor)
        p = np.empty((vn.size, NP))
        p[:, P_MK] = self.racket_mass
        p[:, P_MB] = b.mass
        p[:, P_I] = b.inertia
        p[:, P_R] = b.radius
        p[:, P_KK] = self.string_stiffness
        p[:, P_KB] = kb
        p[:, P_CB] = cb
        kt = self.tangential_stiffness_ratio * kb
        p[:, P_KT] = kt
        p[:, P_CT] = TANGENTIAL_DAMPING[self.tangential_damping](kt, tc, e_t, b.mass, b.inertia, b.radius)
        p[:, P_MU] = self.friction
        p[:, P_FM] = FRICTION_MODELS[self.friction_model]
        p[:, P_GAP] = self.approach_gap
        return p

    def caveats(self) -> list[str]:
        """One sentence per model caveat of these parameters (shown next to results)."""
        out = []
        note = self.ball_model.caveat()
        if note:
            out.append(note)
        if self.friction_model == "seed-clamp":
            out.append(
                "impact: friction rule 'seed-clamp' (the paper's eq 20 read literally) can create energy; "
                "the default 'elastoplastic' never does (docs/impact.md)"
            )
        if self.approach_gap > 0:
            out.append(
                f"impact: approach gap {self.approach_gap:g} m loads the tangential spring before the ball is "
                "touched (the paper's start); this adds energy (docs/impact.md)"
            )
        return out


# ----------------------------------------------------------------------------------------------
# compiled kernel
# ----------------------------------------------------------------------------------------------


@nb.njit(cache=True)
def _node(s, p):
    """(x3, x3') of the massless node; algebraic (series springs) when c_b == 0."""
    kk, kb, cb = p[P_KK], p[P_KB], p[P_CB]
    if cb > 0.0:
        return s[2], s[4] + (kk * (s[0] - s[2]) - kb * (s[2] - s[1])) / cb
    x3 = (kk * s[0] + kb * s[1]) / (kk + kb)
    return x3, (kk * s[3] + kb * s[4]) / (kk + kb)


@nb.njit(cache=True)
def normal_force(s, p):
    """String force on the ball F_N = k_k (x1 - x3) [N]."""
    x3, _ = _node(s, p)
    return p[P_KK] * (s[0] - x3)


@nb.njit(cache=True)
def rhs(s, p, out):
    """Right-hand side of the impact ODE (state x1, x2, x3, v1, v2, e, w1, w2, w3).

    Returns the tangential force F_t [N] (on the ball, along +t)."""
    mk, mb, inertia, r = p[P_MK], p[P_MB], p[P_I], p[P_R]
    kk, kt, ct, mu = p[P_KK], p[P_KT], p[P_CT], p[P_MU]
    x3, x3d = _node(s, p)
    fn = kk * (s[0] - x3)
    lim = mu * fn if fn > 0.0 else 0.0
    slip = s[6] - s[7] - r * s[8]
    e = s[5]
    ffree = kt * e + ct * slip
    if p[P_FM] == 1.0:
        edot = slip
        ft = min(max(ffree, -lim), lim)
    elif ffree > lim:
        edot = (lim - kt * e) / ct
        ft = lim
    elif ffree < -lim:
        edot = (-lim - kt * e) / ct
        ft = -lim
    else:
        edot = slip
        ft = ffree
    out[0] = s[3]
    out[1] = s[4]
    out[2] = x3d if p[P_CB] > 0.0 else 0.0
    out[3] = -fn / mk
    out[4] = fn / mb
    out[5] = edot
    out[6] = -ft / mk
    out[7] = ft / mb
    out[8] = r * ft / inertia
    return ft


@nb.njit(cache=True)
def _step(s, p, h, method, out, k1, k2, k3, k4, tmp):
    n = s.shape[0]
    rhs(s, p, k1)
    if method == 1:
        for i in range(n):
            out[i] = s[i] + h * k1[i]
        return
    for i in range(n):
        tmp[i] = s[i] + 0.5 * h * k1[i]
    rhs(tmp, p, k2)
    for i in range(n):
        tmp[i] = s[i] + 0.5 * h * k2[i]
    rhs(tmp, p, k3)
    for i in range(n):
        tmp[i] = s[i] + h * k3[i]
    rhs(tmp, p, k4)
    for i in range(n):
        out[i] = s[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])


@nb.njit(cache=True)
def step_size(p, steps):
    """h = T/steps, T = pi sqrt(mu_red / k_series) the undamped half period; also
    <= 0.5 of the node and tangential relaxation times (explicit stability)."""
    mk, mb, kk, kb, cb, kt, ct = p[P_MK], p[P_MB], p[P_KK], p[P_KB], p[P_CB], p[P_KT], p[P_CT]
    ks = kk * kb / (kk + kb)
    mred = mk * mb / (mk + mb)
    h = math.pi * math.sqrt(mred / ks) / steps
    if cb > 0.0:
        h = min(h, 0.5 * cb / (kk + kb))
    if ct > 0.0 and kt > 0.0:
        h = min(h, 0.5 * ct / kt)
    return h


@nb.njit(cache=True, inline="always")
def _grip(s, r, s0, gripped, grip_t, t):
    """(gripped, grip_time [s]) for state ``s`` at time ``t`` [s]: the contact point grips when
    its slip velocity y1' - y2' - r omega [m/s] reaches zero or changes sign from the initial ``s0``."""
    sl = s[6] - s[7] - r * s[8]
    if not gripped and sl * s0 <= 0.0:
        return True, t
    return gripped, grip_t


@nb.njit(cache=True, inline="always")
def _record(hist, row, t, s, fn, ft):
    """Write history row ``row``: time t [s], the state, F_N [N] and F_t [N]."""
    hist[row, 0] = t
    for i in range(NS):
        hist[row, 1 + i] = s[i]
    hist[row, 1 + NS] = fn
    hist[row, 2 + NS] = ft


@nb.njit(cache=True)
def impact_one(vn, vt, p, steps, dt, method, out, hist, nhist):
    """Integrate one impact (racket approach V_n, V_t relative to the ball at rest).

    Writes the row of :data:`OUT_COLUMNS` into ``out``; if ``nhist`` > 0 also
    records (t, state..., F_N, F_t) into ``hist`` rows (for plots) and returns
    the number of rows written."""
    s = np.zeros(NS)
    s[3] = vn
    s[6] = vt
    s[5] = p[P_GAP] * vt / vn  # tangential travel of the racket during the approach (0 = unloaded)
    new = np.empty(NS)
    k1 = np.empty(NS)
    k2 = np.empty(NS)
    k3 = np.empty(NS)
    k4 = np.empty(NS)
    tmp = np.empty(NS)
    h = dt if dt > 0.0 else step_size(p, steps)
    t = 0.0
    r = p[P_R]
    s0 = s[6] - s[7] - r * s[8]
    gripped = s0 == 0.0
    grip_t = 0.0 if gripped else -1.0
    peak = 0.0
    nstep = 0
    status = 1
    row = 0
    max_steps = 200 * steps + 1000000
    if nhist > 0:
        _record(hist, 0, t, s, 0.0, rhs(s, p, k1))
        row = 1
    while nstep < max_steps:
        _step(s, p, h, method, new, k1, k2, k3, k4, tmp)
        nstep += 1
        fn_new = normal_force(new, p)
        if fn_new <= 0.0 and nstep > 1:
            # locate F_N = 0 inside the step by regula falsi (Illinois) on the step length
            fa = normal_force(s, p)
            a, b = 0.0, 1.0
            fb = fn_new
            side = 0
            theta = 1.0
            for _ in range(60):
                theta = (a * fb - b * fa) / (fb - fa)
                _step(s, p, theta * h, method, new, k1, k2, k3, k4, tmp)
                fc = normal_force(new, p)
                if abs(fc) < 1e-9 * (peak + 1e-30) or (b - a) < 1e-13:
                    break
                if fc > 0.0:
                    a, fa = theta, fc
                    if side == 1:
                        fb *= 0.5
                    side = 1
                else:
                    b, fb = theta, fc
                    if side == -1:
                        fa *= 0.5
                    side = -1
            t += theta * h
            for i in range(NS):
                s[i] = new[i]
            status = 0
            gripped, grip_t = _grip(s, r, s0, gripped, grip_t, t)
            if nhist > 0 and row < nhist:
                _record(hist, row, t, s, 0.0, 0.0)
                row += 1
            break
        t += h
        for i in range(NS):
            s[i] = new[i]
        if fn_new > peak:
            peak = fn_new
        gripped, grip_t = _grip(s, r, s0, gripped, grip_t, t)
        if nhist > 0 and row < nhist:
            _record(hist, row, t, s, fn_new, rhs(s, p, k1))
            row += 1
    out[0] = s[4]
    out[1] = s[7]
    out[2] = s[8]
    out[3] = t
    out[4] = 1.0 if gripped else 0.0
    out[5] = s[3]
    out[6] = s[6]
    out[7] = peak
    out[8] = grip_t
    out[9] = nstep
    out[10] = status
    return row


@nb.njit(cache=True, parallel=True)
def _impact_batch_kernel(vn, vt, P, steps, dt, method, out):
    for i in nb.prange(vn.shape[0]):
        dummy = np.empty((1, NS + 3))
        impact_one(vn[i], vt[i], P[i], steps, dt, method, out[i], dummy, 0)


@nb.njit(cache=True)
def _impact_serial_kernel(vn, vt, P, steps, dt, method, out):
    dummy = np.empty((1, NS + 3))
    for i in range(vn.shape[0]):
        impact_one(vn[i], vt[i], P[i], steps, dt, method, out[i], dummy, 0)


# ----------------------------------------------------------------------------------------------
# Python API
# ----------------------------------------------------------------------------------------------


def _check_method(method: str) -> int:
    try:
        return METHODS[method]
    except KeyError:
        raise InputError(f"method: unknown {method!r}; choose from {', '.join(METHODS)}") from None


def impact_batch(
    speed,
    alpha,
    params: ImpactParams | None = None,
    *,
    toss_n=0.0,
    toss_t=0.0,
    steps: int = 400,
    dt: float = 0.0,
    method: str = "rk4",
    parallel: bool = True,
) -> dict[str, np.ndarray]:
    """Impacts for arrays of racket speed V [m/s] and impact angle alpha [rad] (broadcast).

    ``toss_n``, ``toss_t``: ball velocity before impact in the racket frame [m/s]
    (0 = ball at rest).  Returns a dict of :data:`OUT_COLUMNS` arrays plus
    ``speed`` (ball speed [m/s]) and ``spin`` (= omega, [rad/s], > 0 topspin); ball
    velocities are in the racket frame and include the toss.  ``regime`` is 0 for
    slide, 1 for roll; ``status`` 0 = contact ended normally.
    """
    params = params or ImpactParams()
    V, A, un, ut = np.broadcast_arrays(*(np.asarray(x, float) for x in (speed, alpha, toss_n, toss_t)))
    shape = V.shape
    V, A, un, ut = (np.ascontiguousarray(x.ravel()) for x in (V, A, un, ut))
    if not (np.all(np.isfinite(V)) and np.all(np.isfinite(A))):
        raise InputError("speed: speed and alpha must be finite")
    if np.any(V < 0) or np.any(V > 150):
        raise InputError("speed: outside the allowed range [0, 150] m/s")
    V, A = (np.where(np.abs(x) < TINY, 0.0, x) for x in (V, A))  # subnormals are read as 0 (errors.check_finite)
    if np.any(np.abs(A) > math.pi / 2):
        raise InputError("alpha: outside the allowed range [-pi/2, pi/2] rad")
    steps = int(check_range("steps", steps, 4, 1e6))
    dt = check_dt(dt)
    m = _check_method(method)
    vn = V * np.cos(A) - un
    vt = V * np.sin(A) - ut
    if np.any(vn <= 0):
        raise InputError("impact: the racket must approach the ball (V cos(alpha) > toss normal speed)")
    P = params.vectors(vn)
    out = np.empty((vn.size, NOUT))
    (_impact_batch_kernel if parallel and vn.size > 1 else _impact_serial_kernel)(vn, vt, P, steps, float(dt), m, out)
    check_contact_ended(out[:, _O["status"]])
    res = {c: out[:, i].reshape(shape) for i, c in enumerate(OUT_COLUMNS)}
    # back to the ground frame (add the toss)
    res["v_n"] = res["v_n"] + un.reshape(shape)
    res["v_t"] = res["v_t"] + ut.reshape(shape)
    res["racket_v_n"] = res["racket_v_n"] + un.reshape(shape)
    res["racket_v_t"] = res["racket_v_t"] + ut.reshape(shape)
    res["speed"] = np.hypot(res["v_n"], res["v_t"])
    res["spin"] = res["omega"]
    return res


@dataclass(frozen=True)
class ImpactResult:
    """One impact in the racket frame.

    v_n, v_t : ball velocity along the face normal and tangent after impact [m/s]
    omega : ball spin [rad/s] (> 0: topspin in the serve frame)
    contact_time : [s]; regime : ``slide`` or ``roll``; grip_time : [s] or None
    racket_v_n, racket_v_t : racket velocity after impact [m/s]; peak_force : max F_N [N]
    history : dict of arrays (t, x1, x2, x3, v1, v2, e, w1, w2, w3, F_N, F_t) or None
    """

    v_n: float
    v_t: float
    omega: float
    contact_time: float
    regime: str
    grip_time: float | None
    racket_v_n: float
    racket_v_t: float
    peak_force: float
    history: dict | None = field(default=None, repr=False)

    @property
    def speed(self) -> float:
        return math.hypot(self.v_n, self.v_t)


HIST_COLUMNS = ("t", "x1", "x2", "x3", "v1", "v2", "e", "w1", "w2", "w3", "F_N", "F_t")


def impact_single(
    speed: float,
    alpha: float,
    params: ImpactParams | None = None,
    *,
    toss_n: float = 0.0,
    toss_t: float = 0.0,
    steps: int = 400,
    dt: float = 0.0,
    method: str = "rk4",
    history: bool = False,
) -> ImpactResult:
    """One impact: racket speed V [m/s] at impact angle alpha [rad] (see module docstring).

    ``steps`` per half period (RK4 step h = T/steps), or a fixed step ``dt`` [s] if > 0
    (``method="euler", dt=1e-4`` is the seed's scheme).  ``history=True`` keeps every step.
    """
    params = params or ImpactParams()
    V = check_range("speed", speed, 0.0, 150.0, "m/s", lo_open=True)
    A = check_range("alpha", alpha, -math.pi / 2, math.pi / 2, "rad")
    steps = int(check_range("steps", steps, 4, 1e6))
    dt = check_dt(dt)
    vn, vt = V * math.cos(A) - toss_n, V * math.sin(A) - toss_t
    if vn <= 0:
        raise InputError("impact: the racket must approach the ball (V cos(alpha) > toss normal speed)")
    p = params.vectors(vn)[0]
    out = np.empty(NOUT)
    nh = 0
    hist = np.empty((1, NS + 3))
    if history:
        h0 = dt if dt > 0 else step_size(p, steps)
        nh = int(0.05 / h0) + 100
        hist = np.empty((nh, NS + 3))
    rows = impact_one(vn, vt, p, steps, float(dt), _check_method(method), out, hist, nh)
    H = None
    if history:
        H = {c: hist[:rows, i].copy() for i, c in enumerate(HIST_COLUMNS)}
        # back to the ground frame
        for c, u in (("v1", toss_n), ("v2", toss_n), ("w1", toss_t), ("w2", toss_t)):
            H[c] = H[c] + u
    check_contact_ended(out[_O["status"]])
    for i, name in enumerate(OUT_COLUMNS[:9]):
        check_answer(f"impact {name}", out[i])
    return ImpactResult(
        out[0] + toss_n,
        out[1] + toss_t,
        out[2],
        out[3],
        REGIMES[int(out[4])],
        None if out[8] < 0 else float(out[8]),
        out[5] + toss_n,
        out[6] + toss_t,
        out[7],
        H,
    )


def impact_reference(
    speed: float, alpha: float, params: ImpactParams | None = None, *, rtol: float = 1e-11, atol: float = 1e-13
) -> ImpactResult:
    """The same ODE integrated by SciPy ``solve_ivp`` (DOP853) with an F_N = 0 event (reference)."""
    params = params or ImpactParams()
    vn, vt = speed * math.cos(alpha), speed * math.sin(alpha)
    p = params.vectors(vn)[0]
    s0 = np.zeros(NS)
    s0[3], s0[6] = vn, vt
    s0[5] = p[P_GAP] * vt / vn
    buf = np.empty(NS)

    def f(t, y):
        rhs(np.ascontiguousarray(y), p, buf)
        return buf.copy()

    def ev(t, y):
        return normal_force(np.ascontiguousarray(y), p)

    ev.terminal = True  # type: ignore[attr-defined]  # solve_ivp's event attributes
    ev.direction = -1  # type: ignore[attr-defined]
    from scipy.integrate import solve_ivp  # (here: SciPy loads only for a dense flight)

    sol = solve_ivp(
        f,
        (0.0, 0.1),
        s0,
        method="DOP853",
        rtol=rtol,
        atol=atol,
        events=ev,
        first_step=1e-7,
        max_step=1e-5,
        dense_output=True,
    )
    te = float(sol.t_events[0][0])
    y = sol.y_events[0][0]
    r = p[P_R]
    slip = sol.y[6] - sol.y[7] - r * sol.y[8]
    gi = np.nonzero(slip * slip[0] <= 0)[0] if slip[0] != 0 else np.array([0])
    regime = "roll" if gi.size else "slide"
    return ImpactResult(
        float(y[4]),
        float(y[7]),
        float(y[8]),
        te,
        regime,
        float(sol.t[gi[0]]) if gi.size else None,
        float(y[3]),
        float(y[6]),
        float(max(normal_force(np.ascontiguousarray(sol.y[:, i]), p) for i in range(sol.y.shape[1]))),
    )


def energy(s, p) -> float:
    """Mechanical energy of an impact state [J] (kinetic + the three springs)."""
    x3, _ = _node(np.asarray(s, float), np.asarray(p, float))
    mk, mb, inertia = p[P_MK], p[P_MB], p[P_I]
    return (
        0.5 * mk * (s[3] ** 2 + s[6] ** 2)
        + 0.5 * mb * (s[4] ** 2 + s[7] ** 2)
        + 0.5 * inertia * s[8] ** 2
        + 0.5 * p[P_KK] * (s[0] - x3) ** 2
        + 0.5 * p[P_KB] * (x3 - s[1]) ** 2
        + 0.5 * p[P_KT] * s[5] ** 2
    )


# ----------------------------------------------------------------------------------------------
# frames (seed eq 21)
# ----------------------------------------------------------------------------------------------


def to_court(v_n, v_t, beta):
    """Racket-frame velocity (v_n, v_t) -> court (v_x, v_z) for face angle beta [rad] (seed eq 21).

    n = (cos b, -sin b), t = (sin b, cos b) in (x, z): v_x = v_n cos b + v_t sin b,
    v_z = -v_n sin b + v_t cos b.
    """
    cb, sb = np.cos(beta), np.sin(beta)
    return v_n * cb + v_t * sb, -v_n * sb + v_t * cb


def launch_angle(v_n, v_t, beta):
    """Launch angle gamma [rad] above the horizontal (negative: downward)."""
    vx, vz = to_court(v_n, v_t, beta)
    return np.arctan2(vz, vx)


def __getattr__(name: str):
    """``impact``: the old name of :func:`impact_single`, kept working with a :class:`DeprecationWarning`
    (tennislab.serve.impact is the impact workflow: two public functions of one name must not do different things)."""
    if name == "impact":
        warnings.warn(
            "tennislab.core.impact.impact is now impact_single (tennislab.serve.impact is the impact workflow)",
            DeprecationWarning,
            stacklevel=2,
        )
        return impact_single
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
