r"""The Johnson translation system (Johnson 1949) fitted to a skewness and kurtosis.

Every attainable pair (skewness, kurtosis) with Sku > Ssk² + 1 has exactly one Johnson member:
S_U above the lognormal line, S_B below it, S_L on it, S_N at (0, 3). :func:`johnson_for` fits
(gamma, delta) to the shape and (xi, lambda) to zero mean and the target variance. Used for
the non-Gaussian heights of :mod:`roughgp.non_gaussian` (a noise model of eq 8).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import scipy.optimize
import scipy.special
import scipy.stats

from roughgp.common.checks import check_finite, check_positive

FAMILIES = ("SU", "SB", "SL", "SN")
_LINE_TOLERANCE = 1e-9   # relative distance to the lognormal line treated as on it (SL / SN)
_MOMENT_TOLERANCE = 1e-9  # a fit is accepted when skewness and kurtosis match to this
_SU_MIN_DELTA = 0.1      # below it SU's kurtosis exceeds ~1e170: float64 moments overflow
_SB_MIN_DELTA = 0.01     # SB this close to the two-point boundary Sku = Ssk^2 + 1 is refused
_LOG_SQRT_2PI = 0.5 * math.log(2 * math.pi)


class Moments(NamedTuple):
    """Mean, variance, skewness and (Pearson, normal = 3) kurtosis of a distribution."""

    mean: float
    variance: float
    skewness: float
    kurtosis: float


# ------------------------------------------------------------------ moments of the families


def _su_shape(delta, log_q):
    """Skewness and kurtosis of sinh((X - gamma)/delta) for gamma = delta * Omega >= 0, in terms
    of log_q = -2 Omega (scaled by exp(-2 Omega) so that Omega -> inf, the lognormal limit,
    is q = 0). Johnson (1949): with w = exp(1/delta^2)

    mu2 = (w-1)(w cosh 2Omega + 1)/2, mu3 = -sqrt(w)(w-1)^2 (w(w+2) sinh 3Omega + 3 sinh Omega)/4,
    mu4 = (w-1)^2 (w^2 (w^4+2w^3+3w^2-3) cosh 4Omega + 4 w^2 (w+2) cosh 2Omega + 3(2w+1))/8."""
    w = math.exp(1.0 / delta**2)
    wm1 = math.expm1(1.0 / delta**2)
    q = math.exp(log_q)
    m2 = wm1 * (w * (1 + q * q) / 2 + q) / 2
    m3 = -0.25 * math.sqrt(w) * wm1**2 * (w * (w + 2) * (1 - q**3) / 2 + 3 * (q - q * q) / 2)
    m4 = 0.125 * wm1**2 * (w * w * (w**4 + 2 * w**3 + 3 * w * w - 3) * (1 + q**4) / 2
                           + 4 * w * w * (w + 2) * (q + q**3) / 2 + 3 * (2 * w + 1) * q * q)
    return m3 / m2**1.5, m4 / m2**2


def _su_moments(gamma, delta):
    w = math.exp(1.0 / delta**2)
    omega = gamma / delta
    mean = -math.sqrt(w) * math.sinh(omega)
    variance = math.expm1(1.0 / delta**2) * (w * math.cosh(2 * omega) + 1) / 2
    skew, kurt = _su_shape(delta, -2 * abs(omega))
    return Moments(mean, variance, math.copysign(1.0, omega) * skew if omega else 0.0, kurt)


def _sb_moments(gamma, delta):
    """Moments of expit((X - gamma)/delta) by the trapezoidal rule on the normal density
    (exponentially accurate for this analytic integrand: step <= delta/4 keeps the error below
    exp(-8 pi^2)), in log space so that a tiny bounded variable (large gamma/delta) neither
    underflows nor loses its relative precision."""
    if gamma < 0:
        m = _sb_moments(-gamma, delta)   # expit((X + g)/d) = 1 - expit((-X - g)/d): reflection
        return Moments(1 - m.mean, m.variance, -m.skewness, m.kurtosis)
    h = min(0.02, delta / 4)
    upper = 13.0 + min(4.0 / delta, gamma)   # the 4th moment's mass lies near min(4/delta, gamma)
    x = np.arange(-13.0, upper + h, h)
    log_weight = -0.5 * x * x - _LOG_SQRT_2PI + math.log(h)
    log_y = -np.logaddexp(0.0, -(x - gamma) / delta)
    log_mean = scipy.special.logsumexp(log_weight + log_y)
    d = np.expm1(log_y - log_mean)                            # y / mean - 1
    with np.errstate(divide="ignore"):
        log_d = np.log(np.abs(d))
    sign = np.sign(d)
    log_m2 = scipy.special.logsumexp(log_weight + 2 * log_d)
    log_m3, sign3 = scipy.special.logsumexp(log_weight + 3 * log_d, b=sign, return_sign=True)
    log_m4 = scipy.special.logsumexp(log_weight + 4 * log_d)
    return Moments(math.exp(log_mean), math.exp(log_m2 + 2 * log_mean),
                   float(sign3) * math.exp(log_m3 - 1.5 * log_m2), math.exp(log_m4 - 2 * log_m2))


def lognormal_kurtosis(skewness):
    """The lognormal line: kurtosis of the lognormal (Johnson S_L) with this skewness, and its
    w = exp(sigma^2). w solves (w + 2)^2 (w - 1) = skewness^2; kurtosis = w^4 + 2w^3 + 3w^2 - 3."""
    b1 = float(skewness) ** 2
    root = math.sqrt(b1 + b1 * b1 / 4)
    w = np.cbrt(1 + b1 / 2 + root) + np.cbrt(1 + b1 / 2 - root) - 1
    for _ in range(3):  # Newton polish of w^3 + 3 w^2 - 4 - b1 = 0
        w -= (w**3 + 3 * w * w - 4 - b1) / (3 * w * w + 6 * w) if w > 1 else 0.0
    w = max(float(w), 1.0)
    return w**4 + 2 * w**3 + 3 * w * w - 3, w


# ------------------------------------------------------------------------------ the family


@dataclass(frozen=True)
class Johnson:
    r"""A member of the Johnson system, :math:`Z = \xi + \lambda f^{-1}((X - \gamma)/\delta)`
    with X standard normal (scipy's ``johnsonsu/johnsonsb(a=gamma, b=delta, loc=xi,
    scale=lam)``). ``family``: ``"SU"`` (sinh, unbounded), ``"SB"`` (expit, bounded to
    (xi, xi + lam)), ``"SL"`` (exp, lognormal; ``lam < 0`` is the reflected lognormal, gamma = 0),
    ``"SN"`` (identity, normal; gamma = 0, delta = 1)."""

    family: str
    gamma: float
    delta: float
    xi: float
    lam: float

    def __post_init__(self):
        if self.family not in FAMILIES:
            raise ValueError(f"family must be one of {FAMILIES}, got {self.family!r}")
        check_finite("gamma", self.gamma)
        check_finite("xi", self.xi)
        check_positive("delta", self.delta)
        check_finite("lam", self.lam)
        if self.lam == 0 or (self.lam < 0 and self.family != "SL"):
            raise ValueError(f"lam must be > 0 (or < 0 for a reflected SL), got {self.lam!r}")

    def _base(self, u):
        return {"SU": np.sinh, "SB": scipy.special.expit, "SL": np.exp,
                "SN": lambda v: v}[self.family](u)

    def transform(self, x):
        """Heights Z = T(x) of standard-normal values x (any shape)."""
        return self.xi + self.lam * self._base((np.asarray(x, dtype=np.float64) - self.gamma)
                                               / self.delta)

    def inverse(self, z):
        """The standard-normal value x with T(x) = z (z inside the support)."""
        u = (np.asarray(z, dtype=np.float64) - self.xi) / self.lam
        with np.errstate(divide="ignore", invalid="ignore"):
            f = {"SU": np.arcsinh, "SB": scipy.special.logit, "SL": np.log,
                 "SN": lambda v: v}[self.family](u)
        return self.gamma + self.delta * f

    def pdf(self, z):
        """Density of Z (0 outside the support)."""
        u = (np.asarray(z, dtype=np.float64) - self.xi) / self.lam
        with np.errstate(divide="ignore", invalid="ignore"):
            if self.family == "SU":
                f, df = np.arcsinh(u), 1 / np.sqrt(1 + u * u)
            elif self.family == "SB":
                f, df = scipy.special.logit(u), 1 / (u * (1 - u))
            elif self.family == "SL":
                f, df = np.log(u), 1 / u
            else:
                f, df = u, np.ones_like(u)
            density = scipy.stats.norm.pdf(self.gamma + self.delta * f) * self.delta * df \
                / abs(self.lam)
        z = np.asarray(z, dtype=np.float64)
        lo, hi = self.support
        return np.where((z > lo) & (z < hi), np.nan_to_num(density), 0.0)

    @property
    def support(self):
        """(lowest, highest) height."""
        if self.family == "SB":
            return (self.xi, self.xi + self.lam)
        if self.family == "SL":
            return (self.xi, math.inf) if self.lam > 0 else (-math.inf, self.xi)
        return (-math.inf, math.inf)

    def standard_moments(self) -> Moments:
        """Moments of :math:`f^{-1}((X - \\gamma)/\\delta)` (xi = 0, lam = 1)."""
        if self.family == "SU":
            return _su_moments(self.gamma, self.delta)
        if self.family == "SB":
            return _sb_moments(self.gamma, self.delta)
        if self.family == "SL":
            w = math.exp(1 / self.delta**2)
            scale = math.exp(-self.gamma / self.delta)
            return Moments(scale * math.sqrt(w), scale**2 * w * math.expm1(1 / self.delta**2),
                           (w + 2) * math.sqrt(math.expm1(1 / self.delta**2)),
                           w**4 + 2 * w**3 + 3 * w * w - 3)
        return Moments(-self.gamma / self.delta, 1 / self.delta**2, 0.0, 3.0)

    def moments(self) -> Moments:
        """(mean, variance, skewness, kurtosis) of Z (kurtosis: Pearson's, normal = 3)."""
        m = self.standard_moments()
        sign = math.copysign(1.0, self.lam)
        return Moments(self.xi + self.lam * m.mean, self.lam**2 * m.variance,
                       sign * m.skewness, m.kurtosis)

    def scipy(self):
        """The frozen ``scipy.stats`` distribution (not for a reflected SL)."""
        if self.family == "SU":
            return scipy.stats.johnsonsu(self.gamma, self.delta, loc=self.xi, scale=self.lam)
        if self.family == "SB":
            return scipy.stats.johnsonsb(self.gamma, self.delta, loc=self.xi, scale=self.lam)
        if self.family == "SN":
            return scipy.stats.norm(loc=self.xi - self.lam * self.gamma / self.delta,
                                    scale=self.lam / self.delta)
        if self.lam < 0:
            raise ValueError("scipy.stats has no reflected lognormal (lam < 0); use moments() "
                             "and pdf()")
        return scipy.stats.lognorm(1 / self.delta, loc=self.xi,
                                   scale=self.lam * math.exp(-self.gamma / self.delta))


def _check_moment_targets(skewness, kurtosis, variance):
    for name, value in (("skewness", skewness), ("kurtosis", kurtosis), ("variance", variance)):
        if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
            raise ValueError(f"{name} must be a real number, got {value!r}")
        if not math.isfinite(value):
            raise ValueError(f"{name} must be finite, got {value!r}")
    check_positive("variance", variance)
    bound = skewness**2 + 1
    if kurtosis <= bound:
        raise ValueError(
            f"no distribution has skewness={skewness!r} and kurtosis={kurtosis!r}: the kurtosis "
            f"(Pearson's, 3 for a normal) must exceed skewness**2 + 1 = {bound:.6g} (equality is a "
            f"two-point distribution); allowed region: kurtosis > skewness**2 + 1")


def _solve(f, lo, hi, what):
    try:
        return scipy.optimize.brentq(f, lo, hi, xtol=1e-15, rtol=4 * np.finfo(float).eps,
                                     maxiter=400)
    except (RuntimeError, ValueError) as err:
        raise ValueError(f"the Johnson fit did not converge ({what}): {err}") from None


def _fit_su(s, k):
    """SU: Omega >= 0 gives the (negative) skewness -|s| at each delta; delta then sets the
    kurtosis, which decreases from inf (delta -> 0) to the lognormal line (delta -> delta_L)."""
    _, w_line = lognormal_kurtosis(s)
    delta_line = math.inf if w_line <= 1 else 1 / math.sqrt(math.log(w_line))

    def log_q(delta):
        skew_limit = _su_shape(delta, -1400.0)[0]       # q = 0: the lognormal limit
        if -skew_limit <= abs(s):
            return -1400.0
        if s == 0:
            return 0.0
        return _solve(lambda t: -_su_shape(delta, t)[0] - abs(s), -1400.0, 0.0, "SU skewness")

    def excess(log_delta):
        delta = math.exp(log_delta)
        return math.log(_su_shape(delta, log_q(delta))[1] / k)

    hi = math.log(delta_line * (1 - 1e-12)) if math.isfinite(delta_line) else math.log(1e4)
    lo = min(0.0, hi - 0.7)
    floor = math.log(_SU_MIN_DELTA)
    while not excess(lo) >= 0:                      # (nan: the moments overflowed)
        if lo <= floor:
            raise ValueError(f"kurtosis={k!r} is too large for a Johnson SU fit in float64 "
                             f"(delta would be below {_SU_MIN_DELTA})")
        lo = max(lo - 0.7, floor)
    if excess(hi) > 0:
        raise ValueError(f"the Johnson SU fit did not converge: no delta in ({math.exp(lo):.3g},"
                         f" {math.exp(hi):.3g}) gives kurtosis={k!r}")
    delta = math.exp(_solve(excess, lo, hi, "SU kurtosis"))
    omega = -0.5 * log_q(delta)
    if omega > 300:
        raise ValueError("the Johnson SU fit did not converge (gamma/delta > 300: the target lies "
                         "too close to the lognormal line)")
    return delta * omega * (1.0 if s < 0 else -1.0), delta


def _fit_sb(s, k):
    """SB: gamma >= 0 gives the (positive) skewness |s| at each delta; delta then sets the
    kurtosis, which increases from skewness**2 + 1 (delta -> 0) to the lognormal line."""
    _, w_line = lognormal_kurtosis(s)
    delta_line = math.inf if w_line <= 1 else 1 / math.sqrt(math.log(w_line))

    def gamma_of(delta):
        if s == 0:
            return 0.0
        cap = 4 / delta + 40 * delta + 20          # beyond it SB equals the lognormal limit
        hi = 1.0
        while _sb_moments(hi, delta).skewness < abs(s):
            if hi >= cap:
                return math.inf
            hi = min(2 * hi, cap)
        return _solve(lambda g: _sb_moments(g, delta).skewness - abs(s), 0.0, hi, "SB skewness")

    def excess(log_delta):
        delta = math.exp(log_delta)
        gamma = gamma_of(delta)
        if math.isinf(gamma):
            w = math.exp(1 / delta**2)
            return math.log((w**4 + 2 * w**3 + 3 * w * w - 3) / k)
        return math.log(_sb_moments(gamma, delta).kurtosis / k)

    if math.isfinite(delta_line):
        hi = math.log(delta_line * (1 - 1e-9))
    else:                                           # symmetric: kurtosis -> 3 as delta -> inf
        hi = 0.0
        while excess(hi) < 0:
            hi += 0.7
            if hi > math.log(1e4):
                raise ValueError(f"the Johnson SB fit did not converge for kurtosis={k!r}")
    lo = min(0.0, hi - 0.7)
    floor = math.log(_SB_MIN_DELTA)
    while excess(lo) > 0:
        if lo <= floor:
            reach = k * math.exp(excess(floor))
            raise ValueError(
                f"skewness={s!r}, kurtosis={k!r} lies too close to the boundary kurtosis = "
                f"skewness**2 + 1 = {s * s + 1:.6g} (the two-point distribution) for a Johnson SB "
                f"fit: delta would be below {_SB_MIN_DELTA}; at this skewness the fit reaches "
                f"kurtosis >= {reach:.6g}")
        lo = max(lo - 0.7, floor)
    if excess(hi) < 0:
        raise ValueError(f"the Johnson SB fit did not converge: no delta in "
                         f"({math.exp(lo):.3g}, {math.exp(hi):.3g}) gives kurtosis={k!r}")
    delta = math.exp(_solve(excess, lo, hi, "SB kurtosis"))
    gamma = gamma_of(delta)
    if math.isinf(gamma):
        raise ValueError("the Johnson SB fit did not converge (the target lies too close to "
                         "the lognormal line)")
    return gamma * (1.0 if s > 0 else -1.0), delta


def johnson_for(skewness, kurtosis, variance=1.0) -> Johnson:
    r"""The Johnson distribution with zero mean, ``variance`` and the given skewness and
    (Pearson's, normal = 3) kurtosis: the height distribution of a non-Gaussian noise model
    (eq 8, 9), for the surfaces the paper's conclusion leaves to future work.

    The family follows from the pair: S_N at (0, 3), S_L on the lognormal line
    (:func:`lognormal_kurtosis`, within a relative 1e-9), S_U above it, S_B below it. (gamma,
    delta) are found by nested bracketing root searches (``scipy.optimize.brentq``): at fixed
    delta the skewness is monotone in gamma, and along that curve the kurtosis is monotone in
    delta. The result is verified: skewness and kurtosis match to 1e-9.

    Raises:
        ValueError: for a non-finite input, ``variance <= 0``, a pair in the impossible region
            ``kurtosis <= skewness**2 + 1``, or a fit that does not converge: a pair so close to
            that boundary that S_B would need delta < 0.01 (a gap kurtosis - skewness**2 - 1 of
            about 0.01 at skewness 0, more at larger skewness; the message gives the reachable
            kurtosis), or a kurtosis so large that S_U would need delta < 0.1.
    """
    _check_moment_targets(skewness, kurtosis, variance)
    s, k = float(skewness), float(kurtosis)
    k_line, _ = lognormal_kurtosis(s)
    if abs(k - k_line) <= _LINE_TOLERANCE * k_line:
        if s == 0:
            base = Johnson("SN", 0.0, 1.0, 0.0, 1.0)
        else:
            _, w = lognormal_kurtosis(s)
            base = Johnson("SL", 0.0, 1 / math.sqrt(math.log(w)), 0.0, math.copysign(1.0, s))
    elif k > k_line:
        gamma, delta = _fit_su(s, k)
        base = Johnson("SU", gamma, delta, 0.0, 1.0)
    else:
        gamma, delta = _fit_sb(s, k)
        base = Johnson("SB", gamma, delta, 0.0, 1.0)
    m = base.standard_moments()
    lam = math.copysign(math.sqrt(variance / m.variance), base.lam)
    fitted = Johnson(base.family, base.gamma, base.delta, -lam * m.mean, lam)
    got = fitted.moments()
    if not (abs(got.skewness - s) <= _MOMENT_TOLERANCE * max(1.0, abs(s))
            and abs(got.kurtosis - k) <= _MOMENT_TOLERANCE * k
            and abs(got.variance - variance) <= 1e-9 * variance
            and abs(got.mean) <= 1e-7 * math.sqrt(variance)):
        raise ValueError(f"the Johnson fit did not converge: asked skewness={s}, kurtosis={k}, "
                         f"got {got.skewness:.10g}, {got.kurtosis:.10g} ({fitted})")
    return fitted
