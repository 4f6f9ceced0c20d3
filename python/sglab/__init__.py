"""sglab: spherical Gaussian (SG) diffuse lighting from Python.

The C++ runtime's irradiance methods on NumPy arrays (broadcasting, no Python
loops, the GIL released during the work), their exact gradients (Ceres Jets
through the runtime's own templates), the quadrature reference engine, the
shader export and environment maps (``sglab.envmap``). ``sglab.torch`` wraps
the methods as a PyTorch autograd function. Bad input raises
``sglab.InputError`` (a ``ValueError``) with the message of the ``sglab``
command. See docs/python.md.
"""

import numpy as _np

from . import _sglab
from ._sglab import InputError
from . import envmap

__all__ = ["InputError", "methods", "irradiance", "irradiance_grad", "reference", "export",
           "envmap"]


def methods():
    """Every irradiance method: a list of dicts with id, origin (published,
    refit, sglab), source, constants, per_light_split (the runtime's), export,
    export_split and export_half (what sglab.export can write)."""
    return _sglab.methods()


def _real_array(x, name):
    """x as an array of real numbers: float16/32/64 or integers; anything else
    (complex, bool, object, strings, long double) is refused."""
    a = _np.asarray(x)
    kind, size = a.dtype.kind, a.dtype.itemsize
    if kind == "f" and size in (2, 4, 8):
        return a, _np.float64 if size == 8 else _np.float32
    if kind in "iu":
        return a, _np.float64
    raise TypeError(f"{name}: expected real numbers (float16, float32, float64 or integers), "
                    f"got an array of dtype {a.dtype}")


def _prepare(kappa, cosine):
    """kappa and cosine broadcast to one shape, each C-contiguous in native
    float32 (from float16/float32) or float64 (from float64/integers): a copy
    only where the input is not already that."""
    (k, kt), (c, ct) = _real_array(kappa, "kappa"), _real_array(cosine, "cosine")
    try:
        k, c = _np.broadcast_arrays(k, c)
    except ValueError:
        raise InputError(f"kappa and cosine: shapes {k.shape} and {c.shape} do not broadcast "
                         "to one shape") from None
    return _np.asarray(k, dtype=kt, order="C"), _np.asarray(c, dtype=ct, order="C")


def _result(a):
    return a[()] if a.ndim == 0 else a


def irradiance(method, kappa, cosine, precision="float"):
    """Irradiance E(c, kappa) of a unit-amplitude SG light (axis v, sharpness
    kappa) on a Lambertian surface whose normal n has c = v.n, by one method
    of the runtime, element by element over kappa and cosine broadcast.

    precision "float": kappa and cosine rounded to float32, the runtime's float
    batch, a float32 result (bit for bit that of the C++ float path); "double":
    float64 throughout. Refused (InputError): an unknown method, a kappa that
    is not finite and >= 0, a cosine outside [-1, 1] or NaN, and in float a
    kappa above the largest float or rounding to 0 there."""
    k, c = _prepare(kappa, cosine)
    return _result(_sglab.irradiance(method, k, c, precision))


def irradiance_grad(method, kappa, cosine):
    """(E, dE/dkappa, dE/dcosine) of a method in double, as float64 arrays:
    E is the runtime's double value bit for bit, the derivatives those of the
    same C++ template (forward-mode automatic differentiation with Ceres
    Jets), exact up to rounding, not finite differences."""
    k, c = _prepare(kappa, cosine)
    return tuple(_result(a) for a in _sglab.irradiance_grad(method, k, c))


def reference(kappa, cosine, quantity="irradiance"):
    """The reference engine (Boost.Math quadrature, double) of
    docs/quantities.md: "irradiance" E(c, kappa), "hemispherical" H(c, kappa)
    or "normalized" s(c, kappa), as float64. In parallel over the points (about
    10 microseconds of one core each); memory bounded whatever their number."""
    k, c = _prepare(kappa, cosine)
    return _result(_sglab.reference(k.astype(_np.float64), c.astype(_np.float64), quantity))


def export(method, lang="glsl", precision="float", split=False):
    """The method as self-contained source, constants baked in, as `sglab
    export --lang LANG --method METHOD [--precision half] [--split]` writes it
    with the compiled-in constants (the header states no GPU cost or Vulkan
    error: those come from the checkout's result files, which the CLI reads)."""
    return _sglab.export(method, lang, precision, bool(split))
