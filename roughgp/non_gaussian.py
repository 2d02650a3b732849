r"""Non-Gaussian heights with a prescribed skewness and kurtosis (beyond the paper).

The paper's model (eq 9) splits a rough surface into a stationary GP
:math:`G \sim \mathcal{GP}(0, r)` (eq 7), which carries the correlation, and a noise model
:math:`p(z \mid g)` (eq 8), which sets the height distribution. With the Gaussian noise the
paper uses, the heights are Gaussian (Ssk = 0, Sku = 3) whatever the ACVF; the conclusion names
the limit: stationary GPs with Gaussian noise models cannot describe surfaces whose roughness
"exhibits strong non-Gaussian distribution", and leaves non-Gaussian surfaces to future work.

This module takes the degenerate noise model :math:`p(z \mid g) = \delta(z - T(g))` of eq 8: a
memoryless transform of a standard GP,

.. math::  Z(\mathbf x) = T(X(\mathbf x)), \qquad X \sim \mathcal{GP}(0, \rho_X),\ \rho_X(0) = 1,

with :math:`T` the translation of the **Johnson system** (Johnson 1949), used for rough surfaces
by Hu & Tonder (1992), Watson & Spedding and Bakolas (2003):

.. math::  Z = \xi + \lambda\, f^{-1}\!\left(\frac{X - \gamma}{\delta}\right),\qquad
   f^{-1} = \sinh\ (S_U),\quad \operatorname{expit}\ (S_B),\quad \exp\ (S_L),\quad
   \text{identity}\ (S_N).

Every attainable pair (skewness, kurtosis) with Sku > Ssk² + 1 has exactly one Johnson member:
S_U above the lognormal line, S_B below it, S_L on it, S_N at (0, 3). :func:`johnson_for` fits
(gamma, delta) to the shape and (xi, lambda) to zero mean and the target variance.

The transform changes the correlation: for correlated standard normals with correlation
:math:`\rho_X`, expanding T in normalised Hermite polynomials :math:`h_k = He_k/\sqrt{k!}`,
:math:`T = \sum_k b_k h_k`, gives (Mehler's formula)

.. math::  \rho_Z = g(\rho_X) = \frac{\sum_{k \ge 1} b_k^2 \rho_X^k}{\sum_{k \ge 1} b_k^2},

exact for any memoryless T. g is increasing (Price's theorem: :math:`g' \propto
E[T'(X_1)T'(X_2)] > 0` for increasing T), g(0) = 0, g(1) = 1, and its range is
:math:`[g(-1), 1]`: correlations below g(-1) cannot be produced by any Gaussian input.
**Pre-distortion** draws X with :math:`\rho_X(\tau) = g^{-1}(r(\tau)/r(0))` so that Z has the
target ACVF r; that input ACVF must itself be positive definite on the grid, which the circulant
embedding checks (and, when it is not, clips and reports).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from typing import Callable, NamedTuple

import numpy as np
import scipy.optimize
import scipy.special
import scipy.stats

from roughgp import circulant
from roughgp._checks import as_generator as _rng
from roughgp._checks import check_finite, check_positive
from roughgp.sampling import SamplingInfo, _acvf_of, sample_grid

__all__ = ["Johnson", "Moments", "johnson_for", "lognormal_kurtosis", "CorrelationMap",
           "correlation_map", "PredistortedACVF", "predistort", "NonGaussianInfo",
           "non_gaussian_surface", "FAMILIES"]

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


# ------------------------------------------------------------------ the correlation map g


@dataclass(frozen=True, eq=False)
class CorrelationMap:
    r"""The map :math:`\rho_Z = g(\rho_X) = \sum_k a_k \rho_X^k` of a memoryless transform,
    with :math:`a_k = b_k^2 / \sum_j b_j^2` from the normalised Hermite coefficients
    :math:`b_k` of T (k = 1..n_terms). Call it for g, ``inverse`` for :math:`g^{-1}`.

    Attributes:
        johnson: the transform.
        coefficients: :math:`a_1, \dots, a_K` (>= 0, summing to 1).
        captured: :math:`\sum_{k \le K} b_k^2 / \operatorname{Var} Z` before renormalising: the
            share of the variance the kept terms and the quadrature account for (1 when exact).
        lower: g(-1), the most negative attainable output correlation.
    """

    johnson: Johnson
    coefficients: np.ndarray
    captured: float
    lower: float = field(init=False)
    _table: tuple = field(init=False, repr=False)

    def __post_init__(self):
        object.__setattr__(self, "lower", max(float(self(-1.0)), -1.0))
        grid = np.linspace(-1.0, 1.0, 4097)
        object.__setattr__(self, "_table", (self(grid), grid))

    @property
    def n_terms(self) -> int:
        return len(self.coefficients)

    def __call__(self, rho_x):
        """g(rho_x) for rho_x in [-1, 1]."""
        rho_x = np.asarray(rho_x, dtype=np.float64)
        return np.polynomial.polynomial.polyval(rho_x, np.r_[0.0, self.coefficients])

    def derivative(self, rho_x):
        """g'(rho_x) (> 0 on [-1, 1])."""
        k = np.arange(1, self.n_terms + 1)
        return np.polynomial.polynomial.polyval(np.asarray(rho_x, dtype=np.float64),
                                                k * self.coefficients)

    def inverse(self, rho_z, unattainable="raise"):
        r"""The input correlation :math:`g^{-1}(\rho_Z)`, for :math:`\rho_Z \in [g(-1), 1]`.

        Args:
            unattainable: ``"raise"`` (default) or ``"clip"``: what to do with rho_z < g(-1),
                which no Gaussian input can give (``"clip"`` returns -1 there, i.e. g(-1)).

        Raises:
            ValueError: rho_z > 1 (not a correlation), non-finite, or below g(-1) with
                ``unattainable="raise"``.
        """
        if unattainable not in ("raise", "clip"):
            raise ValueError(f"unattainable must be 'raise' or 'clip', got {unattainable!r}")
        rho_z = np.asarray(rho_z, dtype=np.float64)
        check_finite("rho_z", rho_z)
        if rho_z.size and rho_z.max() > 1 + 1e-12:
            raise ValueError(f"rho_z must be a correlation <= 1, got max {rho_z.max()!r}")
        low = rho_z < self.lower
        if low.any() and unattainable == "raise":
            raise ValueError(
                f"target correlations down to {rho_z.min():.4g} are not attainable: a transform "
                f"of a Gaussian field gives correlations in [g(-1), 1] = [{self.lower:.4g}, 1] "
                f"for this Johnson {self.johnson.family}; pass unattainable='clip' to use "
                f"g(-1) there")
        target = np.clip(rho_z, self.lower, 1.0)
        g_table, x_table = self._table
        x = np.interp(target, g_table, x_table)
        for _ in range(8):  # Newton from the table's linear interpolation: quadratic convergence
            step = (self(x) - target) / self.derivative(x)
            x = np.clip(x - step, -1.0, 1.0)
            if not step.size or np.max(np.abs(step)) < 1e-15:
                break
        return x


