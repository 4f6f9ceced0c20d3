"""sglab.irradiance, sglab.reference and sglab.methods against the `sglab`
command of the same build (an independent path: the CLI evaluates each row
with the runtime's scalar f32/f64, the module its batch kernels), and the
handling of dtypes, layouts, broadcasting, bad input and the GIL."""

import json
import threading
import time

import numpy as np
import pytest

import sglab
from sglab import _sglab
from conftest import random_points, read_csv_column, run_cli, write_points

METHOD_IDS = [m["id"] for m in sglab.methods()]


def test_methods_match_the_cli():
    cli = json.loads(run_cli("methods", "--json").stdout)["irradiance"]
    assert [m["id"] for m in sglab.methods()] == [m["id"] for m in cli]
    for mine, theirs in zip(sglab.methods(), cli):
        assert mine["origin"] == theirs["origin"]
        assert mine["source"] == theirs["source"]
        assert mine["per_light_split"] == theirs["per_light_split"]
    assert {m["id"] for m in sglab.methods() if m["export_split"]} >= {"tokuyoshi2024",
                                                                       "sglab_acc4"}


# The methods whose float batch is a kernel of its own (include/sglab/registry.hpp:
# with_batch32, make_sglab_acc), which vectorizes with branch-free functions and
# so differs from the scalar f32 in the last bits.
FLOAT_KERNELS = {"tokuyoshi2024", "tokuyoshi2024_refit", "sglab_fast", "sglab_mid", "sglab_acc1",
                 "sglab_acc2", "sglab_acc3", "sglab_acc4"}


@pytest.mark.parametrize("precision", ["float", "double"])
def test_values_equal_the_cli_bit_for_bit(tmp_path, precision):
    kappa, cosine = random_points(200)
    points = tmp_path / "points.csv"
    write_points(points, kappa, cosine)
    dtype = np.float32 if precision == "float" else np.float64
    assert FLOAT_KERNELS < set(METHOD_IDS)
    for method in METHOD_IDS:
        out = run_cli("eval", "--method", method, "--points", points, "--precision",
                      precision).stdout
        # %.9g round-trips a float exactly, %.17g a double.
        expected = read_csv_column(out, "value").astype(dtype)
        got = sglab.irradiance(method, kappa, cosine, precision=precision)
        assert got.dtype == dtype
        if precision == "float" and method in FLOAT_KERNELS:
            # The C++ float batch itself, on the float-rounded inputs; and the
            # CLI's scalar f32 within 2e-6 of E(1, kappa) (measured 1.7e-6).
            np.testing.assert_array_equal(
                got, _sglab._batch32(method, kappa.astype(np.float32), cosine.astype(np.float32)))
            peak = sglab.irradiance(method, kappa, 1.0, precision="double")
            assert np.max(np.abs(got.astype(np.float64) - expected) / peak) < 2e-6, method
        else:
            np.testing.assert_array_equal(got, expected, err_msg=method)


def test_reference_equals_the_cli(tmp_path):
    kappa, cosine = random_points(20)
    points = tmp_path / "points.csv"
    write_points(points, kappa, cosine)
    out = run_cli("reference", "--points", points).stdout
    for quantity in ("irradiance", "hemispherical", "normalized"):
        np.testing.assert_array_equal(sglab.reference(kappa, cosine, quantity=quantity),
                                      read_csv_column(out, quantity), err_msg=quantity)


