"""Aerodynamic coefficient models, chosen by name or passed as a callable.

Every model gives the drag and lift coefficients (C_D, C_L) from the air speed
v [m/s] and the spin rate w = |omega| [rad/s] of a ball of radius r [m].  Forces
(see :mod:`tennislab.core.flight`): drag 1/2 C_D rho A v^2 opposite the air
velocity; Magnus lift 1/2 C_L rho A v^2 along omega x v (unit vectors' cross
product, so spin along the velocity gives no lift).

A model is an :class:`AeroModel`: a Numba kernel ``kernel(v, w, r, p) ->
(cd, cl)`` with the fixed signature :data:`AERO_SIGNATURE` plus its parameter
array ``p``.  The same kernel serves the SciPy dense path and the compiled batch
path: tennislab's own kernels are compiled into a batch kernel per model (via
their inline tags, below); any other kernel is passed to one shared batch
kernel as a first-class function.

Registered models (``get_aero_model(name, **params)``):

``constant``       C_D, C_L given (defaults 0.55, 0).
``stepanek1988``   Stepanek 1988, Am. J. Phys. 56:138, as written in seed 000
                   eqs 3-4: C_D = 0.55 + 1/(22.5 + 4.2 (v/(r w))^2.5)^0.4,
                   C_L = 1/(2 + v/(r w)).  Fitted at 13-27 m/s and 800-3250
                   rpm (C_D 0.55-0.75, C_L 0.075-0.275); elsewhere an
                   extrapolation (reference-data.md, after Cross 2000).
``launcher2015``   Seed 002 (Wojcicki, Pucilowski & Kulesza, Acta Mech. Autom.)
                   eqs 1 and 3: constant c_d; Magnus F = 1/2 c_l pi r^3 rho
                   omega x v, i.e. C_L = c_l r w / v.  The seed gives no
                   values; defaults c_d = 0.55 (the low end of Alam et al.
                   2007's 0.55-0.85 quoted by the seed) and c_l = 0.6 (Cross
                   2020, Sports Eng. 23:9, C_L = 0.6 S).  Alias ``wojcicki2010``.
``cross2014``      Cross & Lindsey 2014, Sports Eng. 17:89: C_D = 0.507 in
                   flight (launcher, 15-30 m/s, <= 2500 rpm); C_L = 0.6 S
                   as in Cross 2020 (their lift data scatter widely).
``choppin2018``    Real balls in match play (the default): C_D = 0.60 (Choppin et
                   al. 2018, 9,224 Hawk-Eye serves: 0.579 new, 0.603 used
                   balls), C_L = min(0.6 S, 0.5), blended smoothly (Cross 2020); evidence in
                   docs/validation.md.
``tennislab2026``  Identified from real 50 Hz match tracks by ``tennislab calibrate
                   tracks``: C_D falling with speed (0.81 at 15 m/s, 0.55 at 50),
                   C_L(S) piecewise linear; with a spin decay of 0.17 /s
                   (docs/validation.md).
``table``          C_D, C_L bilinearly interpolated over a grid of speed and
                   spin (e.g. wind-tunnel data), clamped at the grid's edges.

References
----------
.. [1] Stepanek (1988), Am. J. Phys. 56:138
.. [2] Grosen, Kousted & Treichel (2021), 2-dimensional tennis serves show similar successful mechanical
    parameter across physiological differences, Aalborg University (seed 000), eqs 3-4
.. [3] Wojcicki, Pucilowski & Kulesza (2010), Acta Mechanica et Automatica (seed 002), eqs 1 and 3
.. [4] Cross & Lindsey (2014), Sports Eng. 17:89
.. [5] Cross (2020), Sports Eng. 23:9
.. [6] Choppin et al. (2018), Proceedings 2:265
"""

from __future__ import annotations

import collections
import dataclasses
import functools
import hashlib
import inspect
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numba as nb
import numpy as np
from numba import types
from numba.extending import overload

from tennislab.core._jit import JIT, JIT_DYNAMIC
from tennislab.core.names import DEFAULT_AERO  # the default model (stated there, for --help)
from tennislab.errors import InputError, check_range

#: Numba signature of every aero kernel: (v [m/s], w [rad/s], r [m], params) -> (C_D, C_L)
AERO_SIGNATURE = types.UniTuple(types.float64, 2)(types.float64, types.float64, types.float64, types.float64[::1])
AERO_FUNCTION_TYPE = types.FunctionType(AERO_SIGNATURE)