def correlation_map(johnson: Johnson, n_terms=None, *, tolerance=1e-12, n_nodes=None):
    r"""The correlation map g of ``Z = johnson.transform(X)`` by a Hermite expansion of T.

    The normalised Hermite coefficients :math:`b_k = E[T(X) h_k(X)]` come from Gauss-Hermite
    quadrature (probabilists' weight, ``n_nodes`` nodes); :math:`\rho_Z = g(\rho_X) =
    \sum_{k\ge1} b_k^2 \rho_X^k / \sum_{k\ge1} b_k^2` is exact for the memoryless transform of
    eq 8 used here (Mehler's formula).

    Args:
        n_terms: number of Hermite terms; default: the fewest (up to 200) whose captured
            variance is within ``tolerance`` of Var Z.
        n_nodes: quadrature nodes, default ``max(300, 2 * n_terms + 100)``.

    A captured share below 1 - 1e-6 (slowly converging series: S_B near its bounds) is warned
    about; g is renormalised so that g(1) = 1 in any case.
    """
    if not isinstance(johnson, Johnson):
        raise ValueError(f"johnson must be a Johnson (see johnson_for), got {johnson!r}")
    k_max = 200 if n_terms is None else n_terms
    if isinstance(k_max, bool) or not isinstance(k_max, (int, np.integer)) or k_max < 1:
        raise ValueError(f"n_terms must be an integer >= 1, got {n_terms!r}")
    n_nodes = max(300, 2 * int(k_max) + 100) if n_nodes is None else int(n_nodes)
    nodes, weights = scipy.special.roots_hermitenorm(n_nodes)  # stable for many nodes
    keep = weights > 1e-300
    nodes, weights = nodes[keep], weights[keep] / math.sqrt(2 * math.pi)
    with np.errstate(over="ignore"):
        t = johnson.transform(nodes)
    if not np.all(np.isfinite(t)):
        raise ValueError("the transform overflows at the quadrature nodes (kurtosis too large "
                         "for the Hermite expansion)")
    t = t - weights @ t                            # b_0 = E[T] removed
    coef = np.empty(int(k_max))
    h_prev, h = np.ones_like(nodes), nodes.copy()  # h_0, h_1 (orthonormal: h_k = He_k/sqrt(k!))
    for k in range(1, int(k_max) + 1):
        coef[k - 1] = weights @ (t * h)
        h_prev, h = h, (nodes * h - math.sqrt(k) * h_prev) / math.sqrt(k + 1)
    if not np.all(np.isfinite(coef)):
        raise ValueError("the Hermite coefficients of the transform are not finite (kurtosis "
                         "too large for the expansion)")
    variance = johnson.moments().variance
    shares = coef**2 / variance
    cumulative = np.cumsum(shares)
    if n_terms is None:
        done = np.nonzero(np.abs(1 - cumulative) <= tolerance)[0]
        n = int(done[0]) + 1 if done.size else int(k_max)
    else:
        n = int(k_max)
    captured = float(cumulative[n - 1])
    if abs(1 - captured) > 1e-6:
        warnings.warn(f"the Hermite expansion of the Johnson {johnson.family} transform captures "
                      f"{captured:.8f} of the variance with {n} terms; g is renormalised",
                      stacklevel=2)
    return CorrelationMap(johnson, shares[:n] / shares[:n].sum(), captured)


