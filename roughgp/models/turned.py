r"""Synthetic, measurement-like turned profiles and surfaces with known truth (section 3.3).

The paper fits its turned-profile and turned-surface models to confocal measurements of a
turned Rubert roughness standard (figures 4 and 6) that are not public. This module is a
physically grounded stand-in, so that every chapter can run and every claim about the fit can
be judged against a known truth.

The model (all lengths in micrometres)
--------------------------------------
**Kinematic profile.** A tool with nose radius :math:`r` advances by the feed :math:`f` per
revolution. Pass :math:`k` leaves the circular arc
:math:`a_k(x) = r - \sqrt{r^2 - (x - c_k)^2} + d_k` around its centre :math:`c_k = k f`
(depth offset :math:`d_k`), and the surface is what no pass removed, the lower envelope
:math:`z(x) = \min_k a_k(x)`. Arcs meet in sharp cusps: **wide dales, narrow hills**. With
:math:`d_k = 0` the peak-to-valley height is :math:`R_t = r - \sqrt{r^2 - f^2/4}
\approx f^2 / (8r)` (:func:`kinematic_rt`).

**Deviations** that a measurement of a real turned part shows, each switchable:

* *feed-mark to feed-mark variation*: the centre :math:`c_k` jitters by ``feed_jitter``
  (spindle run-out, vibration) and the depth :math:`d_k` by ``depth_jitter``; on a surface
  :math:`d_k` also varies slowly along the feed mark (a smooth random function of y with
  correlation length ``lay_lengthscale``).
* *tool-edge roughness*: the cutting edge is not a perfect circle; its small deviation
  :math:`e(u)` (a smooth random function, standard deviation ``edge_roughness``,
  correlation length ``edge_lengthscale``) is copied into every feed mark, at
  :math:`u = x - c_k`, so it repeats with the feed.
* *material side flow and built-up edge*: a stationary random field (exponential ACVF,
  standard deviation ``flow_roughness``, correlation length ``flow_lengthscale``) on top.
* *instrument noise*: white, standard deviation ``noise_sd`` (eq 8's noise model, literally).
* *tilt*: a plane of slope ``tilt`` (per axis, micrometres per micrometre), as a
  measurement that was not levelled has. A fit must remove it first
  (:func:`roughgp.metrology.levelling.level`).

The defaults, :data:`RUBERT_LIKE`, are a coarse finish of the kind on a Rubert turned
standard with a high Ra: f = 250 um, r = 800 um (Rt about 9.8 um, Ra about 2.5 um), sampled
at 1 um as a confocal microscope with a 10x objective does after stitching.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from roughgp.common.checks import as_generator, check_integer, check_nonnegative, check_positive
from roughgp.common.grid import normalize

__all__ = ["TurnedParameters", "RUBERT_LIKE", "kinematic_rt", "kinematic_profile",
           "turned_profile", "turned_surface"]


@dataclasses.dataclass(frozen=True)
class TurnedParameters:
    """Parameters of the turned-surface generator (module docstring), in micrometres.

    Attributes:
        feed: f > 0, the feed per revolution (the period of the profile).
        nose_radius: r > f / 2, the tool nose radius.
        feed_jitter: >= 0, standard deviation of each feed mark's centre.
        depth_jitter: >= 0, standard deviation of each feed mark's depth.
        edge_roughness, edge_lengthscale: standard deviation (>= 0) and correlation length
            (> 0) of the tool-edge deviation copied into every feed mark.
        flow_roughness, flow_lengthscale: standard deviation (>= 0) and correlation length
            (> 0) of the side-flow field (exponential ACVF).
        noise_sd: >= 0, the instrument noise.
        tilt: slope per axis in array order, (dz/dx,) for a profile or (dz/dy, dz/dx) for a
            surface; a scalar is the slope along x.
        lay_lengthscale: > 0, correlation length along a feed mark of its depth variation
            (surfaces only).
    """

    feed: float = 250.0
    nose_radius: float = 800.0
    feed_jitter: float = 2.0
    depth_jitter: float = 0.3
    edge_roughness: float = 0.15
    edge_lengthscale: float = 6.0
    flow_roughness: float = 0.1
    flow_lengthscale: float = 3.0
    noise_sd: float = 0.05
    tilt: float | tuple = 0.0
    lay_lengthscale: float = 150.0

    def __post_init__(self):
        kinematic_rt(self.feed, self.nose_radius)  # checks feed > 0 and nose_radius > feed / 2
        for name in ("feed_jitter", "depth_jitter", "edge_roughness", "flow_roughness",
                     "noise_sd"):
            check_nonnegative(name, getattr(self, name))
        if not self.feed_jitter < self.feed / 4:
            raise ValueError(f"feed_jitter must be in [0, feed / 4 = {self.feed / 4:g}), "
                             f"got {self.feed_jitter!r}")
        for name in ("edge_lengthscale", "flow_lengthscale", "lay_lengthscale"):
            check_positive(name, getattr(self, name))
        check_nonnegative("abs(tilt)", np.abs(np.asarray(self.tilt, dtype=float)))

    @property
    def rt(self) -> float:
        """The kinematic peak-to-valley height :func:`kinematic_rt` of feed and nose radius."""
        return kinematic_rt(self.feed, self.nose_radius)


def kinematic_rt(feed, nose_radius):
    r"""Peak-to-valley height of the ideal turned profile, :math:`r - \sqrt{r^2 - f^2/4}`
    (about :math:`f^2 / (8r)` for :math:`f \ll r`)."""
    check_positive("feed", feed)
    check_positive("nose_radius", nose_radius)
    if not nose_radius > feed / 2:
        raise ValueError(f"nose_radius must be > feed / 2 = {feed / 2:g} (a circular nose "
                         f"cannot cut a mark wider than its diameter), got {nose_radius!r}")
    return nose_radius - math.sqrt(nose_radius ** 2 - feed ** 2 / 4)


#: The chapters' default: a coarse turned finish (f = 250 um, r = 800 um), 1 um sampling.
RUBERT_LIKE = TurnedParameters()


def _arc(u, radius):
    # beyond the nose (|u| >= r) the tool does not cut: +inf leaves the envelope to others
    inside = np.abs(u) < radius
    out = np.full(np.shape(u), np.inf)
    out[inside] = radius - np.sqrt(radius ** 2 - u[inside] ** 2)
    return out


def kinematic_profile(x, feed, nose_radius, centres=None, depths=None, edge=None):
    """The lower envelope of the tool's arcs at positions ``x`` (module docstring).

    Args:
        x: positions, shape (n,), micrometres.
        feed, nose_radius: as in :class:`TurnedParameters`.
        centres: arc centres :math:`c_k`, sorted, spaced about ``feed`` apart; default
            ``k * feed`` covering ``x``. ``depths``: :math:`d_k`, one per centre, default 0.
        edge: optional function of the offset ``u = x - c_k`` added to each arc (the tool-edge
            deviation).

    Returns:
        heights of shape ``x.shape``; the lowest point of an undisturbed arc is at 0.
    """
    x = np.asarray(x, dtype=np.float64)
    kinematic_rt(feed, nose_radius)
    if centres is None:
        k = np.arange(math.floor(x.min() / feed) - 1, math.ceil(x.max() / feed) + 2)
        centres = k * feed
    centres = np.asarray(centres, dtype=np.float64)
    depths = np.zeros(centres.size) if depths is None else np.asarray(depths, float)
    if centres.ndim != 1 or depths.shape != centres.shape:
        raise ValueError(f"centres and depths must have the same shape (marks,), got "
                         f"{centres.shape} and {depths.shape}")
    # the envelope at x is set by the arcs whose centres are nearest: two on either side
    nearest = np.searchsorted(centres, x)
    out = np.full(x.shape, np.inf)
    for shift in (-2, -1, 0, 1):
        idx = np.clip(nearest + shift, 0, centres.size - 1)
        u = x - centres[idx]
        arc = _arc(u, nose_radius) + depths[idx]
        if edge is not None:
            arc = arc + edge(u)
        out = np.minimum(out, arc)
    return out


def _smooth_field(n, spacing, lengthscale, sd, rng, extra_shape=()):
    """Smooth random functions (squared-exponential ACVF) on a grid of n points, by filtering
    white noise with a Gaussian (whose ACVF is Gaussian with correlation length
    ``lengthscale``); shape ``extra_shape + (n,)``."""
    if sd == 0:
        return np.zeros(extra_shape + (n,))
    width = lengthscale / spacing / math.sqrt(2.0)  # filter sd in samples
    half = int(math.ceil(4 * width))
    white = rng.standard_normal(extra_shape + (n + 2 * half,))
    taps = np.exp(-0.5 * (np.arange(-half, half + 1) / width) ** 2)
    taps /= math.sqrt(np.sum(taps ** 2))
    spectrum = np.fft.rfft(white, axis=-1) * np.fft.rfft(taps, white.shape[-1])
    filtered = np.fft.irfft(spectrum, white.shape[-1], axis=-1)[..., 2 * half:2 * half + n]
    return sd * filtered


def _edge_function(params, spacing, rng):
    """The tool-edge deviation e(u) on |u| <= feed, interpolated (module docstring)."""
    if params.edge_roughness == 0:
        return None
    step = min(spacing, params.edge_lengthscale / 4)
    u = np.arange(-params.feed, params.feed + step, step)
    values = _smooth_field(u.size, step, params.edge_lengthscale, params.edge_roughness, rng)
    return lambda offset: np.interp(offset, u, values)


def _flow_field(shape, spacing, params, rng):
    if params.flow_roughness == 0:
        return np.zeros(shape)
    from roughgp.gp.numpy_kernels import MaternACVF
    from roughgp.sampling.grid_sampler import sample_grid
    kernel = MaternACVF(variance=params.flow_roughness ** 2,
                        lengthscale=params.flow_lengthscale, nu=0.5, dim=len(shape))
    return sample_grid(kernel, shape, spacing=spacing, seed=rng)[0]


def _tilt(params, ndim):
    tilt = np.atleast_1d(np.asarray(params.tilt, dtype=np.float64))
    if tilt.size == 1:
        tilt = np.concatenate((np.zeros(ndim - 1), tilt))
    if tilt.size != ndim:
        raise ValueError(f"tilt must be a scalar or have {ndim} values (array order), got "
                         f"{params.tilt!r}")
    return tilt


def turned_profile(n=8192, spacing=1.0, params=RUBERT_LIKE, *, seed=None):
    """A measurement-like turned profile with known truth (module docstring).

    Args:
        n: number of points (>= 16). spacing: > 0, micrometres.
        params: :class:`TurnedParameters` (default :data:`RUBERT_LIKE`).
        seed: int, None or Generator; the same seed gives the same profile.

    Returns:
        ``(x, z)``: positions from 0 and heights, shape (n,) each, micrometres.
    """
    (n,), (spacing,) = normalize((check_integer("n", n, 16),), spacing)
    if not isinstance(params, TurnedParameters):
        raise ValueError(f"params must be a TurnedParameters, got {type(params).__name__}")
    rng = as_generator(seed)
    x = np.arange(n) * spacing
    z = _turned(x[None, :], spacing, params, rng)[0]
    z = z + _flow_field((n,), spacing, params, rng)
    z = z + params.noise_sd * rng.standard_normal(n)
    z = z + _tilt(params, 1)[0] * x
    return x, z


def _turned(x, spacing, params, rng, depth_variation=None):
    """Kinematic profile with jittered feed marks and edge deviation for every row of x."""
    length = x.max()
    k = np.arange(-2, math.ceil(length / params.feed) + 3)
    offset = rng.uniform(0, params.feed)  # where the first feed mark lies
    centres = k * params.feed + offset + params.feed_jitter * rng.standard_normal(k.size)
    centres.sort()
    depths = params.depth_jitter * rng.standard_normal(k.size)
    edge = _edge_function(params, spacing, rng)
    rows = x.shape[0]
    if depth_variation is not None:
        depths = depths[None, :] + depth_variation  # (rows, marks)
    else:
        depths = np.broadcast_to(depths, (rows, k.size))
    z = np.empty(x.shape)
    for i in range(rows):
        z[i] = kinematic_profile(x[i], params.feed, params.nose_radius, centres, depths[i],
                                 edge)
    return z


def turned_surface(shape=(256, 1024), spacing=1.0, params=RUBERT_LIKE, *, seed=None):
    """A measurement-like turned surface: feed marks run along y (rows), the feed is along x.

    Each feed mark's depth varies slowly along y (``params.lay_lengthscale``, with standard
    deviation ``params.depth_jitter``); the tool-edge deviation, side-flow field, noise and
    tilt are as in :func:`turned_profile`.

    Args:
        shape: ``(ny, nx)``, each >= 16. spacing: scalar or ``(dy, dx)`` in micrometres.
        params: :class:`TurnedParameters`. seed: int, None or Generator.

    Returns:
        ``z`` of shape ``(ny, nx)`` (``z[iy, ix]``), micrometres.
    """
    shape, spacing = normalize(shape, spacing)
    if len(shape) != 2 or min(shape) < 16:
        raise ValueError(f"shape must be (ny, nx) with both >= 16, got {shape!r}")
    if not isinstance(params, TurnedParameters):
        raise ValueError(f"params must be a TurnedParameters, got {type(params).__name__}")
    rng = as_generator(seed)
    ny, nx = shape
    dy, dx = spacing
    x = np.broadcast_to(np.arange(nx) * dx, (ny, nx))
    n_marks = math.ceil(x.max() / params.feed) + 5
    variation = _smooth_field(ny, dy, params.lay_lengthscale, params.depth_jitter, rng,
                              (n_marks,)).T  # (ny, marks)
    z = _turned(x, dx, params, rng, depth_variation=variation)
    z = z + _flow_field(shape, spacing, params, rng)
    z = z + params.noise_sd * rng.standard_normal(shape)
    ty, tx = _tilt(params, 2)
    y = np.arange(ny)[:, None] * dy
    return z + ty * y + tx * x