@dataclass(frozen=True)
class AeroModel:
    """A named aerodynamic model: a compiled kernel and its parameters."""

    name: str
    kernel: Callable = field(repr=False)
    params: np.ndarray = field(repr=False)
    reference: str = ""
    #: default rtol = atol of :func:`tennislab.core.flight.fly_batch` for this model: the loosest that
    #: keeps landings within 0.01 mm of the reference (benchmarks/bench_flight_accuracy.py) [-]
    batch_tol: float = 2e-7
    #: the keyword arguments of the registered factory that built this model (``None`` values left out;
    #: ``{}`` = its defaults), so that ``get_aero_model(name, **options)`` rebuilds it; ``None`` for a
    #: model that no factory built (a callable), which cannot be rebuilt from its name
    options: dict | None = field(default=None, repr=False, compare=False)

    def __eq__(self, other) -> bool:
        """Same name, kernel, parameter values, reference and tolerance (the arrays compared by value)."""
        if not isinstance(other, AeroModel):
            return NotImplemented
        return (
            (self.name, self.kernel, self.reference, self.batch_tol)
            == (other.name, other.kernel, other.reference, other.batch_tol)
        ) and bool(np.array_equal(self.params, other.params))

    def coefficients(self, speed, spin, radius: float):
        """(C_D, C_L) for speed(s) [m/s] and spin rate(s) |omega| [rad/s] of a ball of radius [m]."""
        v = np.asarray(speed, dtype=float)
        w = np.asarray(spin, dtype=float)
        vb, wb = np.broadcast_arrays(v, w)
        cd = np.empty(vb.shape)
        cl = np.empty(vb.shape)
        for idx in np.ndindex(vb.shape):
            cd[idx], cl[idx] = self.kernel(float(vb[idx]), float(wb[idx]), float(radius), self.params)
        if cd.ndim == 0:
            return float(cd), float(cl)
        return cd, cl


# ---------------------------------------------------------------- inlining in compiled kernels
# A kernel reaches compiled code either as a first-class function (one compiled
# caller serves every kernel, through an indirect call) or as its *inline tag*:
# a one-field namedtuple whose class names the kernel, so that Numba compiles
# a caller specialised on it, with the formula inlined.  Tags exist for
# tennislab's own kernels only: their classes live in this module, so Numba's
# on-disk cache can key the specialised callers on them.
_INLINE_KERNEL: dict = {}  # tag class -> kernel
_TAG_SOURCE: dict = {}  # tag class -> the registered kernel itself
_INLINE_TAG: dict = {}  # kernel's (module, qualname) -> tag instance (not the dispatcher
# itself: one unpickled in a worker process is a new object)


def _kernel_key(kernel):
    f = getattr(kernel, "py_func", None)
    return None if f is None else (f.__module__, f.__qualname__)


def _core_digest() -> str:
    """Short hash of the names, sizes and modification times of the sources of :mod:`tennislab.core`.

    It is part of the tag classes' names, hence of the cache keys of every
    kernel compiled for a tag: Numba only checks the date of the file that
    holds a cached function, not of the kernels compiled into it, so without
    this an edited C_D formula or right-hand side could run from a stale cache.
    (File metadata, as Numba's own cache check uses: core reads no file.)
    """
    h = hashlib.sha256()
    for f in sorted(Path(__file__).parent.glob("*.py")):
        st = f.stat()
        h.update(f"{f.name}:{st.st_size}:{st.st_mtime_ns};".encode())
    return h.hexdigest()[:10]


_DIGEST = _core_digest()


def _inlinable(kernel):
    """Give one of this module's kernels an inline tag (decorator)."""
    name = "Inline" + kernel.py_func.__name__.title().replace("_", "") + "_" + _DIGEST
    cls = collections.namedtuple(name, ["unused"], module=__name__)
    globals()[name] = cls  # importable by name, hence picklable
    # compiled callers get the formula inlined in Numba's IR (a call to the dispatcher stays a call,
    # which keeps LLVM from vectorising the lockstep kernel's loops over shots)
    _INLINE_KERNEL[cls] = nb.njit(**JIT, inline="always")(kernel.py_func)
    _INLINE_TAG[_kernel_key(kernel)] = cls(0.0)
    _TAG_SOURCE[cls] = kernel
    return kernel


def __getattr__(name: str):
    """Placeholder for tag classes named in an on-disk Numba cache by another
    version of this module, so that the cache index still loads (its entries
    for the missing class then simply never match and are recompiled)."""
    if name.startswith("Inline"):
        return collections.namedtuple(name, ["unused"], module=__name__)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def inline_tag(kernel):
    """The inline tag of ``kernel`` (a namedtuple), or ``None`` for kernels without one."""
    return _INLINE_TAG.get(_kernel_key(kernel))


def aero_coefficients(aero, v, w, r, p):
    """(C_D, C_L) from ``aero`` (a kernel or its inline tag) at speed v, spin w, radius r."""
    kernel = _INLINE_KERNEL.get(type(aero), aero)
    return kernel(v, w, r, p)


@overload(aero_coefficients, inline="always")
def _aero_coefficients_compiled(aero, v, w, r, p):
    if isinstance(aero, types.BaseNamedTuple):
        kernel = _INLINE_KERNEL.get(aero.instance_class)
        if kernel is None:
            return None

        def tagged(aero, v, w, r, p):
            return kernel(v, w, r, p)

        return tagged

    def first_class(aero, v, w, r, p):
        return aero(v, w, r, p)

    return first_class


