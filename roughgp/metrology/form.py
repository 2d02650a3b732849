"""F-operators: removal of the nominal form (plane, polynomial, cylinder) from a measurement.

ISO 25178-2 / ISO 25178-3 (and ISO 4287 for profiles) put an F-operator before the L-filter:
the least-squares nominal form is fitted and subtracted, and the residual is the
form-removed (SF) surface that the filters of :mod:`roughgp.metrology.filters` act on.
Implemented here, each NaN-aware (the fit uses the finite points only; the residual is NaN
where the input is NaN):

* :func:`remove_plane` -- least-squares line (profile) or plane (surface); it calls
  :func:`roughgp.metrology.levelling.level` and only wraps its result.
* :func:`remove_polynomial` -- least-squares polynomial of total degree ``degree`` in x and y
  with all cross terms ``x**i * y**j`` (``i + j <= degree``); a profile: in x.
* :func:`remove_cylinder` -- least-squares cylinder (ISO 25178-2's "form" of a curved part
  such as a bullet land), axis along x or y (or ``"auto"``: the better of the two), radius,
  axis position and tilt fitted by nonlinear least squares on the orthogonal (radial)
  distances, started from the best quadratic; a profile: a least-squares circle.

Each returns ``(residual, FormFit)``. Coordinates are those of :mod:`roughgp.common.grid`:
``x = ix * dx``, ``y = iy * dy`` with ``spacing`` in array order ``(dy, dx)``; heights and
lengths in the same unit (micrometres in roughgp).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from roughgp.common.checks import check_integer, height_map
from roughgp.common.grid import normalize
from roughgp.metrology.levelling import level

__all__ = ["FormFit", "remove_plane", "remove_polynomial", "remove_cylinder", "remove_form",
           "form_heights"]


@dataclass(frozen=True)
class FormFit:
    """What an F-operator removed.

    Attributes:
        method: ``"plane"``, ``"polynomial"``, ``"cylinder"`` or ``"none"``.
        parameters: the fitted form. plane: ``offset`` (height at x = y = 0), ``slope_x``,
            ``slope_y`` (surface only); polynomial: ``degree`` and ``c[i,j]`` the coefficient
            of ``(x - xc)**i * (y - yc)**j`` with ``xc``, ``yc`` the field centre (also given);
            cylinder: ``radius``, ``axis`` (0 for x, 1 for y as a float; see ``label``),
            ``axis_x0`` / ``axis_y0`` (the axis' position across it at the field centre),
            ``axis_z0`` (its height there), ``tilt`` (dz/ds of the axis along it),
            ``skew`` (its drift across per unit length along it), ``convex`` (1 or 0).
        rms: root mean square of the residual over the finite points.
        label: a one-line description for the output, e.g. ``"F: plane"``.
    """

    method: str
    parameters: dict = field(default_factory=dict)
    rms: float = float("nan")
    label: str = ""


def _rms(residual):
    return float(np.sqrt(np.nanmean(residual ** 2)))


def remove_plane(z, spacing=1.0):
    """Subtract the least-squares line (profile) or plane (surface), NaN-aware.

    Returns ``(residual, FormFit)``; the fit is :func:`~roughgp.metrology.levelling.level`'s.
    Raises ValueError for bad ``z`` (all NaN, too few points) or ``spacing``.
    """
    arr = height_map(z)
    residual, fit = level(arr, spacing=spacing, order=1, return_coefficients=True)
    params = {"offset": fit.offset, "slope_x": fit.slope[-1]}
    if arr.ndim == 2:
        params["slope_y"] = fit.slope[0]
    label = "F: plane" if arr.ndim == 2 else "F: least-squares line"
    return residual, FormFit("plane", params, _rms(residual), label)


def _terms(ndim, degree):
    """Exponent pairs (i, j) of x**i * y**j with i + j <= degree, in surfalize's order."""
    if ndim == 1:
        return [(i, 0) for i in range(degree + 1)]
    return [(d - j, j) for d in range(degree + 1) for j in range(d + 1)]


def remove_polynomial(z, spacing=1.0, degree=2):
    """Subtract the least-squares polynomial of total degree ``degree`` (cross terms
    included; a profile: a polynomial in x), NaN-aware.

    ``degree`` is an integer >= 0 (0: the mean, 1: the plane). Returns ``(residual,
    FormFit)``. Raises ValueError for bad ``z``, ``spacing``, ``degree``, or fewer measured
    points than coefficients.
    """
    arr = height_map(z)
    degree = check_integer("degree", degree, 0)
    _, sp = normalize(arr.shape, spacing)
    axes = [np.arange(n) * d for n, d in zip(arr.shape, sp)]
    centres = [a.mean() for a in axes]
    half = [max((a[-1] - a[0]) / 2, d) for a, d in zip(axes, sp)]  # scaling to about [-1, 1]
    grids = np.meshgrid(*[(a - c) / h for a, c, h in zip(axes, centres, half)], indexing="ij")
    u = grids[-1]
    v = grids[0] if arr.ndim == 2 else np.zeros_like(u)
    terms = _terms(arr.ndim, degree)
    measured = np.isfinite(arr)
    if np.count_nonzero(measured) < len(terms):
        raise ValueError(f"z has {np.count_nonzero(measured)} measured points; degree={degree} "
                         f"needs at least {len(terms)}")
    design = np.stack([u ** i * v ** j for i, j in terms], axis=-1)
    coef, _, rank, _ = np.linalg.lstsq(design[measured], arr[measured], rcond=None)
    if rank < len(terms):
        raise ValueError(f"the measured points of z do not determine a polynomial of "
                         f"degree={degree}; use a lower degree")
    residual = arr - design @ coef
    hx, hy = half[-1], (half[0] if arr.ndim == 2 else 1.0)
    params = {"degree": degree, "xc": float(centres[-1])}
    if arr.ndim == 2:
        params["yc"] = float(centres[0])
    for (i, j), c in zip(terms, coef):
        params[f"c[{i},{j}]"] = float(c / (hx ** i * hy ** j))
    return residual, FormFit("polynomial", params, _rms(residual),
                             f"F: polynomial of degree {degree}")


# --------------------------------------------------------------------------- cylinder

def _cylinder_heights(p, s, t, convex):
    """Height of the cylinder sheet above the points (s along the axis, t across it).

    ``p = (t0, z0, skew, tilt, radius)``: the axis passes through (t0, 0, z0) with direction
    (skew, 1, tilt) in (t, s, z). Solves |w x d| = R for the vertical line at (t, s).
    """
    t0, z0, skew, tilt, radius = p
    d = np.array([skew, 1.0, tilt]) / np.sqrt(1.0 + skew ** 2 + tilt ** 2)
    wt, ws = t - t0, s
    # |w|^2 - (w.d)^2 = R^2 with w = (wt, ws, h) and h = z - z0: a quadratic in h.
    a = 1.0 - d[2] ** 2
    lin = wt * d[0] + ws * d[1]
    b = -2.0 * lin * d[2]
    c = wt ** 2 + ws ** 2 - lin ** 2 - radius ** 2
    disc = np.sqrt(np.maximum(b * b - 4.0 * a * c, 0.0))
    h = (-b + disc) / (2 * a) if convex else (-b - disc) / (2 * a)
    return z0 + h


def _radial(p, s, t, z, convex):
    t0, z0, skew, tilt, radius = p
    d = np.array([skew, 1.0, tilt]) / np.sqrt(1.0 + skew ** 2 + tilt ** 2)
    w = np.stack([t - t0, s, z - z0])
    dot = d @ w
    dist = np.sqrt(np.maximum((w * w).sum(axis=0) - dot ** 2, 0.0))
    return dist - radius


def _fit_cylinder(z, s_axis, t_axis, circle=False):
    """Fit a cylinder whose axis runs along array axis 0 of ``z`` (coordinates s) and whose
    cross-section runs along axis 1 (coordinates t); both centred. Returns (params, convex,
    residual surface, rms) or None when the quadratic start shows no curvature. ``circle``:
    one row (a profile), the axis is held normal to it (no skew, no tilt)."""
    ss, tt = np.meshgrid(s_axis, t_axis, indexing="ij")
    m = np.isfinite(z)
    s, t, h = ss[m], tt[m], z[m]
    design = np.column_stack([np.ones_like(t), t, t * t] + ([] if circle else [s, s * t]))
    c0, c1, c2, *rest = np.linalg.lstsq(design, h, rcond=None)[0]
    c3 = 0.0 if circle else rest[0]
    if c2 == 0 or not np.isfinite(c2):
        return None
    convex = bool(c2 < 0)
    radius = 1.0 / (2.0 * abs(c2))
    t_vertex = -c1 / (2.0 * c2)
    z_vertex = c0 - c1 ** 2 / (4.0 * c2)
    z0 = z_vertex - radius if convex else z_vertex + radius
    start = np.array([t_vertex, z0, 0.0, c3, radius])
    scale = np.array([radius, radius, 1e-3, 1e-3, radius])
    free = np.array([0, 1, 4]) if circle else np.arange(5)

    def distances(q):
        p = start.copy()
        p[free] = q
        return _radial(p, s, t, h, convex)

    from scipy.optimize import least_squares  # here: 0.2-0.5 s a plane or polynomial skips

    fit = least_squares(distances, start[free], x_scale=scale[free], method="lm")
    p = start.copy()
    p[free] = fit.x
    residual = np.full(z.shape, np.nan)
    residual[m] = h - _cylinder_heights(p, s, t, convex)
    return p, convex, residual, _rms(residual)


def remove_cylinder(z, spacing=1.0, axis="auto"):
    """Subtract the least-squares cylinder (a surface) or circle (a profile), NaN-aware.

    Args:
        z: a surface ``z[iy, ix]`` (or a profile ``z[ix]``: the circle's axis is normal to it).
        spacing: scalar or ``(dy, dx)``, > 0.
        axis: ``"x"`` (axis along x, the cross-section is curved in y), ``"y"`` (axis along
            y, curved in x: a bullet land whose striations run along y) or ``"auto"`` (both
            fitted, the smaller residual rms kept). Ignored for a profile.

    The radius, the axis position, its height and its two tilts are fitted by
    ``scipy.optimize.least_squares`` on the orthogonal distances to the cylinder, started
    from the least-squares quadratic across the axis; the residual returned is the vertical
    height above the fitted cylinder surface (the sheet facing the instrument). Returns
    ``(residual, FormFit)``. Raises ValueError for bad ``z``, ``spacing``, ``axis``, fewer
    than 6 measured points, or a flat quadratic (no curvature to fit).
    """
    arr = height_map(z)
    _, sp = normalize(arr.shape, spacing)
    if axis not in ("x", "y", "auto"):
        raise ValueError(f"axis must be 'x', 'y' or 'auto', got {axis!r}")
    if np.count_nonzero(np.isfinite(arr)) < 6:
        raise ValueError("z must hold at least 6 measured points for a cylinder fit")
    surf = arr[None, :] if arr.ndim == 1 else arr
    dy, dx = (1.0, sp[0]) if arr.ndim == 1 else (sp[0], sp[1])
    x = np.arange(surf.shape[1]) * dx
    y = np.arange(surf.shape[0]) * dy
    xc, yc = x.mean(), y.mean()
    candidates = []
    for ax in (["y"] if arr.ndim == 1 else (["x", "y"] if axis == "auto" else [axis])):
        if ax == "y":  # axis along y = array axis 0, cross-section along x
            out = _fit_cylinder(surf, y - yc, x - xc, circle=arr.ndim == 1)
            if out is not None:
                candidates.append((ax, out[0], out[1], out[2], out[3]))
        else:
            out = _fit_cylinder(surf.T, x - xc, y - yc)
            if out is not None:
                candidates.append((ax, out[0], out[1], out[2].T, out[3]))
    if not candidates:
        raise ValueError("z shows no curvature: no cylinder can be fitted (use form='plane')")
    ax, p, convex, residual, rms = min(candidates, key=lambda c: c[4])
    t0, z0, skew, tilt, radius = (float(v) for v in p)
    across = "axis_x0" if ax == "y" else "axis_y0"
    params = {"radius": radius, "axis": 1.0 if ax == "y" else 0.0,
              across: float(t0 + (xc if ax == "y" else yc)), "axis_z0": z0, "tilt": tilt,
              "skew": skew, "convex": 1.0 if convex else 0.0}
    if arr.ndim == 1:
        residual = residual[0]
        params = {"radius": radius, "axis_x0": float(t0 + xc), "axis_z0": z0,
                  "convex": 1.0 if convex else 0.0}
        label = f"F: circle (R = {radius:.4g} um)"
    else:
        label = f"F: cylinder (axis along {ax}, R = {radius:.4g} um)"
    return residual, FormFit("cylinder", params, rms, label)


def remove_form(z, spacing=1.0, form="plane", *, degree=2, axis="auto"):
    """Dispatch: ``form`` in {"plane", "polynomial", "cylinder", None} (None: nothing
    removed, ``FormFit("none")``). Returns ``(residual, FormFit)``."""
    if form is None:
        arr = height_map(z)
        return arr, FormFit("none", {}, _rms(arr), "F: none")
    if form == "plane":
        return remove_plane(z, spacing)
    if form == "polynomial":
        return remove_polynomial(z, spacing, degree)
    if form == "cylinder":
        return remove_cylinder(z, spacing, axis)
    raise ValueError(f"form must be 'plane', 'polynomial', 'cylinder' or None, got {form!r}")


def form_heights(fit: FormFit, shape, spacing=1.0) -> np.ndarray:
    """The form that ``fit`` removed, evaluated on the whole grid of ``shape`` (missing points
    included): what to add back to a form-removed surface after filling its holes.

    ``fit`` comes from one of this module's operators applied to a grid of this ``shape`` and
    ``spacing`` (its parameters refer to that grid's coordinates and centre).
    """
    shape, sp = normalize(shape, spacing)
    axes = [np.arange(n) * d for n, d in zip(shape, sp)]
    grids = np.meshgrid(*axes, indexing="ij")
    x = grids[-1]
    y = grids[0] if len(shape) == 2 else np.zeros_like(x)
    p = fit.parameters
    if fit.method == "none":
        return np.zeros(shape)
    if fit.method == "plane":
        return p["offset"] + p["slope_x"] * x + p.get("slope_y", 0.0) * y
    if fit.method == "polynomial":
        u, v = x - p["xc"], y - p.get("yc", 0.0)
        out = np.zeros(shape)
        for i, j in _terms(len(shape), int(p["degree"])):
            out += p[f"c[{i},{j}]"] * u ** i * v ** j
        return out
    if fit.method == "cylinder":
        convex = bool(p["convex"])
        if len(shape) == 1:
            q = (p["axis_x0"] - x.mean(), p["axis_z0"], 0.0, 0.0, p["radius"])
            return _cylinder_heights(q, np.zeros_like(x), x - x.mean(), convex)
        along_y = p["axis"] == 1.0
        s_coord, t_coord = (y - y.mean(), x - x.mean()) if along_y else (x - x.mean(),
                                                                         y - y.mean())
        t0 = p["axis_x0"] - x.mean() if along_y else p["axis_y0"] - y.mean()
        q = (t0, p["axis_z0"], p["skew"], p["tilt"], p["radius"])
        return _cylinder_heights(q, s_coord, t_coord, convex)
    raise ValueError(f"unknown form method {fit.method!r}")