# -------------------------------------------------------------------------- pre-distortion


def _zero_lag_value(acvf, dim):
    value = np.asarray(acvf(np.zeros((1, dim))), dtype=np.float64).reshape(-1)[0]
    if not (math.isfinite(value) and value > 0):
        raise ValueError(f"the target ACVF at lag 0 must be finite and > 0, got {value!r}")
    return float(value)


class PredistortedACVF:
    r"""The input ACVF :math:`\rho_X(\boldsymbol\tau) = g^{-1}(r(\boldsymbol\tau)/r(0))` as a
    function of lags of shape (..., D): what :func:`roughgp.sampling.sample_grid` takes as its
    ``kernel`` (a plain function: the embedding is not cached between calls).

    It counts the lags it is asked for whose target correlation is below g(-1)
    (``n_unattainable`` of ``n_evaluated``; they get rho_X = -1) and keeps the lowest target
    correlation seen (``min_target``).
    """

    def __init__(self, target, cmap: CorrelationMap, unattainable="clip"):
        self.target = _acvf_of(target, name="target")
        self.cmap = cmap
        self.unattainable = unattainable
        self.n_evaluated = 0
        self.n_unattainable = 0
        self.min_target = math.inf
        self._variance = {}

    def __call__(self, lags):
        lags = np.asarray(lags, dtype=np.float64)
        dim = lags.shape[-1]
        if dim not in self._variance:
            self._variance[dim] = _zero_lag_value(self.target, dim)
        rho = np.asarray(self.target(lags), dtype=np.float64) / self._variance[dim]
        check_finite("target ACVF", rho)
        if rho.size and rho.max() > 1 + 1e-9:
            raise ValueError(f"the target ACVF exceeds r(0) (by a factor {rho.max():.6g}): "
                             f"|r(tau)| <= r(0) for any ACVF")
        self.n_evaluated += rho.size
        self.n_unattainable += int(np.count_nonzero(rho < self.cmap.lower))
        if rho.size:
            self.min_target = min(self.min_target, float(rho.min()))
        return self.cmap.inverse(np.minimum(rho, 1.0), unattainable=self.unattainable)

    @property
    def unattainable_fraction(self) -> float:
        return self.n_unattainable / self.n_evaluated if self.n_evaluated else 0.0