def cap_distance(aero, v, w, r, p):
    """c_l S - cap [-] of a capped linear-lift model (its blend zone is where this is within a few
    :data:`_CAP_BLEND`); -inf for every other model (no zone).  See :data:`CAP_ZONE`."""
    if _TAG_SOURCE.get(type(aero)) is not _linear_lift_kernel or v <= 0.0:
        return -math.inf
    return p[1] * r * w / v - p[2]


@overload(cap_distance, inline="always")
def _cap_distance_compiled(aero, v, w, r, p):
    if isinstance(aero, types.BaseNamedTuple) and _TAG_SOURCE.get(aero.instance_class) is _linear_lift_kernel:

        def linear(aero, v, w, r, p):
            return p[1] * r * w / v - p[2] if v > 0.0 else -math.inf

        return linear

    def none(aero, v, w, r, p):
        return -math.inf

    return none


# ---------------------------------------------------------------- kernels
@_inlinable
@nb.njit(AERO_SIGNATURE, **JIT)
def _constant_kernel(v, w, r, p):
    return p[0], p[1]


@_inlinable
@nb.njit(AERO_SIGNATURE, **JIT)
def _stepanek_kernel(v, w, r, p):
    # Seed 000 eqs 3-4 (Stepanek 1988).  p = (C_D0, a, b, h, q): C_D = C_D0 + 1/(a + b (v/rw)^h)^q
    rw = r * w
    if rw <= 0.0:
        return p[0], 0.0
    if v <= 0.0:
        return p[0] + 1.0 / p[1] ** p[4], 0.5
    x = v / rw
    xh = x * x * math.sqrt(x) if p[3] == 2.5 else x ** p[3]  # fast path for the published h
    cd = p[0] + (p[1] + p[2] * xh) ** (-p[4])
    cl = 1.0 / (2.0 + x)
    return cd, cl


#: Width [-] of the smooth cap of the linear-lift models: with a = c_l S and b = cl_max,
#: C_L = (a + b - sqrt((a - b)^2 + e^2)) / 2 + (sqrt(b^2 + e^2) - b) / 2, a smooth minimum of a and
#: b shifted so that C_L(0) = 0 exactly (no lift without spin, none reversed at low spin).  A hard
#: min() puts a kink in the force that the embedded error estimate of the batch integrator does not
#: see (choppin2018 landings 0.44 mm from the reference at rtol 2e-7, against 0.003 mm for the uncapped
#: models).  Against min(a, b) the blend differs by at most e / 2 = 0.01 at a = b, by at most 0.00052
#: (0.14 %) for S <= 0.6 at c_l = 0.6, and by e^2 / (4 b) = 0.0002 far above the cap: far inside the
#: scatter of measured lift (Cross 2020, +-0.05).
_CAP_BLEND = 0.02
#: Half-width of the capped lift's blend zone, in units of :data:`_CAP_BLEND` of c_l S - cap: a step that
#: starts or ends there, or crosses the cap, is held to a tolerance :data:`CAP_ZONE_ERR` times tighter.
#: The blend's n-th derivative grows as _CAP_BLEND^(1-n) near the cap, where the 5th-order solution kept
#: loses the margin over the 4th-order error estimate that the default tolerance relies on elsewhere:
#: on 3,000 mixed shots at 2e-7 the flights passing within one blend width of the cap landed up to
#: 0.042 mm from the reference, all others within 0.0017 mm (as the uncapped models).
CAP_ZONE = 2.0
#: the error scale of a step in the blend zone (10: the zone's steps as at rtol = atol 2e-8)
CAP_ZONE_ERR = 10.0
#: batch tolerance of the piecewise-linear ``curves`` models (their knots are kinks; docs/flight.md, Accuracy:
#: the loosest with a margin over 1.5 on 9,000 shots of choppin2018 when its cap was flown that way); the
#: capped linear-lift models fly at 2e-7, their blend zone held to a tighter error by the kernels (CAP_ZONE)
CAPPED_BATCH_TOL = 2e-8


@_inlinable
@nb.njit(AERO_SIGNATURE, **JIT)
def _linear_lift_kernel(v, w, r, p):
    # C_D constant, C_L = c_l * r w / v (seed 002 eq 3), capped at p[2]
    # (each value assigned once: the formula is inlined into compiled callers' IR)
    if v <= 0.0:
        return p[0], 0.0
    lin = p[1] * r * w / v
    cap = p[2]
    if cap < math.inf:  # a smooth minimum of c_l S and the cap, zero at S = 0 (see _CAP_BLEND)
        d = cap - lin
        e2 = _CAP_BLEND * _CAP_BLEND
        return p[0], 0.5 * (lin + cap - math.sqrt(d * d + e2)) + 0.5 * (math.sqrt(cap * cap + e2) - cap)
    return p[0], lin


@nb.njit(**JIT, inline="always")
def _locate(p, off, n, x):
    """(cell index, fraction) of x on the grid p[off:off + n], clamped at its ends."""
    if n == 1 or x <= p[off]:
        return 0, 0.0
    if x >= p[off + n - 1]:
        return n - 2, 1.0
    i = 0
    while p[off + i + 1] < x:
        i += 1
    return i, (x - p[off + i]) / (p[off + i + 1] - p[off + i])


