r"""Fit eq 18 plus noise to a whole height map, holes allowed, by the debiased spatial Whittle
likelihood (beyond the paper; issue 40, item 2).

The block composite likelihood (:mod:`roughgp.inference.block_fit`) uses a fixed number of
small blocks whatever the map's size, so its precision does not grow with the map; and on an
exponential covariance (eq 18) the variance and the lengths are only weakly identified
within a block, so both come out short together. This fit uses every measured point at the
cost of FFTs. The periodogram of the centred heights :math:`y = m\,(z - \bar z)` (``m`` the
0/1 map of measured points),

.. math::
    I(\boldsymbol\omega_k) = \frac{1}{\sum_s m_s}\Big|\sum_{\mathbf s} m_{\mathbf s}
    y_{\mathbf s} e^{-i\boldsymbol\omega_k^\top\mathbf s}\Big|^2 ,

has the expectation, exactly, for any grid size and any pattern of holes,

.. math::
    \bar I(\boldsymbol\omega_k; \boldsymbol\alpha) = \sum_{\boldsymbol\tau}
    \big(r(\boldsymbol\tau; \boldsymbol\alpha) + \sigma^2\delta_{\boldsymbol\tau}\big)\,
    g(\boldsymbol\tau)\, e^{-i\boldsymbol\omega_k^\top\boldsymbol\tau},
    \qquad g(\boldsymbol\tau) = \frac{\sum_{\mathbf s} m_{\mathbf s}
    m_{\mathbf s + \boldsymbol\tau}}{\sum_{\mathbf s} m_{\mathbf s}},

with :math:`r` eq 18 (or its Matérn variant) and :math:`\sigma^2` the noise of eq 8: the ACVF
times the measured points' own autocorrelation, Fourier-transformed over the
:math:`(2n_y - 1)(2n_x - 1)` lags of the grid and folded onto its :math:`n_y n_x` Fourier
frequencies. The fit maximises

.. math::
    \ell_W(\boldsymbol\alpha) = -\sum_{k \in K}\Big[\log \bar I(\boldsymbol\omega_k;
    \boldsymbol\alpha) + \frac{I(\boldsymbol\omega_k)}{\bar I(\boldsymbol\omega_k;
    \boldsymbol\alpha)}\Big]

over the frequencies :math:`K` of the grid but the lowest (:data:`EXCLUDED_LOWEST`: the
mean and the F-operator's plane act there, and the expectation does not know them). This is
the debiased spatial Whittle likelihood of Sykulski et al. (2019) with the missing points of
Guillaumin et al. (2022): the periodogram's bias (aliasing, the grid's edges, the holes) is in
:math:`\bar I`, not in the estimate, so the estimate is consistent and its spread falls with the
number of measured points, at :math:`O(N \log N)` a likelihood evaluation. The gradient comes
from torch's automatic differentiation; L-BFGS-B searches the log scales and the angle within
the block fit's bounds, from the best two of its starts. The optimum is reported with
:math:`\lambda_a \ge \lambda_b` and :math:`\phi \in [-\pi/2, \pi/2)`.

With ``device=`` (:mod:`roughgp.common.device`) the FFTs, the expected periodogram and its
gradient run through torch on that device (a CUDA GPU); the optimiser stays on the CPU and
receives the value and the gradient as numbers, so a fit on a GPU takes the same path as on
the CPU, up to rounding. ``benchmarks/device.py`` (case ``whittle fit``) times both.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.optimize

from roughgp.common.checks import boolean_map
from roughgp.common.grid import normalize
from roughgp.models.surfaces import GrooveParameters

__all__ = ["EXCLUDED_LOWEST", "MIN_POINTS", "FAR_BEYOND", "WhittleFit", "WhittleLikelihood",
           "UNDETERMINED_SE", "fit_whittle", "implied_fit", "held_inverse", "robust_covariance"]

#: frequencies excluded around zero: ``|k_y| <= 1`` and ``|k_x| <= 1`` (the mean, the plane)
EXCLUDED_LOWEST = 1
MIN_POINTS = 16  #: the fewest rows and columns of a map this fit takes
#: a length beyond this many times the map's longer side is "far beyond the map": the map does
#: not identify it (roughgp.surface_models.in_range caps it; robust_covariance gives NaN)
FAR_BEYOND = 4.0
#: the standard error of ``u``'s coordinates (log variance, log lengths, angle in radians, log
#: noise) beyond which the grid does not determine it: a factor of 10 per standard error, 45 deg
UNDETERMINED_SE = (math.log(10.0), math.log(10.0), math.log(10.0), math.pi / 4, math.log(10.0))
_NAMES = ("variance", "lambda_a", "lambda_b", "angle", "noise_variance")
_ANGLE = 3
# float64 arrays of the (2 ny) x (2 nx) lag grid held at once per likelihood evaluation (lags,
# covariance, the autocorrelation of the measured points, autograd's copies), per map point
_BYTES_PER_POINT = 4 * 8 * 24


@dataclass(frozen=True)
class WhittleFit:
    """The result of :func:`fit_whittle`.

    Attributes:
        groove: the fitted eq 18 hyperparameters (``lambda_a >= lambda_b``).
        noise_variance: the fitted :math:`\\sigma^2` of eq 8.
        mean: the constant mean removed (mean of the measured heights).
        log_likelihood: :math:`\\ell_W` at the optimum.
        n_points: measured points used (all of them).
        n_frequencies: Fourier frequencies in the likelihood.
        nu: the Matérn smoothness of the radial profile (0.5: eq 18 itself).
        u: the optimum as ``(log variance, log lambda_a, log lambda_b, angle, log noise)``
            (the reported order: ``lambda_a >= lambda_b``).
        covariance: the inverse of the observed information :math:`-\\nabla^2\\ell_W` at
            ``u`` (5 x 5, the same order): the fit's own uncertainty, NaN where the
            information is not positive definite (a parameter the map does not determine).
    """

    groove: GrooveParameters
    noise_variance: float
    mean: float
    log_likelihood: float
    n_points: int
    n_frequencies: int
    nu: float = 0.5
    u: tuple = ()
    covariance: np.ndarray | None = None

    def standard_errors(self) -> np.ndarray:
        """The standard errors of ``u``'s five entries (NaN where undetermined)."""
        if self.covariance is None:
            return np.full(len(_NAMES), np.nan)
        return np.sqrt(np.where(np.diag(self.covariance) > 0, np.diag(self.covariance), np.nan))