def predistort(target, johnson, *, variance=None, unattainable="raise"):
    r"""Pre-distort a target ACVF for the transform: :math:`\rho_X = g^{-1}(r/r(0))`.

    Args:
        target: a roughgp kernel, a function of lags (..., D), or an array of ACVF values.
        johnson: a :class:`Johnson` or its :class:`CorrelationMap`.
        variance: r(0) for an array (default: its maximum, the ACVF's value at lag 0).
        unattainable: ``"raise"`` or ``"clip"`` for target correlations below g(-1).

    Returns:
        for an array, the input correlations (same shape, unit variance); otherwise a
        :class:`PredistortedACVF` (a function of lags) that ``sample_grid`` can draw X from.
    """
    cmap = johnson if isinstance(johnson, CorrelationMap) else correlation_map(johnson)
    if callable(target) or callable(getattr(target, "acvf", None)):
        return PredistortedACVF(target, cmap, unattainable=unattainable)
    values = np.asarray(target, dtype=np.float64)
    check_finite("target", values)
    r0 = float(values.max()) if variance is None else variance
    check_positive("variance", r0)
    rho = values / r0
    if rho.max() > 1 + 1e-12:
        raise ValueError(f"the target ACVF exceeds variance={r0!r} (max {values.max()!r}): "
                         f"|r(tau)| <= r(0) for any ACVF")
    return cmap.inverse(np.minimum(rho, 1.0), unattainable=unattainable)


# --------------------------------------------------------------------------- the surface


@dataclass
class NonGaussianInfo:
    """What :func:`non_gaussian_surface` did.

    Attributes:
        johnson, correlation_map: the transform and its g.
        sampling: the :class:`roughgp.sampling.SamplingInfo` of the Gaussian input X.
        predistortion: whether X had the pre-distorted ACVF (else the target's correlation).
        variance: r(0) of the target (the heights' variance).
        clipped_fraction: the share of the embedding's trace clipped (0: exact draw).
        unattainable_fraction: share of the evaluated lags whose target correlation is below
            g(-1) (the output correlation is g(-1) there instead).
        min_target_correlation: the lowest r(tau)/r(0) among the evaluated lags.
    """

    johnson: Johnson
    correlation_map: CorrelationMap
    sampling: SamplingInfo
    predistortion: bool
    variance: float
    clipped_fraction: float
    unattainable_fraction: float
    min_target_correlation: float

    @property
    def attainable_range(self):
        """[g(-1), 1]: the output correlations a Gaussian input can give."""
        return (self.correlation_map.lower, 1.0)


def _draw_clipped(acvf, shape, spacing, n_samples, seed, max_clipped_fraction):
    """The approximate circulant draw of a non-positive-definite pre-distorted ACVF: negative
    eigenvalues clipped (at most ``max_clipped_fraction`` of the trace), X rescaled to unit
    variance so that the marginal moments stay exact."""
    try:
        embedding = circulant.embed(acvf, shape, spacing, approximate=True,
                                    max_clipped_fraction=max_clipped_fraction)
    except circulant.NotEmbeddableError as again:
        unattainable = (f" {acvf.unattainable_fraction:.1%} of the lags had target "
                        f"correlations below g(-1) = {acvf.cmap.lower:.3g} (down to "
                        f"{acvf.min_target:.3g}), set to g(-1)." if acvf.n_unattainable else "")
        raise ValueError(f"the pre-distorted ACVF is not positive definite on this grid and "
                         f"clipping its circulant embedding would remove more than "
                         f"max_clipped_fraction={max_clipped_fraction!r} of the trace: this "
                         f"target ACVF and height distribution cannot be combined.{unattainable}"
                         f" ({again})") from None
    variance = float(np.sum(embedding.scale.astype(np.float64) ** 2))  # clipped torus' r_X(0)
    x = circulant.draw(embedding, n_samples, _rng(seed)) / math.sqrt(variance)
    info = SamplingInfo(method="circulant", reason="approximate: pre-distorted ACVF not "
                        "non-negative definite, negative eigenvalues clipped",
                        torus_shape=embedding.torus_shape, min_eigenvalue=embedding.min_eigenvalue,
                        clipped_fraction=embedding.clipped_fraction,
                        details={"input_variance_before_rescaling": variance})
    return x, info