@_inlinable
@nb.njit(AERO_SIGNATURE, **JIT)
def _table_kernel(v, w, r, p):
    # p = [nv, nw, v_0..v_nv-1, w_0..w_nw-1, cd (nv*nw, row-major in v), cl (same)]
    nv = int(p[0])
    nw = int(p[1])
    ov = 2
    ow = 2 + nv
    ocd = ow + nw
    ocl = ocd + nv * nw
    i, tv = _locate(p, ov, nv, v)
    j, tw = _locate(p, ow, nw, w)
    i1 = min(i + 1, nv - 1)
    j1 = min(j + 1, nw - 1)
    out0 = 0.0
    out1 = 0.0
    for k in range(2):
        base = ocd if k == 0 else ocl
        a = p[base + i * nw + j]
        b = p[base + i1 * nw + j]
        c = p[base + i * nw + j1]
        d = p[base + i1 * nw + j1]
        val = a * (1 - tv) * (1 - tw) + b * tv * (1 - tw) + c * (1 - tv) * tw + d * tv * tw
        if k == 0:
            out0 = val
        else:
            out1 = val
    return out0, out1


@_inlinable
@nb.njit(AERO_SIGNATURE, **JIT)
def _curves_kernel(v, w, r, p):
    # p = [nv, ns, v_0..v_nv-1, cd_0..cd_nv-1, S_1..S_ns, cl_1..cl_ns, cd_s, S_drag_max]:
    # C_D = cd(v) + cd_s min(S, S_drag_max), C_L = cl(S); both piecewise linear, clamped beyond the
    # last knot, C_L rising linearly from (0, 0) to the first knot (no lift without spin)
    nv = int(p[0])
    ns = int(p[1])
    ov = 2
    ocd = ov + nv
    osk = ocd + nv
    ocl = osk + ns
    i, tv = _locate(p, ov, nv, v)
    cd = p[ocd + i] * (1.0 - tv) + p[ocd + min(i + 1, nv - 1)] * tv
    s = r * w / v if v > 0.0 else (math.inf if w > 0.0 else 0.0)
    if s <= p[osk]:
        cl = p[ocl] * s / p[osk]
    else:
        j, ts = _locate(p, osk, ns, s)
        cl = p[ocl + j] * (1.0 - ts) + p[ocl + min(j + 1, ns - 1)] * ts
    cd += p[ocl + ns] * min(s, p[ocl + ns + 1])
    return cd, cl


# ---------------------------------------------------------------- registry
_REGISTRY: dict[str, Callable[..., AeroModel]] = {}


def register_aero(name: str, *aliases: str):
    """Decorator registering a factory ``f(**params) -> AeroModel`` under ``name``.

    The registered factory records the arguments it was called with in the model's
    :attr:`AeroModel.options` (what ``FlightParams.to_dict`` writes and ``from_dict`` rebuilds from).
    """

    def deco(factory):
        sig = inspect.signature(factory)

        @functools.wraps(factory)
        def build(*args, **kwargs) -> AeroModel:
            model = factory(*args, **kwargs)
            given = {k: v for k, v in sig.bind(*args, **kwargs).arguments.items() if v is not None}
            return dataclasses.replace(model, options=given)

        for n in (name, *aliases):
            _REGISTRY[n] = build
        return build

    return deco


def aero_model_names() -> list[str]:
    """Names of all registered aero models."""
    return sorted(_REGISTRY)


def _params(*vals) -> np.ndarray:
    a = np.ascontiguousarray(np.array(vals, dtype=np.float64))
    return a


@register_aero("constant")
def constant(cd: float = 0.55, cl: float = 0.0) -> AeroModel:
    """Constant C_D and C_L [-] (user-given constants, e.g. a wind-tunnel point).

    Parameters
    ----------
    cd : drag coefficient C_D [-], 0-2
    cl : lift coefficient C_L [-], -2-2

    Returns
    -------
    AeroModel ``constant``

    References
    ----------
    .. [1] Cross & Lindsey (2014), Sports Eng. 17:89: C_D of tennis balls in flight is nearly constant
       (0.507 +- 0.024 at 15-30 m/s), the case this model represents.
    """
    cd = check_range("cd", cd, 0.0, 2.0)
    cl = check_range("cl", cl, -2.0, 2.0)
    return AeroModel("constant", _constant_kernel, _params(cd, cl), "user-given constants")


