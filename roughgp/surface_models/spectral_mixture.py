r"""A 2-D spectral mixture of a measured surface, fitted by the Whittle likelihood (beyond the
paper; the areal member of eq 22's family).

The paper models turned profiles by the spectral mixture of eq 21 (a sum of Gaussians in
frequency, each a plane wave under a Gaussian envelope in lag, :math:`\boldsymbol\Sigma_q`
diagonal) and turned surfaces by the sum of two such mixtures, one along x and one along y
(eq 22, the additivity assumption: its PSD lies on the two axes); it names "its multivariate
variant" as the other way. This module is that variant, for structured or periodic texture at
any angle that eq 18's single exponential cannot describe: a feed mark, a lay with a period,
its harmonics (eq 22's components are its limit of a vanishing bandwidth along one axis). The
model (equation ``"sm2d"``) is

.. math::
    r(\boldsymbol\tau) = \sum_{q=1}^{Q} w_q \cos(2\pi\boldsymbol\tau^\top\boldsymbol\mu_q)
    \exp(-2\pi^2\boldsymbol\tau^\top\boldsymbol\Sigma_q\boldsymbol\tau) + \sigma^2
    \delta_{\boldsymbol\tau}, \qquad
    S(\mathbf f) = \sum_q \frac{w_q}{2}\left[\mathcal N(\mathbf f; \boldsymbol\mu_q,
    \boldsymbol\Sigma_q) + \mathcal N(\mathbf f; -\boldsymbol\mu_q, \boldsymbol\Sigma_q)
    \right] + \sigma^2 \Delta y \Delta x,

the form of :func:`roughgp.gp.acvf.spectral_mixture` (eq 21) in two dimensions with a **full**
2 x 2 covariance :math:`\boldsymbol\Sigma_q = R(\theta_q)\,\mathrm{diag}(a_q^2, b_q^2)\,
R(\theta_q)^\top`, stored as the bandwidths :math:`a_q, b_q` (1/um, the standard deviations of
the Gaussian along its own axes) and the axes' angle :math:`\theta_q` (degrees from x). Full,
because a lay's peak in the PSD is elongated along the lay's normal at any angle, and
diagonal in the (x, y) frame it could only be elongated along x or y; the rotated-diagonal
form keeps :math:`\boldsymbol\Sigma_q` positive definite and its bounds readable (one frequency
bin to the band, per axis). The ACVF is evaluated in closed form by
:func:`~roughgp.gp.acvf.spectral_mixture` on lags rotated by :math:`\theta_q`
(:func:`sm2d_acvf`), for kriging (``fill --model``) and for the exact circulant embedding of
``simulate --from`` / ``check`` (:meth:`~roughgp.surface_models.model.FittedModel.simulate`).

**The fit** (:func:`whittle_fit`; :func:`roughgp.surface_models.fit.fit_sm_model` keeps it
as a model). An exact GP likelihood on 16k points costs
:math:`O(n^3)`; the Whittle likelihood of a stationary field,
:math:`-\sum_{\mathbf f}[\log E(\mathbf f) + I(\mathbf f)/E(\mathbf f)]` over the half
plane of non-zero DFT frequencies, costs one FFT and a sum. :math:`I` is the Tukey-windowed
periodogram of the differences of the form-removed heights along x plus that along y, holes
allowed (:func:`roughgp.surface_models.psd_table.periodogram`, prewhitened), and
:math:`E = S\,T` its expectation: the model's spectrum :math:`S`, folded over the
neighbouring aliases of the grid where a component reaches them, times the differences'
transmission :math:`T = 4\sin^2(\pi f_x \Delta x) + 4\sin^2(\pi f_y \Delta y)`. The
differences keep the long wavelengths, which hold most of a real surface's variance, from
leaking through the holes' mean fill and the window's sidelobes into every frequency
(:mod:`~roughgp.surface_models.psd_table` measured that leak). Fitted to the plain
periodogram instead, the mixture's simulations had too short a correlation: Sal outside on 15
of the 18 maps of ``data/`` (128 x 128, IAAFT heights); prewhitened, on 3 of the 5 of them
tried first, and the held-out kriging RMSE fell on all 5 (0.345 to 0.243 of linear
interpolation's on ``al3d-1.al3d``). Above :data:`MAX_ORDINATES` the periodogram is
averaged over square blocks of frequencies first (a Daniell smoother; each average counts as
its block's ordinates). Components are added one at a time: a broad component at zero
frequency (the roughness), then at the frequency where the prewhitened periodogram exceeds the
fitted spectrum most (the lay, a period, a harmonic); after each the whole mixture is refitted
(L-BFGS-B, analytic gradient) and scored by BIC, :math:`-2\ell + (6Q + 1)\log n`; the Q of the
lowest BIC is kept (:data:`MAX_COMPONENTS` by default). The Whittle likelihood assumes
periodogram ordinates spread as a Gaussian field's; a deterministic lay (a sinusoid) puts its
power into a few ordinates far above any smooth spectrum, and the fitted weight fell to half
of it (on a sinusoid of variance 0.5 um^2 plus an eq 18 roughness of 0.25 um^2, 128 x 128:
the mixture's variance 0.48 um^2 of the measured 0.74 um^2, fitted to the plain
periodogram). So the fitted weights are finally set to the periodogram power each component is
responsible for (one EM step on the
spectrum, :func:`_apportioned`): the model keeps the fitted shapes and the measured variance,
as the measured-PSD rung does. Bounds: :math:`|\mu|` within the
Nyquist frequency of each axis, the bandwidths between one frequency bin of the grid fitted
and the band (Nyquist); a fitted value on a bound is reported (``range_notes``, kept in the
model's ``fit``), as eq 18's fit reports its lengths at a bound.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import scipy.optimize

from roughgp.common.numerics import perturbed_start
from roughgp.surface_models import psd_table

__all__ = ["MAX_COMPONENTS", "MAX_ORDINATES", "Mixture2D", "check_embeddable", "sm2d_acvf",
           "sm2d_psd", "whittle_fit"]

MAX_COMPONENTS = 4  #: the most components the fit tries by default
MAX_ORDINATES = 1 << 14  #: above this many half-plane ordinates the periodogram is block-averaged
_PER_COMPONENT = 6  #: log w, mu_x, mu_y, log a, log b, theta
_TAIL = 5.0  #: a component further than this many bandwidths from an alias is not folded in


@dataclasses.dataclass(frozen=True)
class Mixture2D:
    """A 2-D spectral mixture: ``weights`` (Q,) um^2, ``means`` (Q, 2) as (f_x, f_y) 1/um,
    ``bandwidths`` (Q, 2) as (a, b) 1/um, ``angles`` (Q,) radians, ``noise`` um^2."""

    weights: np.ndarray
    means: np.ndarray
    bandwidths: np.ndarray
    angles: np.ndarray
    noise: float

    @property
    def size(self) -> int:
        return int(np.size(self.weights))

    def hyperparameters(self) -> dict:
        """The model file's fields (:mod:`roughgp.surface_models.schema`, ``"sm2d"``)."""
        return {"weights_um2": [float(w) for w in self.weights],
                "frequencies_x_per_um": [float(m) for m in self.means[:, 0]],
                "frequencies_y_per_um": [float(m) for m in self.means[:, 1]],
                "bandwidths_a_per_um": [float(v) for v in self.bandwidths[:, 0]],
                "bandwidths_b_per_um": [float(v) for v in self.bandwidths[:, 1]],
                "axes_deg": [math.degrees(float(t)) for t in self.angles],
                "noise_variance_um2": float(self.noise)}

    @classmethod
    def from_hyperparameters(cls, hp) -> "Mixture2D":
        return cls(np.asarray(hp["weights_um2"], dtype=np.float64),
                   np.stack([hp["frequencies_x_per_um"], hp["frequencies_y_per_um"]], -1)
                   .astype(np.float64),
                   np.stack([hp["bandwidths_a_per_um"], hp["bandwidths_b_per_um"]], -1)
                   .astype(np.float64),
                   np.radians(np.asarray(hp["axes_deg"], dtype=np.float64)),
                   float(hp["noise_variance_um2"]))


