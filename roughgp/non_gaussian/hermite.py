r"""The correlation map of a memoryless transform, and the pre-distorted ACVF.

For correlated standard normals with correlation :math:`\rho_X` and :math:`T = \sum_k b_k h_k`
in normalised Hermite polynomials, Mehler's formula gives
:math:`\rho_Z = g(\rho_X) = \sum_{k \ge 1} b_k^2 \rho_X^k / \sum_{k \ge 1} b_k^2`.
**Pre-distortion** draws X with :math:`\rho_X(\tau) = g^{-1}(r(\tau)/r(0))` so that Z has the
target ACVF r (of eq 18 or any other).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field

import numpy as np
import scipy.optimize
import scipy.special
import scipy.stats

from roughgp.common.checks import check_finite, check_positive
from roughgp.non_gaussian.johnson import Johnson
from roughgp.sampling.grid_sampler import acvf_of
from roughgp.sampling.kernel_identity import kernel_identity

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


def zero_lag_value(acvf, dim):
    """The target ACVF at lag 0 in ``dim`` dimensions (its variance); finite and > 0 or an error."""
    value = np.asarray(acvf(np.zeros((1, dim))), dtype=np.float64).reshape(-1)[0]
    if not (math.isfinite(value) and value > 0):
        raise ValueError(f"the target ACVF at lag 0 must be finite and > 0, got {value!r}")
    return float(value)


class PredistortedACVF:
    r"""The input ACVF :math:`\rho_X(\boldsymbol\tau) = g^{-1}(r(\boldsymbol\tau)/r(0))` as a
    function of lags of shape (..., D): what :func:`roughgp.sampling.sample_grid` takes as its
    ``kernel``; ``cache_key()`` identifies it for that function's embedding cache when the
    target is a roughgp kernel (a target given as a plain function: not cached).

    It counts the lags it is asked for whose target correlation is below g(-1)
    (``n_unattainable`` of ``n_evaluated``; they get rho_X = -1) and keeps the lowest target
    correlation seen (``min_target``).
    """

    def __init__(self, target, cmap: CorrelationMap, unattainable="clip"):
        self._kernel = target
        self.target = acvf_of(target, name="target")
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
            self._variance[dim] = zero_lag_value(self.target, dim)
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

    def cache_key(self):
        """The target kernel's identity and the correlation map's; None for a target given as
        a plain function (its embedding is then not cached)."""
        target = kernel_identity(self._kernel)
        if target is None:
            return None
        return ("PredistortedACVF", target, tuple(self.cmap.coefficients.tolist()),
                self.unattainable)

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