@register_aero("stepanek1988")
def stepanek1988(cd0: float = 0.55, cd: float | None = None, cl: float | None = None) -> AeroModel:
    """Stepanek (1988) C_D(S), C_L(S) as written in seed 000 eqs 3-4.

    C_D = C_D0 + 1/(22.5 + 4.2 (v/(r w))^2.5)^0.4 and C_L = 1/(2 + v/(r w)), with the spin ratio
    S = r w / v; fitted at 13-27 m/s and 800-3250 rpm (module docstring).

    Parameters
    ----------
    cd0 : base drag C_D0 [-] (0.55)
    cd : replaces ``cd0`` when given [-], 0-2
    cl : not used by this model (C_L comes from the spin); refused

    Returns
    -------
    AeroModel ``stepanek1988``

    References
    ----------
    .. [1] Stepanek (1988), Am. J. Phys. 56:138.
    .. [2] Grosen, Kousted & Treichel (2021), Aalborg University (seed 000), eqs 3-4.
    """
    if cl is not None:
        raise InputError('cl: the stepanek1988 model computes C_L from spin; use aero="constant" to set it')
    base = check_range("cd", cd0 if cd is None else cd, 0.0, 2.0)
    return AeroModel(
        "stepanek1988",
        _stepanek_kernel,
        _params(base, 22.5, 4.2, 2.5, 0.4),
        "Stepanek 1988 Am. J. Phys. 56:138; seed 000 eqs 3-4",
    )


@register_aero("launcher2015", "wojcicki2010")
def launcher2015(cd: float = 0.55, cl: float = 0.6, cl_max: float = math.inf) -> AeroModel:
    """Seed 002 eqs 1, 3: constant c_d; Magnus 1/2 c_l pi r^3 rho omega x v (C_L = c_l r w / v).

    The seed's lift grows without bound with spin; ``cl_max`` optionally caps C_L
    (a cap makes the right-hand side non-smooth; default: no cap, as published).

    Parameters
    ----------
    cd : drag coefficient c_d [-], 0-2 (0.55: the low end of Alam et al. 2007's 0.55-0.85, quoted by the seed)
    cl : lift slope c_l [-], -5-5 (0.6, Cross 2020)
    cl_max : cap of C_L [-] (inf: none)

    Returns
    -------
    AeroModel ``launcher2015`` (alias ``wojcicki2010``)

    References
    ----------
    .. [1] Wojcicki, Pucilowski & Kulesza (2010), Acta Mechanica et Automatica (seed 002), eqs 1 and 3.
    .. [2] Alam et al. (2007), as quoted by seed 002 (c_d 0.55-0.85).
    .. [3] Cross (2020), Sports Eng. 23:9 (C_L = 0.6 S).
    """
    cd = check_range("cd", cd, 0.0, 2.0)
    cl = check_range("cl", cl, -5.0, 5.0)
    return AeroModel(
        "launcher2015",
        _linear_lift_kernel,
        _params(cd, cl, cl_max),
        "seed 002 eqs 1, 3; c_d after Alam et al. 2007, c_l after Cross 2020",
        batch_tol=2e-7,
    )


@register_aero("cross2014")
def cross2014(cd: float = 0.507, cl: float = 0.6, cl_max: float = math.inf) -> AeroModel:
    """In-flight C_D = 0.507 (Cross & Lindsey 2014); C_L = 0.6 S (Cross 2020).

    Parameters
    ----------
    cd : drag coefficient [-], 0-2 (0.507)
    cl : lift slope [-], -5-5 (0.6): C_L = cl S, S = r w / v
    cl_max : cap of C_L [-] (inf: none)

    Returns
    -------
    AeroModel ``cross2014``

    References
    ----------
    .. [1] Cross & Lindsey (2014), Sports Eng. 17:89 (launcher, 15-30 m/s, up to 2500 rpm).
    .. [2] Cross (2020), Sports Eng. 23:9.
    """
    cd = check_range("cd", cd, 0.0, 2.0)
    cl = check_range("cl", cl, -5.0, 5.0)
    return AeroModel(
        "cross2014",
        _linear_lift_kernel,
        _params(cd, cl, cl_max),
        "Cross & Lindsey 2014 Sports Eng. 17:89; Cross 2020 Sports Eng. 23:9",
        batch_tol=2e-7,
    )


@register_aero("choppin2018")
def choppin2018(cd: float = 0.60, cl: float = 0.6, cl_max: float = 0.5) -> AeroModel:
    """Real balls in match play: C_D = 0.60 constant, C_L = min(0.6 S, 0.5) (smoothly: :data:`_CAP_BLEND`), S = r w / v.

    C_D: Choppin et al. 2018 (Proceedings 2:265) found effective drag coefficients of 0.579 (new
    balls) and 0.603 (used balls) from 9,224 timed Hawk-Eye serves; the 50 Hz tracks of a
    professional match behind issue 13 converge to 0.60-0.61 whatever the model family; in-flight
    launcher measurements found C_D independent of speed and spin (Cross & Lindsey 2014, Sports Eng.
    17:89, 0.507 +- 0.024 at 15-30 m/s).  C_L = 0.6 S as in Cross 2020 (Sports Eng. 23:9), capped at
    Stepanek's limit 1/2.  On 13,092 CourtVision serves (docs/validation.md) it reaches the measured
    bounce with a held-out median miss of 0.225 m and -1.3 cm length bias (spin axis fitted per serve
    type), as good as ``stepanek1988`` there, whose drag at rally spin ratios (0.69-0.75) is above
    what real match flights show.  The default model (:data:`DEFAULT_AERO`).

    Parameters
    ----------
    cd : drag coefficient [-], 0-2 (0.60)
    cl : lift slope [-], -5-5 (0.6): C_L = cl S, S = r w / v
    cl_max : cap of C_L [-] (0.5, Stepanek's limit)

    Returns
    -------
    AeroModel ``choppin2018``

    References
    ----------
    .. [1] Choppin et al. (2018), Proceedings 2:265 (effective C_D of 9,224 Hawk-Eye serves).
    .. [2] Cross & Lindsey (2014), Sports Eng. 17:89.
    .. [3] Cross (2020), Sports Eng. 23:9.
    .. [4] Stepanek (1988), Am. J. Phys. 56:138 (C_L tends to 1/2).
    """
    cd = check_range("cd", cd, 0.0, 2.0)
    cl = check_range("cl", cl, -5.0, 5.0)
    return AeroModel(
        "choppin2018",
        _linear_lift_kernel,
        _params(cd, cl, cl_max),
        "Choppin et al. 2018 Proceedings 2:265; Cross 2020 Sports Eng. 23:9; docs/validation.md",
        # the cap's blend (_CAP_BLEND) bends the force faster than the uncapped models: the kernels hold
        # the steps in its zone to a tighter error (CAP_ZONE), so the model flies at the others' tolerance
        batch_tol=2e-7,
    )