#: the envelope :math:`\exp(-2\pi^2 b^2 \tau^2)` is below 1e-6 beyond this many ``1 / b``
_REACH = math.sqrt(math.log(1e6) / (2 * math.pi ** 2))


def check_embeddable(mixture: Mixture2D, shape, spacing):
    """Refuse (``ValueError`` with the reason) a draw of ``shape`` at ``spacing`` whose torus
    would exceed :data:`~roughgp.surface_models.psd_table.MAX_TORUS_POINTS`: the circulant
    embedding needs about twice the field plus the lag at which the narrowest component's
    Gaussian envelope has fallen to 1e-6, :math:`0.84 / b` (the embedding itself then checks
    its eigenvalues, :func:`roughgp.sampling.circulant.embed`)."""
    narrowest = float(mixture.bandwidths.min())
    reach = _REACH / narrowest
    torus = [2 * (n + math.ceil(reach / d)) for n, d in zip(shape, spacing)]
    if math.prod(torus) > psd_table.MAX_TORUS_POINTS:
        raise ValueError(f"the 2-D spectral mixture's narrowest component (bandwidth "
                         f"{narrowest:.3g} 1/um) stays correlated over {reach:.4g} um; an exact "
                         f"circulant embedding of {shape[0]} x {shape[1]} points at a spacing "
                         f"of {spacing[0]:g} x {spacing[1]:g} um would need a torus of about "
                         f"{torus[0]} x {torus[1]} points, more than "
                         f"{psd_table.MAX_TORUS_POINTS} (2**26): draw a smaller field or at a "
                         f"coarser spacing")