def test_reference_across_chunks():
    # More points than one chunk of the engine (65536), cache emptied between
    # chunks: every point still gets its own value.
    unique_k = np.array([0.5, 3.0, 40.0])
    unique_c = np.array([-0.5, 0.25, 0.9])
    idx = np.arange(65536 + 7)
    kappa, cosine = unique_k[idx % 3], unique_c[(idx // 3) % 3]
    got = sglab.reference(kappa, cosine)
    grid = sglab.reference(unique_k[:, None], unique_c[None, :])
    np.testing.assert_array_equal(got, grid[idx % 3, (idx // 3) % 3])


def test_broadcasting_scalars_and_shapes():
    kappa = np.array([[0.1], [2.0], [30.0]])
    cosine = np.linspace(-1, 1, 5)
    got = sglab.irradiance("sglab_acc4", kappa, cosine)
    assert got.shape == (3, 5)
    for i in range(3):
        for j in range(5):
            assert got[i, j] == sglab.irradiance("sglab_acc4", kappa[i, 0], cosine[j])
    scalar = sglab.irradiance("sglab_acc4", 4.0, 0.5)
    assert np.ndim(scalar) == 0 and isinstance(scalar, np.float32)
    assert sglab.irradiance("sglab_acc4", [], []).shape == (0,)


def test_dtypes_and_layouts_give_the_same_values():
    rng = np.random.default_rng(1)
    base_k = np.ascontiguousarray(10 ** rng.uniform(-2, 3, (6, 8)))
    base_c = np.ascontiguousarray(rng.uniform(-1, 1, (6, 8)))
    expected = sglab.irradiance("tokuyoshi2024", base_k, base_c, precision="double")
    variants = {
        "fortran": (np.asfortranarray(base_k), np.asfortranarray(base_c)),
        "strided": (np.repeat(base_k, 2, axis=1)[:, ::2], np.repeat(base_c, 2, axis=1)[:, ::2]),
        "transposed": (base_k.T.copy().T, base_c.T.copy().T),
        "big-endian": (base_k.astype(">f8"), base_c.astype(">f8")),
        "lists": (base_k.tolist(), base_c.tolist()),
    }
    for name, (k, c) in variants.items():
        got = sglab.irradiance("tokuyoshi2024", k, c, precision="double")
        np.testing.assert_array_equal(got, expected, err_msg=name)
    # float16 and float32 inputs: the same as their values in float64.
    for dtype in (np.float16, np.float32):
        k, c = base_k.astype(dtype), base_c.astype(dtype)
        np.testing.assert_array_equal(
            sglab.irradiance("tokuyoshi2024", k, c, precision="double"),
            sglab.irradiance("tokuyoshi2024", k.astype(np.float64), c.astype(np.float64),
                             precision="double"), err_msg=str(dtype))
    # integers are numbers too
    assert sglab.irradiance("hill", 2, 1) == sglab.irradiance("hill", 2.0, 1.0)


@pytest.mark.parametrize("bad", [np.array([1 + 1j]), np.array([True]), np.array(["1"]),
                                 np.array([1.0], dtype=np.longdouble), np.array([object()])])
def test_other_dtypes_are_refused(bad):
    with pytest.raises(TypeError, match=r"kappa: expected real numbers.*got an array of dtype"):
        sglab.irradiance("hill", bad, 0.5)


def cli_message(tmp_path, kappa, cosine, precision="float"):
    """The CLI's message for one bad row, without its `file:line: ` prefix and
    the quoted line."""
    points = tmp_path / "bad.csv"
    points.write_text(f"kappa,cosine\n{kappa},{cosine}\n")
    err = run_cli("eval", "--method", "hill", "--points", points, "--precision", precision,
                  check=False)
    assert err.returncode == 2
    message = err.stderr.strip().split(f"{points}:2: ", 1)[1]
    return message.rsplit(" (line: ", 1)[0]


@pytest.mark.parametrize("kappa,cosine,precision", [
    ("-1", "0.5", "float"), ("nan", "0.5", "double"), ("inf", "0", "double"),
    ("2", "1.5", "float"), ("2", "nan", "double"), ("1e39", "0", "float"),
    ("1e-50", "0", "float")])
def test_bad_points_raise_the_cli_message(tmp_path, kappa, cosine, precision):
    expected = cli_message(tmp_path, kappa, cosine, precision)
    k = np.array([1.0, 2.0, float(kappa)])
    c = np.array([0.0, 0.5, float(cosine)])
    with pytest.raises(sglab.InputError) as info:
        sglab.irradiance("hill", k, c, precision=precision)
    assert str(info.value) == f"{expected} (at flat index 2)"


def test_double_takes_what_float_refuses():
    assert sglab.irradiance("hill", 1e39, 0.0, precision="double") > 0
    assert np.isfinite(sglab.irradiance("hill", 1e-50, 0.0, precision="double"))


def test_bad_names_and_shapes_raise():
    with pytest.raises(sglab.InputError, match=r"^unknown irradiance method 'nope' \(known: "
                                                r"wang2009, .*sglab_acc4\)$"):
        sglab.irradiance("nope", 1.0, 0.5)
    with pytest.raises(sglab.InputError, match="precision must be float or double; got 'half'"):
        sglab.irradiance("hill", 1.0, 0.5, precision="half")
    with pytest.raises(sglab.InputError, match=r"kappa and cosine: shapes \(3,\) and \(4,\) do "
                                                r"not broadcast"):
        sglab.irradiance("hill", np.ones(3), np.zeros(4))
    with pytest.raises(sglab.InputError, match="quantity must be irradiance, hemispherical or "
                                                "normalized; got 'x'"):
        sglab.reference(1.0, 0.5, quantity="x")
    assert issubclass(sglab.InputError, ValueError)


def test_batch_work_releases_the_gil():
    # While another thread is inside sglab.reference (0.1 to 0.3 s of
    # quadrature here), this thread keeps running Python code: the longest
    # pause between two of its steps is far below the call's duration. A call
    # holding the GIL would stop it for the whole call.
    kappa = np.full(30000, 7.0) + np.arange(30000) * 1e-3
    started, done = threading.Event(), threading.Event()
    duration = []

    def work():
        started.set()
        t0 = time.perf_counter()
        sglab.reference(kappa, 0.3)
        duration.append(time.perf_counter() - t0)
        done.set()

    t = threading.Thread(target=work)
    t.start()
    started.wait()
    longest, last = 0.0, time.perf_counter()
    while not done.is_set():
        now = time.perf_counter()
        longest, last = max(longest, now - last), now
    t.join()
    assert duration[0] > 0.05
    assert longest < duration[0] / 3, (longest, duration[0])
