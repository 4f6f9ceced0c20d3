"""sglab.envmap against the `sglab envmap` command and closed forms."""

import json

import numpy as np
import pytest

import sglab
from conftest import ROOT, read_csv_column, run_cli

MAP = ROOT / "data" / "envmaps" / "city.exr"


def test_irradiance_equals_the_cli():
    out = run_cli("envmap", "irradiance", MAP, "--normals", 16).stdout
    normals = sglab.envmap.fibonacci_normals(16)
    np.testing.assert_array_equal(normals, np.stack([read_csv_column(out, x)
                                                     for x in ("nx", "ny", "nz")], axis=1))
    e = sglab.envmap.irradiance(str(MAP), normals)
    expected = np.stack([read_csv_column(out, ch) for ch in "rgb"], axis=1)
    np.testing.assert_array_equal(e, expected)
    # The same map given as an array, and normals of any length.
    m = sglab.envmap.load(MAP)
    assert (m.width, m.height) == (128, 64) and m.rgb.shape == (64, 128, 3)
    np.testing.assert_array_equal(sglab.envmap.irradiance(m.rgb, normals), expected)
    np.testing.assert_allclose(sglab.envmap.irradiance(m, 3 * normals), expected, rtol=1e-14)


def test_constant_map_gives_pi_times_the_radiance():
    # E(n) = L * integral of max(w.n, 0) dw = pi L for a constant map
    # (docs/envmaps.md: within 8.4e-7 relative at 128 x 64).
    rgb = np.broadcast_to(np.array([0.5, 1.0, 2.0], dtype=np.float32), (64, 128, 3))
    normals = np.array([[0, 0, 1], [1, 0, 0], [0.3, -0.4, 0.2], [0, 0, -1]])
    e = sglab.envmap.irradiance(rgb, normals)
    np.testing.assert_allclose(e, np.pi * np.array([[0.5, 1.0, 2.0]] * 4), rtol=1e-6)


def test_fit_equals_the_cli():
    cli = json.loads(run_cli("envmap", "fit", MAP, "--lobes", 2, "--json").stdout)
    fit = sglab.envmap.fit(MAP, 2)
    lights = cli["lights"]
    np.testing.assert_array_equal(fit["axis"], [l["axis"] for l in lights])
    np.testing.assert_array_equal(fit["sharpness"], [l["sharpness"] for l in lights])
    np.testing.assert_array_equal(fit["amplitude"], [l["amplitude"] for l in lights])
    assert fit["iterations"] == cli["provenance"]["ceres_iterations"]
    assert fit["converged"] == cli["provenance"]["converged"]


def test_lobes_irradiance_is_the_sum_of_reference_values():
    axis = np.array([[0, 0, 1.0], [0.6, 0.8, 0]])
    sharpness = np.array([3.0, 40.0])
    amplitude = np.array([[1.0, 2.0, 0.5], [0.25, 0.0, 4.0]])
    normals = sglab.envmap.fibonacci_normals(10)
    expected = sum(amplitude[k][None, :] *
                   sglab.reference(sharpness[k], np.clip(normals @ axis[k], -1, 1))[:, None]
                   for k in range(2))
    got = sglab.envmap.lobes_irradiance(axis, sharpness, amplitude, normals)
    # Each lobe's E comes from the irradiance table, exact to 1e-10 of its
    # peak E(1, kappa) (docs/quantities.md): the sum is exact to that per lobe.
    bound = sum(amplitude[k] * 1e-10 * sglab.reference(sharpness[k], 1.0) for k in range(2))
    assert np.all(np.abs(got - expected) <= bound[None, :])
    assert not np.array_equal(got, np.zeros_like(got))


def test_bad_maps_and_normals_raise_the_cli_messages(tmp_path):
    with pytest.raises(sglab.InputError, match=r"envmap array: .*2:1"):
        sglab.envmap.load(np.ones((64, 64, 3)))
    with pytest.raises(sglab.InputError, match=r"expected shape \(height, width, 3\)"):
        sglab.envmap.load(np.ones((64, 128)))
    bad = np.ones((64, 128, 3))
    bad[3, 5, 1] = np.nan
    with pytest.raises(sglab.InputError, match="envmap array"):
        sglab.envmap.load(bad)
    missing = tmp_path / "missing.exr"
    err = run_cli("envmap", "irradiance", missing, check=False)
    assert err.returncode == 2
    with pytest.raises(sglab.InputError) as info:
        sglab.envmap.load(missing)
    assert str(info.value) in err.stderr
    with pytest.raises(sglab.InputError, match=r"normals\[1\]: \(0, 0, 0\) is not a nonzero"):
        sglab.envmap.irradiance(MAP, [[0, 0, 1], [0, 0, 0]])
    with pytest.raises(sglab.InputError, match="lobes 0: at least one lobe is needed"):
        sglab.envmap.fit(MAP, 0)
