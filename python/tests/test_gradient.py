"""sglab.irradiance_grad: exact derivatives of every method's double
template, against Richardson-extrapolated central differences of the same
method (truncation error O(h^4)) and against the derivatives of the exact
irradiance (central differences of the reference engine)."""

import numpy as np
import pytest

import sglab

# Points away from the kinks some methods have (max(c, 0) of punctual at c = 0).
K, C = np.broadcast_arrays(np.array([0.05, 0.7, 3.0, 25.0, 300.0])[:, None],
                           np.array([-0.7, -0.2, 0.15, 0.55, 0.93])[None, :])
METHOD_IDS = [m["id"] for m in sglab.methods()]


def richardson(f, x, h):
    """f'(x) from central differences at h and h/2, extrapolated."""
    d = lambda step: (f(x + step) - f(x - step)) / (2 * step)
    return (4 * d(h / 2) - d(h)) / 3


def scaled_error(got, expected):
    """max |got - expected| over the grid, each row (one kappa) divided by the
    largest |expected| of that row: derivatives span 130 orders of magnitude
    over c at kappa = 300."""
    scale = np.max(np.abs(expected), axis=1, keepdims=True)
    return np.max(np.abs(got - expected) / scale)


@pytest.mark.parametrize("method", METHOD_IDS)
def test_gradient_equals_central_differences(method):
    value, d_kappa, d_cosine = sglab.irradiance_grad(method, K, C)
    f = lambda k, c: sglab.irradiance(method, k, c, precision="double")
    np.testing.assert_array_equal(value, f(K, C))
    # Measured: at most 3.2e-8 (tokuyoshi2022, whose alpha(p - q) cancels), 3e-11 elsewhere.
    assert scaled_error(d_kappa, richardson(lambda k: f(k, C), K, 1e-3 * K)) < 1e-6
    assert scaled_error(d_cosine, richardson(lambda c: f(K, c), C, 1e-3)) < 1e-6


@pytest.mark.parametrize("method,bound", [("sglab_acc4", 1e-4), ("tokuyoshi2024", 1e-2)])
def test_gradient_near_the_exact_derivative(method, bound):
    # The exact E's derivatives, by differences of the reference engine (which
    # agree to 1e-11 between steps h and 2h); the model's derivative error is
    # its own (measured: acc4 2.9e-5 in kappa, 5.5e-5 in c; tokuyoshi2024
    # 1.8e-3 and 5.4e-3).
    _, d_kappa, d_cosine = sglab.irradiance_grad(method, K, C)
    assert scaled_error(d_kappa, richardson(lambda k: sglab.reference(k, C), K, 1e-3 * K)) < bound
    assert scaled_error(d_cosine, richardson(lambda c: sglab.reference(K, c), C, 1e-3)) < bound


def test_gradient_closed_form_of_punctual():
    # punctual: E = max(c, 0) * 2 pi / kappa, so dE/dkappa = -E/kappa and
    # dE/dc = 2 pi / kappa for c > 0, 0 for c < 0.
    value, d_kappa, d_cosine = sglab.irradiance_grad("punctual", K, C)
    np.testing.assert_allclose(d_kappa, -value / K, rtol=1e-15)
    np.testing.assert_allclose(d_cosine, np.where(C > 0, 2 * np.pi / K, 0.0), rtol=1e-15)


def test_gradient_refuses_what_irradiance_refuses():
    with pytest.raises(sglab.InputError, match=r"cosine must be in \[-1, 1\], got 1.5 \(at flat "
                                                r"index 0\)"):
        sglab.irradiance_grad("sglab_acc4", 1.0, 1.5)
    with pytest.raises(sglab.InputError, match="unknown irradiance method 'x'"):
        sglab.irradiance_grad("x", 1.0, 0.5)