class WhittleLikelihood:
    r""":math:`\ell_W` of the centred heights ``y`` (0 where unmeasured) with the measured map
    ``valid`` (module docstring), as a function of
    ``u = (log variance, log lambda_a, log lambda_b, angle, log noise)``; ``device`` (None:
    torch on the CPU) is where its tensors live."""

    def __init__(self, y, valid, spacing, nu=0.5, device=None):
        import torch

        from roughgp.common import device as devices
        self._torch = torch
        self.nu = nu
        self.device = devices.resolve(device) or torch.device("cpu")
        ny, nx = y.shape
        devices.check_memory(_BYTES_PER_POINT * ny * nx, self.device, "the Whittle likelihood")
        m = torch.as_tensor(valid, dtype=torch.float64, device=self.device)
        data = torch.as_tensor(np.where(valid, y, 0.0), dtype=torch.float64, device=self.device)
        count = float(m.sum())
        self._valid, self._count = np.asarray(valid, dtype=bool), count
        self.periodogram = torch.fft.fft2(data).abs() ** 2 / count
        spectrum = torch.fft.fft2(m, s=(2 * ny, 2 * nx))
        self._g = torch.fft.ifft2(spectrum.abs() ** 2).real / count   # lags in FFT order
        dy, dx = (float(s) for s in spacing)
        ky = torch.fft.fftfreq(2 * ny, 1.0 / (2 * ny), dtype=torch.float64, device=self.device)
        kx = torch.fft.fftfreq(2 * nx, 1.0 / (2 * nx), dtype=torch.float64, device=self.device)
        ty, tx = torch.meshgrid(ky * dy, kx * dx, indexing="ij")
        self._lags = torch.stack([tx, ty], dim=-1)
        self._shape = (ny, nx)
        fy = torch.fft.fftfreq(ny, 1.0 / ny, device=self.device).abs()
        fx = torch.fft.fftfreq(nx, 1.0 / nx, device=self.device).abs()
        low = (fy[:, None] <= EXCLUDED_LOWEST) & (fx[None, :] <= EXCLUDED_LOWEST)
        self._keep = ~low
        self.n_frequencies = int(self._keep.sum())

    def _parameters(self, u):
        return self._torch.as_tensor(np.asarray(u, dtype=np.float64), dtype=self._torch.float64,
                                     device=self.device)

    def expected(self, u):
        r""":math:`\bar I` on the grid's Fourier frequencies at ``u`` (a float64 tensor)."""
        from roughgp.gp import acvf
        torch = self._torch
        variance, lam_a, lam_b = torch.exp(u[0]), torch.exp(u[1]), torch.exp(u[2])
        scales = torch.stack([lam_a, lam_b])
        if self.nu == 0.5:
            c = acvf.rotated_exponential(self._lags, variance, scales, u[3])
        else:
            c = acvf.rotated_matern(self._lags, variance, scales, u[3], self.nu)
        c = c.clone()
        c[0, 0] = c[0, 0] + torch.exp(u[4])
        cg = c * self._g
        ny, nx = self._shape
        folded = cg[:ny] + cg[ny:]
        folded = folded[:, :nx] + folded[:, nx:]
        return torch.fft.fft2(folded).real

    def value_and_gradient(self, u):
        """``(ell_W, d ell_W / d u)`` at ``u`` (numpy); ``(-inf, zeros)`` where the expected
        periodogram is not positive."""
        torch = self._torch
        t = self._parameters(u)
        t.requires_grad_(True)
        expected = self.expected(t)[self._keep]
        if not bool((expected > 0).all()):
            return -math.inf, np.zeros(len(_NAMES))
        value = -(torch.log(expected) + self.periodogram[self._keep] / expected).sum()
        value.backward()
        return float(value.detach()), t.grad.detach().cpu().numpy().copy()

    def with_heights(self, y) -> "WhittleLikelihood":
        """The same likelihood (mask, lags, device) for other heights ``y`` of the same grid
        (centred here on their measured points' mean): a shallow copy with their periodogram."""
        torch = self._torch
        copy = object.__new__(type(self))
        copy.__dict__.update(self.__dict__)
        valid = self._valid
        centred = np.where(valid, y - np.mean(y[valid]), 0.0)
        data = torch.as_tensor(centred, dtype=torch.float64, device=self.device)
        copy.periodogram = torch.fft.fft2(data).abs() ** 2 / self._count
        return copy

    def information(self, u) -> np.ndarray:
        r"""The observed information :math:`-\nabla^2_u \ell_W` at ``u`` (5 x 5, by torch's
        automatic differentiation)."""
        torch = self._torch

        def value(t):
            expected = self.expected(t)[self._keep]
            return -(torch.log(expected) + self.periodogram[self._keep] / expected).sum()

        hessian = torch.autograd.functional.hessian(value, self._parameters(u))
        return -hessian.detach().cpu().numpy()

    def expected_information(self, u) -> np.ndarray:
        r"""The expected (Fisher) information :math:`E[-\nabla^2_u \ell_W]` at ``u`` (5 x 5):
        the observed information of a periodogram equal to its expectation :math:`\bar I(u)`,
        where the Hessian reduces to :math:`\sum_k \nabla\log\bar I_k\,\nabla\log\bar
        I_k^\top`. It needs no heights: a model's own information on this grid and mask."""
        torch = self._torch
        copy = object.__new__(type(self))
        copy.__dict__.update(self.__dict__)
        with torch.no_grad():
            copy.periodogram = self.expected(self._parameters(u))
        return copy.information(u)

    def value(self, u) -> float:
        torch = self._torch
        with torch.no_grad():
            expected = self.expected(self._parameters(u))
        expected = expected[self._keep]
        if not bool((expected > 0).all()):
            return -math.inf
        return float(-(torch.log(expected) + self.periodogram[self._keep] / expected).sum())