def sm2d_acvf(lags, mixture: Mixture2D):
    r"""The latent ACVF at ``lags`` (..., 2) in (x, y) order, um^2: each component by
    :func:`roughgp.gp.acvf.spectral_mixture` (eq 21) on the lags rotated into its axes
    (:func:`roughgp.gp.acvf.rotate`), where :math:`\boldsymbol\Sigma_q` is diagonal."""
    from roughgp.gp.acvf import rotate, spectral_mixture
    lags = np.asarray(lags, dtype=np.float64)
    total = np.zeros(lags.shape[:-1])
    for w, mu, ab, theta in zip(mixture.weights, mixture.means, mixture.bandwidths,
                                mixture.angles):
        turned_mu = rotate(mu[None, :], theta)[0]
        total += spectral_mixture(rotate(lags, theta), np.array([w]), turned_mu[None, :],
                                  (ab * ab)[None, :])
    return total


def _component_terms(fy, fx, w, mu, ab, theta, nyquist):
    r"""One component's Gaussians at ``(fy, fx)`` (flat arrays), one term per sign of
    :math:`\pm\boldsymbol\mu` and alias of the grid it reaches: a list of ``(sign, G, u_a,
    u_b)``, ``G`` the density times ``w / 2`` (um^4), ``u`` the offsets from the term's centre
    in the component's axes (1/um)."""
    c, s = math.cos(theta), math.sin(theta)
    reach = _TAIL * float(ab.max())
    terms = []
    for sign in (1.0, -1.0):
        for my in (-1, 0, 1):
            for mx in (-1, 0, 1):
                cx = sign * mu[0] + 2 * mx * nyquist[1]
                cy = sign * mu[1] + 2 * my * nyquist[0]
                if abs(cx) - reach > nyquist[1] or abs(cy) - reach > nyquist[0]:
                    continue
                dx, dy = fx - cx, fy - cy
                ua, ub = c * dx + s * dy, -s * dx + c * dy
                g = (0.5 * w / (2 * math.pi * ab[0] * ab[1])
                     * np.exp(-0.5 * ((ua / ab[0]) ** 2 + (ub / ab[1]) ** 2)))
                terms.append((sign, g, ua, ub))
    return terms


