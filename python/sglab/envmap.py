"""HDR environment maps as SG lighting, as `sglab envmap`
(docs/envmaps.md): equirectangular maps, +z up, row 0 at the zenith, column
i at azimuth 2*pi*(i + 1/2)/W, direction (sin t cos p, -sin t sin p, cos t)."""

import os as _os

import numpy as _np

from . import _sglab

_env = _sglab.envmap
Map = _env.Map


def load(source):
    """A map from a file path (OpenEXR or Radiance .hdr, read and checked as
    the CLI reads it) or from an array of shape (height, width, 3) of radiance
    (width = 2 * height; converted to float32; the same checks: size, finite,
    no negative value below -5 % of the mean)."""
    if isinstance(source, Map):
        return source
    if isinstance(source, (str, bytes, _os.PathLike)):
        return _env.read(_os.fsdecode(source))
    a = _np.asarray(source)
    if a.dtype.kind not in "fiu":
        raise TypeError(f"envmap: expected a path or an array of real numbers, got dtype {a.dtype}")
    return _env.from_array(_np.ascontiguousarray(a, dtype=_np.float32))


def _vectors(x, name):
    a = _np.asarray(x)
    if a.dtype.kind not in "fiu":
        raise TypeError(f"{name}: expected real numbers, got dtype {a.dtype}")
    return _np.ascontiguousarray(_np.atleast_2d(a), dtype=_np.float64)


def fibonacci_normals(n):
    """n unit vectors over the sphere (Fibonacci lattice), shape (n, 3): the
    normals every envmap error is measured at."""
    return _env.fibonacci_normals(int(n))


def irradiance(source, normals):
    """The map's exact diffuse irradiance at each normal (rows of `normals`,
    normalized here), RGB, shape (n, 3) float64."""
    return _env.irradiance(load(source), _vectors(normals, "normals"))


def fit(source, lobes, objective="irradiance", fit_normals=1024, max_iterations=200):
    """SG lobes fitted to the map with Ceres, as `sglab envmap fit FILE --lobes
    N [--objective radiance]`: on its 128 x 64 working copy, the irradiance
    objective against the full map's exact irradiance at `fit_normals`
    Fibonacci normals. A dict: axis (N, 3), sharpness (N,), amplitude (N, 3),
    iterations, converged."""
    return _env.fit(load(source), int(lobes), objective, int(fit_normals), int(max_iterations))


def lobes_irradiance(axis, sharpness, amplitude, normals):
    """The exact irradiance (reference engine) of SG lobes at the normals, RGB,
    shape (n, 3): compare with `irradiance` for a fit's error."""
    s = _np.ascontiguousarray(_np.atleast_1d(_np.asarray(sharpness, dtype=_np.float64)))
    return _env.lobes_irradiance(_vectors(axis, "axis"), s, _vectors(amplitude, "amplitude"),
                                 _vectors(normals, "normals"))