#: allowed ranges of a table's values: C_D, C_L [-] (as the constant model), speed [m/s], spin [rad/s]
TABLE_CD_RANGE = (0.0, 2.0)
TABLE_CL_RANGE = (-2.0, 2.0)
TABLE_SPEED_RANGE = (0.0, 200.0)
TABLE_SPIN_RANGE = (0.0, 20_000.0 * 2.0 * math.pi / 60.0)  # 20,000 rpm
#: most grid points of a table
TABLE_MAX_POINTS = 100_000


@register_aero("table")
def table(speed=None, spin=None, cd=None, cl=None) -> AeroModel:
    """C_D, C_L interpolated over a grid: ``speed`` [m/s] (n), ``spin`` [rad/s] (m), ``cd``, ``cl`` (n x m).

    Core reads no file: a CSV (columns ``speed_ms, spin_rpm, cd, cl``) is read by
    :func:`tennislab.io.aero_table.read_aero_table` at the edge and its arrays
    passed here (``FlightParams.from_options(aero="table", aero_table=...)``).
    Values are range-checked (:data:`TABLE_CD_RANGE`, :data:`TABLE_CL_RANGE`,
    :data:`TABLE_SPEED_RANGE`, :data:`TABLE_SPIN_RANGE`): a C_L of 10^6 would
    make the flight a stiff problem no integrator finishes, not a study.

    Parameters
    ----------
    speed : grid of air speeds [m/s] (n), increasing
    spin : grid of spin rates [rad/s] (m), increasing
    cd, cl : C_D and C_L [-] on the grid (n x m)

    Returns
    -------
    AeroModel ``table`` (bilinear interpolation, clamped at the grid's edges)

    References
    ----------
    .. [1] the calibrated family of :mod:`tennislab.calibrate.family` writes such tables (docs/validation.md).
    """
    if speed is None or spin is None or cd is None or cl is None:
        raise InputError("aero_table: the table model needs speed, spin, cd and cl arrays (from io.read_aero_table)")
    try:
        v: np.ndarray = np.asarray(speed, dtype=float).ravel()
        w: np.ndarray = np.asarray(spin, dtype=float).ravel()
        cda: np.ndarray = np.asarray(cd, dtype=float).reshape(len(v), len(w))
        cla: np.ndarray = np.asarray(cl, dtype=float).reshape(len(v), len(w))
    except (TypeError, ValueError):
        raise InputError("aero_table: speed, spin, cd and cl must be numbers, cd and cl (speeds x spins)") from None
    if v.size * w.size > TABLE_MAX_POINTS:
        raise InputError(f"aero_table: {v.size * w.size} grid points; at most {TABLE_MAX_POINTS} allowed")
    arr: np.ndarray
    for nm, arr, (lo, hi), unit, scale in (
        ("speed", v, TABLE_SPEED_RANGE, "m/s", 1.0),
        ("spin", w, TABLE_SPIN_RANGE, "rpm", 60.0 / (2.0 * math.pi)),
    ):
        if len(arr) < 1 or not np.all(np.isfinite(arr)) or np.any(np.diff(arr) <= 0):
            raise InputError(f"aero_table: the {nm} grid must be finite and strictly increasing")
        bad = (arr < lo) | (arr > hi)
        if bad.any():
            raise InputError(
                f"aero_table: {nm} {arr[bad][0] * scale:g} {unit} is outside the allowed range "
                f"[{lo * scale:g}, {hi * scale:g}] {unit}"
            )
    for nm, arr, (lo, hi) in (("cd", cda, TABLE_CD_RANGE), ("cl", cla, TABLE_CL_RANGE)):
        bad = ~np.isfinite(arr) | (arr < lo) | (arr > hi)
        if bad.any():
            i, j = np.argwhere(bad)[0]
            raise InputError(
                f"aero_table: {nm} = {arr[i, j]:g} at speed {v[i]:g} m/s, spin {w[j] * 60 / (2 * math.pi):g} rpm "
                f"is outside the allowed range [{lo:g}, {hi:g}]"
            )
    p = _params(len(v), len(w), *v, *w, *cda.ravel(), *cla.ravel())
    return AeroModel("table", _table_kernel, p, "user table")