def sm2d_psd(fy, fx, mixture: Mixture2D, spacing):
    """The model's spectrum (um^4) at the frequencies ``fy``, ``fx`` (arrays of one shape),
    folded over the aliases of a grid of ``spacing`` (dy, dx), plus the noise's
    :math:`\\sigma^2 \\Delta y \\Delta x` (module docstring)."""
    nyquist = (0.5 / spacing[0], 0.5 / spacing[1])
    fy, fx = np.asarray(fy, dtype=np.float64), np.asarray(fx, dtype=np.float64)
    total = np.full(fy.shape, mixture.noise * spacing[0] * spacing[1])
    for q in range(mixture.size):
        for _, g, _, _ in _component_terms(fy, fx, mixture.weights[q], mixture.means[q],
                                           mixture.bandwidths[q], mixture.angles[q], nyquist):
            total += g
    return total


@dataclasses.dataclass(frozen=True)
class _Spectrum:
    """The ordinates the Whittle likelihood sums over: frequencies, the periodogram of the
    differences (``power``, um^4) and their transmission (``gain``: the expected ``power`` is
    the spectrum times ``gain``), the count of raw ordinates each stands for; the grid's
    frequency step and Nyquist."""

    fy: np.ndarray
    fx: np.ndarray
    power: np.ndarray
    gain: np.ndarray
    counts: np.ndarray
    step: float
    nyquist: tuple
    spacing: tuple


def _half_plane(fy, fx):
    return (fx > 0) | ((fx == 0) & (fy > 0))