def non_gaussian_surface(kernel, shape, *, skewness, kurtosis, spacing=1.0, seed=None,
                         method="circulant", n_samples=None, predistortion=True, n_terms=None,
                         max_clipped_fraction=0.01):
    r"""A surface with the target ACVF r of ``kernel`` and Johnson heights of the given
    skewness and kurtosis: :math:`Z = T(X)`, X a standard GP with the pre-distorted ACVF
    :math:`g^{-1}(r/r(0))`. The heights have variance r(0), zero mean and the target skewness
    and kurtosis exactly (marginally; with ``method="lanczos"`` a low rank loses variance, see
    ``info.sampling.kept_trace_fraction``); the ACVF is r wherever r(tau)/r(0) >= g(-1) and the
    pre-distorted ACVF is positive definite on the grid (else see ``info.clipped_fraction``).

    This is eq 9 with a deterministic noise model :math:`p(z \mid g) = \delta(z - T(g))` (eq 8)
    on a pre-distorted GP: the non-Gaussian surfaces of the paper's conclusion.

    Args:
        kernel: a roughgp kernel or a function of lags (..., D) giving the target ACVF r.
        shape: ``(n,)`` or ``(ny, nx)``; ``spacing`` as in :func:`roughgp.sampling.sample_grid`.
        skewness, kurtosis: Ssk and Sku (Pearson's kurtosis, 3 for Gaussian heights);
            kurtosis > skewness**2 + 1.
        seed: int, None or ``numpy.random.Generator``: the same seed gives the same surface.
        method: of ``sample_grid`` (``"circulant"``: exact in O(N log N); if the pre-distorted
            ACVF's embedding has negative eigenvalues that no torus removes, the draw is
            repeated with ``approximate=True``, with a warning, and the clipped share is
            reported).
        n_samples: None for one surface of ``shape``, or an int for ``(n_samples, *shape)``.
        predistortion: False draws X with the target correlation itself (for comparison: the
            output ACVF is then r(0) g(r/r(0)), not r).
        n_terms: Hermite terms of g (default: adaptive, see :func:`correlation_map`).
        max_clipped_fraction: the largest share of the embedding's trace that may be clipped
            when the pre-distorted ACVF is not non-negative definite (else ValueError).

    Returns:
        ``(z, info)`` with info a :class:`NonGaussianInfo`.
    """
    from roughgp.grid import normalize

    shape, spacing = normalize(shape, spacing)
    acvf = _acvf_of(kernel)
    variance = _zero_lag_value(acvf, len(shape))
    johnson = johnson_for(skewness, kurtosis, variance)
    cmap = correlation_map(johnson, n_terms)
    if predistortion:
        input_acvf = PredistortedACVF(acvf, cmap, unattainable="clip")
    else:
        def input_acvf(lags):
            return np.asarray(acvf(lags), dtype=np.float64) / variance
    count = 1 if n_samples is None else n_samples
    try:
        x, sampling = sample_grid(input_acvf, shape, spacing=spacing, n_samples=count,
                                  method=method, seed=seed, return_info=True)
    except circulant.NotEmbeddableError:
        if not predistortion or method not in ("circulant", "auto"):
            raise
        x, sampling = _draw_clipped(input_acvf, shape, spacing, count, seed,
                                    max_clipped_fraction)
        warnings.warn(f"the pre-distorted ACVF is not non-negative definite on this grid: its "
                      f"circulant embedding's negative eigenvalues, {sampling.clipped_fraction:.2e}"
                      f" of the trace, were clipped (and X rescaled to unit variance), so the "
                      f"surface's ACVF only approximates the target", stacklevel=2)
    z = johnson.transform(x)
    if n_samples is None:
        z = z[0]
    unattainable = input_acvf.unattainable_fraction if predistortion else 0.0
    min_target = input_acvf.min_target if predistortion else math.nan
    if unattainable > 0:
        warnings.warn(f"target correlations down to {min_target:.3g} are below g(-1) = "
                      f"{cmap.lower:.3g} at {unattainable:.2%} of the lags: the surface has "
                      f"correlation g(-1) there", stacklevel=2)
    info = NonGaussianInfo(johnson, cmap, sampling, bool(predistortion), variance,
                           sampling.clipped_fraction, unattainable, min_target)
    return z, info