def fit_whittle(z, *, spacing=1.0, mask=None, nu=0.5, maxiter=500, device=None) -> WhittleFit:
    """Fit eq 18 plus white noise (eq 8) to all measured points of ``z`` by the debiased
    spatial Whittle likelihood (module docstring).

    Args:
        z: height map ``z[iy, ix]`` (form-removed), NaN where not measured; at least
            :data:`MIN_POINTS` rows and columns.
        spacing: scalar or ``(dy, dx)``; the lengthscales come in its unit.
        mask: optional boolean array like ``z``; True marks points to leave out as well.
        nu: 0.5 (eq 18), 1.5 or 2.5 (the Matérn variant).
        maxiter: L-BFGS-B iterations (at most), an integer >= 1.
        device: None (torch on the CPU) or a torch device such as ``"cuda"``
            (:mod:`roughgp.common.device`): where the likelihood and its gradient are computed.

    Returns:
        :class:`WhittleFit`.
    """
    z = np.asarray(z, dtype=np.float64)
    if z.ndim != 2:
        raise ValueError(f"z must be a 2-D height map z[iy, ix], got shape {z.shape}")
    if min(z.shape) < MIN_POINTS:
        raise ValueError(f"z must have at least {MIN_POINTS} rows and columns for the Whittle "
                         f"fit, got {z.shape[0]} x {z.shape[1]}")
    if np.any(np.isinf(z)):
        raise ValueError("z must not hold inf; mark unmeasured points with NaN or in mask")
    if nu not in (0.5, 1.5, 2.5):
        raise ValueError(f"nu must be 0.5 (eq 18), 1.5 or 2.5, got {nu!r}")
    if not isinstance(maxiter, (int, np.integer)) or maxiter < 1:
        raise ValueError(f"maxiter must be an integer >= 1, got {maxiter!r}")
    valid = ~np.isnan(z)
    if mask is not None:
        valid &= ~boolean_map(mask, z.shape)
    if valid.sum() < MIN_POINTS * MIN_POINTS:
        raise ValueError(f"z holds {int(valid.sum())} measured points; the Whittle fit needs "
                         f"at least {MIN_POINTS * MIN_POINTS}")
    _, spacing = normalize(z.shape, spacing)
    mean = float(np.mean(z[valid]))
    centred = np.where(valid, z - mean, 0.0)
    var = float(np.mean(centred[valid] ** 2))
    if not var > 0:
        raise ValueError("the measured heights of z are constant")
    likelihood = WhittleLikelihood(centred, valid, spacing, nu, device)
    d = float(np.min(spacing))
    extent = float(max(z.shape[0] * spacing[0], z.shape[1] * spacing[1]))
    scale = (math.log(d / 20.0), math.log(50.0 * extent))
    bounds = [(math.log(1e-4 * var), math.log(100.0 * var)), scale, scale, (None, None),
              (math.log(1e-8 * var), math.log(10.0 * var))]
    side = float(min(z.shape[0] * spacing[0], z.shape[1] * spacing[1]))
    starts = [np.array([math.log(0.9 * var), math.log(side / 16), math.log(side / 16 / ratio),
                        angle, math.log(0.1 * var)])
              for angle in (0.0, math.pi / 4, math.pi / 2, -math.pi / 4) for ratio in (1.5, 6.0)]
    ranked = sorted(starts, key=likelihood.value, reverse=True)
    optima = []
    for u0 in ranked[:2]:
        def objective(u):
            value, grad = likelihood.value_and_gradient(u)
            if not math.isfinite(value):
                return 1e300, np.zeros_like(u)
            return -value, -grad
        optima.append(scipy.optimize.minimize(objective, u0, jac=True, method="L-BFGS-B",
                                              bounds=bounds, options={"maxiter": int(maxiter)}))
    best = min(optima, key=lambda result: result.fun)
    if not best.fun < 1e300:
        raise ValueError("the expected periodogram is not positive at any start: the measured "
                         "heights may hold steps or constant patches")
    covariance = _inverse_information(likelihood.information(best.x))
    variance, lam_a, lam_b, angle, noise = (float(best.x[0]), *np.exp(best.x[1:3]),
                                            float(best.x[3]), float(best.x[4]))
    variance, noise = math.exp(variance), math.exp(noise)
    if lam_a < lam_b:
        lam_a, lam_b, angle = lam_b, lam_a, angle + math.pi / 2
        swap = [0, 2, 1, 3, 4]
        covariance = covariance[np.ix_(swap, swap)]
    angle = (angle + math.pi / 2) % math.pi - math.pi / 2
    u = (math.log(variance), math.log(lam_a), math.log(lam_b), angle, math.log(noise))
    return WhittleFit(GrooveParameters(variance, (float(lam_a), float(lam_b)), angle), noise,
                      mean, float(-best.fun), int(valid.sum()), likelihood.n_frequencies, nu,
                      u, covariance)