def _spectrum(heights, spacing, max_ordinates=MAX_ORDINATES) -> _Spectrum:
    """The half-plane periodogram of the differences of ``heights`` (NaN where unmeasured) and
    its transmission, block-averaged over ``k x k`` frequencies when it has more than
    ``max_ordinates`` ordinates."""
    qy, qx, c = psd_table.periodogram(heights, spacing, prewhiten=True)
    ny, nx = c.shape
    gain = (4 * np.sin(np.pi * qy * spacing[0])[:, None] ** 2
            + 4 * np.sin(np.pi * qx * spacing[1])[None, :] ** 2)
    p, gain = np.fft.fftshift(c * gain), np.fft.fftshift(gain)
    k = max(1, math.ceil(math.sqrt(ny * nx / 2 / max_ordinates)))
    fy = np.fft.fftshift(qy)[:, None] * np.ones((1, nx))
    fx = np.ones((ny, 1)) * np.fft.fftshift(qx)[None, :]
    keep = _half_plane(fy, fx)
    if k > 1:
        ty, tx = ny // k * k, nx // k * k
        oy, ox = (ny - ty) // 2, (nx - tx) // 2

        def blocks(a):
            return a[oy:oy + ty, ox:ox + tx].reshape(ty // k, k, tx // k, k)
        counts = blocks(keep.astype(float)).sum((1, 3))
        with np.errstate(invalid="ignore"):
            power = (blocks(np.where(keep, p, 0.0)).sum((1, 3))) / counts
            gain = (blocks(np.where(keep, gain, 0.0)).sum((1, 3))) / counts
            fy = blocks(np.where(keep, fy, 0.0)).sum((1, 3)) / counts
            fx = blocks(np.where(keep, fx, 0.0)).sum((1, 3)) / counts
        keep = counts > 0
        power, gain, fy, fx, counts = (power[keep], gain[keep], fy[keep], fx[keep],
                                       counts[keep])
    else:
        power, gain, fy, fx, counts = (p[keep], gain[keep], fy[keep], fx[keep],
                                       np.ones(int(keep.sum())))
    step = k * max(1.0 / (ny * spacing[0]), 1.0 / (nx * spacing[1]))
    return _Spectrum(fy, fx, power, gain, counts, step, (0.5 / spacing[0], 0.5 / spacing[1]),
                     tuple(spacing))


def _unpack(x, q):
    comp = x[:_PER_COMPONENT * q].reshape(q, _PER_COMPONENT)
    return Mixture2D(np.exp(comp[:, 0]), comp[:, 1:3].copy(), np.exp(comp[:, 3:5]),
                     comp[:, 5].copy(), float(np.exp(x[-1])))


def _pack(m: Mixture2D):
    comp = np.column_stack([np.log(m.weights), m.means, np.log(m.bandwidths), m.angles])
    return np.concatenate([comp.ravel(), [math.log(m.noise)]])


def _loss(x, spec: _Spectrum, q, scale):
    """The negative Whittle log likelihood (divided by ``scale``) and its gradient in ``x``."""
    m = _unpack(x, q)
    area = spec.spacing[0] * spec.spacing[1]
    parts = [_component_terms(spec.fy, spec.fx, m.weights[j], m.means[j], m.bandwidths[j],
                              m.angles[j], spec.nyquist) for j in range(q)]
    s = np.full(spec.power.shape, m.noise * area)
    for terms in parts:
        for _, g, _, _ in terms:
            s += g
    ratio = spec.power / (s * spec.gain)
    value = float(np.sum(spec.counts * (np.log(s * spec.gain) + ratio))) / scale
    g_s = spec.counts * (1.0 - ratio) / s / scale  # dL/dS
    grad = np.zeros_like(x)
    for j, terms in enumerate(parts):
        a, b = m.bandwidths[j]
        c, sn = math.cos(m.angles[j]), math.sin(m.angles[j])
        row = grad[_PER_COMPONENT * j:_PER_COMPONENT * (j + 1)]
        for sign, g, ua, ub in terms:
            h = g_s * g
            row[0] += h.sum()
            pa, pb = ua / a ** 2, ub / b ** 2  # P d in the component's axes
            row[1] += sign * np.sum(h * (c * pa - sn * pb))
            row[2] += sign * np.sum(h * (sn * pa + c * pb))
            row[3] += np.sum(h * (ua * ua / a ** 2 - 1.0))
            row[4] += np.sum(h * (ub * ub / b ** 2 - 1.0))
            row[5] += -np.sum(h * ua * ub) * (1.0 / a ** 2 - 1.0 / b ** 2)
    grad[-1] = float(np.sum(g_s)) * m.noise * area
    return value, grad


def _bounds(spec: _Spectrum, q, variance):
    low_w, high_w = math.log(1e-8 * variance), math.log(10.0 * variance)
    lo_b, hi_b = math.log(spec.step), math.log(max(spec.nyquist))
    one = [(low_w, high_w), (-spec.nyquist[1], spec.nyquist[1]),
           (-spec.nyquist[0], spec.nyquist[0]), (lo_b, hi_b), (lo_b, hi_b),
           (-math.pi, math.pi)]
    return one * q + [(math.log(1e-10 * variance), math.log(2.0 * variance))]


def _clipped(x, bounds):
    return np.array([min(max(v, lo), hi) for v, (lo, hi) in zip(x, bounds)])


def _log_likelihood(spec, m):
    s = sm2d_psd(spec.fy, spec.fx, m, spec.spacing) * spec.gain
    return -float(np.sum(spec.counts * (np.log(s) + spec.power / s)))


def _new_component(spec: _Spectrum, current: Mixture2D | None, variance):
    """The next component's start: broad at zero frequency first, then at the frequency whose
    excess of the periodogram over the current spectrum is largest (module docstring)."""
    estimate = spec.power / spec.gain  # the prewhitened periodogram, um^4
    if current is None:
        spread = math.sqrt(float(np.sum(estimate * (spec.fx ** 2 + spec.fy ** 2))
                                 / np.sum(estimate)) / 2)
        width = min(max(spread, 2 * spec.step), max(spec.nyquist) / 2)
        noise = float(np.median(estimate[np.hypot(spec.fx / spec.nyquist[1], spec.fy
                                                    / spec.nyquist[0]) > 0.8]))
        noise = min(max(noise / (spec.spacing[0] * spec.spacing[1]), 1e-6 * variance),
                    0.5 * variance)
        return Mixture2D(np.array([variance]), np.zeros((1, 2)), np.full((1, 2), width),
                         np.zeros(1), noise)
    model = sm2d_psd(spec.fy, spec.fx, current, spec.spacing)
    excess = estimate - model
    i = int(np.argmax(excess))
    width = 1.5 * spec.step
    weight = max(float(excess[i]) * 2 * 2 * math.pi * width * width, 1e-6 * variance)
    return Mixture2D(np.concatenate([current.weights, [weight]]),
                     np.vstack([current.means, [[spec.fx[i], spec.fy[i]]]]),
                     np.vstack([current.bandwidths, [[width, width]]]),
                     np.concatenate([current.angles, [0.0]]), current.noise)


def whittle_fit(heights, spacing, max_components=MAX_COMPONENTS, max_ordinates=MAX_ORDINATES):
    """``(mixture, table, notes)``: the BIC-chosen mixture fitted to ``heights`` (NaN where
    unmeasured) by the Whittle likelihood (module docstring); ``table`` a row per Q tried:
    ``(Q, log likelihood, BIC)``; ``notes`` the chosen fit's values on a bound."""
    if not (isinstance(max_components, int) and 1 <= max_components <= 8):
        raise ValueError(f"max_components must be an integer in [1, 8], got "
                         f"{max_components!r}")
    spec = _spectrum(heights, spacing, max_ordinates)
    variance = float(np.nanvar(heights))
    if not variance > 0:
        raise ValueError("the form-removed heights are constant: no spectrum to fit")
    n = float(spec.counts.sum())
    current, best, table = None, None, []
    for q in range(1, max_components + 1):
        start = _new_component(spec, current, variance)
        bounds = _bounds(spec, q, variance)
        x0 = _clipped(perturbed_start(_clipped(_pack(start), bounds)), bounds)
        result = scipy.optimize.minimize(_loss, x0,
                                         args=(spec, q, n), jac=True, method="L-BFGS-B",
                                         bounds=bounds, options={"maxiter": 400})
        current = _unpack(result.x, q)
        ll = _log_likelihood(spec, current)
        bic = -2 * ll + (_PER_COMPONENT * q + 1) * math.log(n)
        table.append((q, ll, bic))
        if best is None or bic < best[2]:
            best = (current, result.x, bic, bounds)
        elif q >= 2 and bic > table[-2][2]:
            break  # the BIC rose: a further component is not supported either
    mixture, x, _, bounds = best
    return _apportioned(spec, mixture), table, _bound_notes(x, bounds, mixture.size)


def _apportioned(spec: _Spectrum, m: Mixture2D) -> Mixture2D:
    r"""``m`` with each weight (and the noise) set to the periodogram's power that its part of
    the spectrum is responsible for, :math:`w_q \sum_k G_{qk} I_k / E_k / \sum_k G_{qk}`
    (one EM step on the spectrum): the variance of the measured heights is conserved (module
    docstring)."""
    area = spec.spacing[0] * spec.spacing[1]
    parts = [sum(g for _, g, _, _ in _component_terms(spec.fy, spec.fx, m.weights[j],
                                                      m.means[j], m.bandwidths[j],
                                                      m.angles[j], spec.nyquist))
             for j in range(m.size)]
    noise = np.full(spec.power.shape, m.noise * area)
    ratio = spec.counts * spec.power / ((sum(parts) + noise) * spec.gain)

    def scale(part):
        return float(np.sum(ratio * part) / np.sum(spec.counts * part))
    weights = np.array([w * scale(part) for w, part in zip(m.weights, parts)])
    return dataclasses.replace(m, weights=np.maximum(weights, 1e-300),
                               noise=m.noise * scale(noise))


_NAMES = ("weight", "frequency x", "frequency y", "bandwidth a", "bandwidth b", "axes angle")


def _bound_notes(x, bounds, q):
    notes = []
    for i, (v, (lo, hi)) in enumerate(zip(x, bounds)):
        if i % _PER_COMPONENT == 5 and i < q * _PER_COMPONENT:
            continue  # the angle is periodic: its box is no bound of the model
        tol = 1e-4 * (hi - lo)
        side = "lower" if v - lo <= tol else "upper" if hi - v <= tol else None
        if side is None:
            continue
        if i == len(x) - 1:
            what = "the noise variance"
        else:
            what = f"component {i // _PER_COMPONENT + 1}'s {_NAMES[i % _PER_COMPONENT]}"
        finest = " (one frequency bin, the finest the field resolves)"
        why = {3: finest, 4: finest, 1: " (the Nyquist frequency)",
               2: " (the Nyquist frequency)"}
        extra = why.get(i % _PER_COMPONENT, "") if i < len(x) - 1 else ""
        notes.append(f"{what} ends on its {side} bound{extra}")
    return notes