#: allowed ranges of a ``curves`` model: knots' speed [m/s] and spin parameter [-], and the drag growth
#: with S (C_D and C_L as :data:`TABLE_CD_RANGE`, :data:`TABLE_CL_RANGE`)
CURVES_SPEED_RANGE = (0.0, 200.0)
CURVES_S_RANGE = (0.0, 10.0)
CURVES_CD_S_RANGE = (-2.0, 5.0)
#: spin parameter beyond which a ``curves`` model holds its drag term cd_s S (as the calibrated family)
CURVES_S_DRAG_MAX = 0.5
CURVES_MAX_KNOTS = 64  #: most knots of one curve


def _knots(name: str, x, y, xr, yr) -> tuple[np.ndarray, np.ndarray]:
    try:
        xa = np.asarray(x, dtype=float).ravel()
        ya = np.asarray(y, dtype=float).ravel()
    except (TypeError, ValueError):
        raise InputError(f"{name}: expected numbers") from None
    if xa.size < 1 or xa.size != ya.size or xa.size > CURVES_MAX_KNOTS:
        raise InputError(f"{name}: 1 to {CURVES_MAX_KNOTS} knots with one value each (got {xa.size}, {ya.size})")
    if not (np.all(np.isfinite(xa)) and np.all(np.diff(xa) > 0) and xa[0] > xr[0] and xa[-1] <= xr[1]):
        raise InputError(f"{name}: knots must be finite, strictly increasing, in ({xr[0]:g}, {xr[1]:g}]")
    bad = ~np.isfinite(ya) | (ya < yr[0]) | (ya > yr[1])
    if bad.any():
        raise InputError(f"{name}: {ya[bad][0]:g} is outside the allowed range [{yr[0]:g}, {yr[1]:g}]")
    return xa, ya


def curves_drag_positive(cd_min: float, cd_s: float) -> bool:
    """Whether curves with least drag coefficient ``cd_min`` [-] and drag growth ``cd_s`` [-] keep a positive
    drag at every spin parameter up to :data:`CURVES_S_DRAG_MAX` (the rule of :func:`curves_model`)."""
    return cd_min + min(cd_s, 0.0) * CURVES_S_DRAG_MAX > 0.0


def curves_model(speed, cd, spin_parameter, cl, cd_s: float = 0.0, name: str = "curves") -> AeroModel:
    """Piecewise-linear curves: C_D = cd(v) + cd_s min(S, 0.5) and C_L = cl(S), S = r w / v.

    ``speed`` [m/s] and ``cd`` [-] are the drag curve's knots (held constant beyond the first and last),
    ``spin_parameter`` [-] (> 0) and ``cl`` [-] the lift curve's (linear from C_L = 0 at S = 0 to the
    first knot, held beyond the last); ``cd_s`` [-] the growth of drag with S (held beyond
    :data:`CURVES_S_DRAG_MAX`).  The form of the identified model (``tennislab2026``) and of
    ``tennislab calibrate tracks`` (not registered by itself: a model of this form is rebuilt from its
    name and knots only as ``tennislab2026``, or written as a table); its piecewise-linear kinks get
    :data:`CAPPED_BATCH_TOL`.
    """
    v, c_d = _knots("cd", speed, cd, CURVES_SPEED_RANGE, TABLE_CD_RANGE)
    s, c_l = _knots("cl", spin_parameter, cl, CURVES_S_RANGE, TABLE_CL_RANGE)
    cds = check_range("cd_s", cd_s, *CURVES_CD_S_RANGE)
    if not curves_drag_positive(float(c_d.min()), cds):
        raise InputError("cd_s: drag would turn negative at high spin; raise cd or cd_s")
    p = _params(len(v), len(s), *v, *c_d, *s, *c_l, cds, CURVES_S_DRAG_MAX)
    return AeroModel(name, _curves_kernel, p, "piecewise-linear curves", batch_tol=CAPPED_BATCH_TOL)


#: knots of ``tennislab2026`` (docs/validation.md, "A ball identified from real flights"): drag speeds
#: [m/s] and C_D, lift spin parameters and C_L (the first held at 0.6 S)
TENNISLAB2026_SPEED = (10.0, 15.0, 20.0, 25.0, 30.0, 35.0, 40.0, 50.0, 60.0)
TENNISLAB2026_CD = (1.040, 0.805, 0.744, 0.668, 0.631, 0.589, 0.575, 0.548, 0.539)
TENNISLAB2026_S = (0.1, 0.2, 0.3, 0.4, 0.6)
TENNISLAB2026_CL = (0.060, 0.161, 0.250, 0.338, 0.454)
#: [1/s] the spin decay identified with it (a flight setting, not the aero model's: ``--spin-decay``)
TENNISLAB2026_SPIN_DECAY = 0.174