def implied_fit(groove: GrooveParameters, noise_variance, valid, spacing=1.0, *, nu=0.5,
                device=None) -> WhittleFit:
    """The :class:`WhittleFit` that eq 18 of ``groove`` plus ``noise_variance`` implies on the
    grid of measured points ``valid``: its ``u`` and, as its ``covariance``, the inverse of the
    expected information there (:meth:`WhittleLikelihood.expected_information`), with the
    coordinates the grid does not determine held (:func:`held_inverse`: their rows and columns
    0, typically a noise variance at 1e-8 of the surface's, where the information is singular).
    For :func:`robust_covariance` of a model whose fitted heights are not at hand (a model
    file: its fitted grid, ``data.shape``, without its holes)."""
    valid = boolean_map(valid, np.shape(valid))
    _, spacing = normalize(valid.shape, spacing)
    if not (noise_variance > 0 and groove.variance > 0 and min(groove.lengthscales) > 0):
        raise ValueError(f"the variance, the lengths and noise_variance must be > 0, got "
                         f"{groove.variance!r}, {groove.lengthscales!r}, {noise_variance!r}")
    u = (math.log(groove.variance), math.log(groove.lengthscales[0]),
         math.log(groove.lengthscales[1]), float(groove.angle), math.log(noise_variance))
    likelihood = WhittleLikelihood(np.zeros(valid.shape), valid, spacing, nu, device)
    covariance, _ = held_inverse(likelihood.expected_information(u))
    return WhittleFit(groove, float(noise_variance), 0.0, math.nan, int(valid.sum()),
                      likelihood.n_frequencies, nu, u, covariance)