@register_aero("tennislab2026")
def tennislab2026() -> AeroModel:
    """Identified from the real 50 Hz tracks of a professional match (tennislab 2026): piecewise-linear
    C_D(v) and C_L(S) (:func:`curves_model`; knots :data:`TENNISLAB2026_SPEED` / :data:`TENNISLAB2026_CD`,
    :data:`TENNISLAB2026_S` / :data:`TENNISLAB2026_CL`).

    Data: set 1 of ``../shared/realdata/match50hz-set1`` (79 points), cut into 239 hit-to-bounce flights;
    fitted on the 111 flights of the odd games, held out on the 128 of the even ones.  Method
    (``tennislab calibrate tracks``, :mod:`tennislab.calibrate.identify`): the curves jointly with every
    flight's state, spin (perpendicular to its path) and drag scale (prior sigma 0.15; the curves are the
    median flight's; shot-to-shot p10-p90 0.77-1.13), variable projection through core's RK4, sandwich
    standard errors clustered by flight.  C_D falls with speed, 0.805 +- 0.033 at 15 m/s, 0.668 +- 0.017
    at 25, 0.589 +- 0.016 at 35, 0.548 +- 0.013 at 50 m/s (1.04 +- 0.08 at 10 m/s, from few slow balls;
    held constant outside 10-60 m/s); C_L 0.161 +- 0.035 at S 0.2, 0.250 +- 0.073 at 0.3, 0.454 +- 0.029
    at 0.6 with its scale held at 0.6 S at S = 0.1 (Cross 2020; positions cannot fix it); spin decay
    0.174 +- 0.112 /s (:data:`TENNISLAB2026_SPIN_DECAY`, given separately as ``spin_decay``).  Held out,
    each flight refitted alone: median whole-flight residual 5.92 -> 4.92 mm against ``choppin2018``
    (serves 2.71 -> 2.53, rally shots 6.92 -> 6.64 mm), p90 12.2 -> 14.2 mm; CourtVision serves in
    docs/validation.md.  Not the default: the held-out evidence is mixed (docs/validation.md).

    References
    ----------
    .. [1] tennislab (2026), docs/validation.md, "A ball identified from real flights" (the data, the
       command, the held-out residuals and the CourtVision validation).
    .. [2] Golub & Pereyra (1973), SIAM J. Numer. Anal. 10:413 (variable projection).
    .. [3] Cross (2020), Sports Eng. 23:9 (C_L = 0.6 S, the anchor of the lift's scale).
    .. [4] Cross & Lindsey (2014), Sports Eng. 17:89 (shot-to-shot variation of C_D in flight).
    """
    return dataclasses.replace(
        curves_model(
            TENNISLAB2026_SPEED, TENNISLAB2026_CD, TENNISLAB2026_S, TENNISLAB2026_CL, 0.0, name="tennislab2026"
        ),
        reference="tennislab 2026, docs/validation.md (50 Hz match tracks, calibrate tracks)",
    )


def callable_model(fn: Callable[[float, float], tuple[float, float]], name: str = "callable") -> AeroModel:
    """Wrap ``fn(speed [m/s], spin [rad/s]) -> (C_D, C_L)`` as an :class:`AeroModel`.

    The function is compiled with Numba so that the batch path can use it; a
    function Numba cannot compile raises :class:`InputError`.
    """
    try:
        jf = nb.njit(**JIT_DYNAMIC)(fn)

        @nb.njit(AERO_SIGNATURE, **JIT_DYNAMIC)
        def _wrapped(v, w, r, p):
            a, b = jf(v, w)
            return float(a), float(b)
    except Exception as exc:  # numba raises many error types
        first = str(exc).strip().splitlines()[0][:160] if str(exc).strip() else ""
        raise InputError(
            f"aero: callable {name!r} cannot be compiled by Numba ({type(exc).__name__}: {first})"
        ) from None
    return AeroModel(name, _wrapped, _params(0.0), "user callable")


def get_aero_model(model=None, **params) -> AeroModel:
    """Resolve an aero model by registered name, :class:`AeroModel` or callable ``f(v, w) -> (cd, cl)``.

    Keyword parameters go to the model's factory; ``None`` values are dropped.
    ``model=None`` is :data:`DEFAULT_AERO`.
    """
    params = {k: v for k, v in params.items() if v is not None}
    if model is None:
        model = DEFAULT_AERO
    if isinstance(model, AeroModel):
        if params:
            raise InputError("aero: parameters cannot be applied to an already built model")
        return model
    if callable(model):
        return callable_model(model)
    if model not in _REGISTRY:
        raise InputError(f"aero: unknown model {model!r}; allowed: {', '.join(aero_model_names())}")
    try:
        return _REGISTRY[model](**params)
    except TypeError:
        raise InputError(f"aero: model {model!r} does not take parameters {sorted(params)}") from None


def spin_parameter(speed, spin, radius):
    """Spin parameter S = r |omega| / v [-]."""
    return radius * np.asarray(spin) / np.asarray(speed)