def robust_covariance(fit: WhittleFit, valid, spacing=1.0, *, n_draws=40, seed=0,
                      device=None) -> np.ndarray:
    r"""The sandwich (Godambe) covariance of a Whittle fit's ``u``: :math:`H^{-1} J H^{-1}`,
    :math:`H^{-1}` the fit's ``covariance`` (its inverse observed information) and :math:`J` the covariance of the
    score :math:`\nabla_u \ell_W` over ``n_draws`` surfaces drawn from the fitted model on the
    same grid with the same measured points (``valid``).

    Why: the Whittle likelihood treats the periodogram's ordinates as independent, and they are
    not (a real map's periodogram is symmetric, :math:`I(\omega) = I(-\omega)`, and the
    grid's edges and holes correlate neighbours), so :math:`H^{-1}` alone understates the
    spread: on 40 maps of 64 x 64 points its standard errors were about half the estimates'
    spread. The score's covariance carries those correlations (Sykulski et al. 2019, section
    4, compute it exactly; here it is estimated by simulation, one gradient per draw).

    Args:
        fit: a :class:`WhittleFit` of a map of ``valid``'s shape.
        valid: the boolean map of measured points the fit used.
        spacing: of the map (scalar or ``(dy, dx)``).
        n_draws: an integer >= 10; seed: of the draws; device: as :func:`fit_whittle`.

    Returns:
        5 x 5, the order of ``fit.u``; NaN where the information is not positive definite,
        where a fitted length lies more than :data:`FAR_BEYOND` times beyond the map's longer
        side (the map does not determine it, and drawing it means searching a huge torus:
        minutes), or where the fit cannot be drawn on the map's grid at all.
    """
    from roughgp.models.surfaces import ground
    from roughgp.sampling.truncation import NotEmbeddableError
    from roughgp.common.checks import as_generator, check_integer
    n = check_integer("n_draws", n_draws, 10)
    valid = boolean_map(valid, np.shape(valid))
    _, spacing = normalize(valid.shape, spacing)
    inverse = fit.covariance
    if inverse is None or not np.all(np.isfinite(inverse)):
        return np.full((len(_NAMES), len(_NAMES)), np.nan)
    likelihood = WhittleLikelihood(np.zeros(valid.shape), valid, spacing, fit.nu, device)
    u = np.asarray(fit.u, dtype=np.float64)
    rng = as_generator(seed)
    g = fit.groove
    if max(g.lengthscales) > FAR_BEYOND * max(n * d for n, d in zip(valid.shape, spacing)):
        return np.full((len(_NAMES), len(_NAMES)), np.nan)
    scores = []
    for _ in range(n):
        try:
            z = ground(valid.shape, variance=g.variance, lengthscales=g.lengthscales,
                       angle=g.angle, noise_variance=fit.noise_variance, spacing=spacing,
                       seed=rng, method="circulant")
        except NotEmbeddableError:
            return np.full((len(_NAMES), len(_NAMES)), np.nan)
        scores.append(likelihood.with_heights(z).value_and_gradient(u)[1])
    score_covariance = np.cov(np.asarray(scores), rowvar=False)
    return inverse @ score_covariance @ inverse


def held_inverse(information, limits=UNDETERMINED_SE) -> tuple[np.ndarray, tuple]:
    """``(inverse, held)``: the inverse of the information matrix over the coordinates it
    determines, 0 in the rows and columns of the others (``held``, their indices). Greedy: while
    the information over the free coordinates is not positive definite, the coordinate with the
    least information in units of its ``limits`` is held; while a free coordinate's standard
    error exceeds its limit, the one furthest beyond is held."""
    information = np.asarray(information, dtype=np.float64)
    limits = np.asarray(limits, dtype=np.float64)
    free = list(range(len(information)))
    inverse = np.zeros((0, 0))
    while free:
        sub = information[np.ix_(free, free)]
        try:
            np.linalg.cholesky(sub)
        except np.linalg.LinAlgError:
            free.pop(int(np.argmin(np.diag(sub) * limits[free] ** 2)))
            continue
        inverse = np.linalg.inv(sub)
        excess = np.sqrt(np.diag(inverse)) / limits[free]
        if excess.max() <= 1.0:
            break
        free.pop(int(np.argmax(excess)))
    out = np.zeros(information.shape)
    if free:
        out[np.ix_(free, free)] = inverse
    return out, tuple(k for k in range(len(information)) if k not in free)


def _inverse_information(information) -> np.ndarray:
    """The inverse of the observed information, NaN-filled where it is not positive definite
    (an optimum at a bound, or a parameter the likelihood is flat in)."""
    try:
        np.linalg.cholesky(information)
    except np.linalg.LinAlgError:
        return np.full(information.shape, np.nan)
    return np.linalg.inv(information)
