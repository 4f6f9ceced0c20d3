"""sglab.torch: the autograd function, torch.autograd.gradcheck in double, and
a small inverse-rendering problem solved by gradient descent through it."""

import importlib.util
import subprocess
import sys

import numpy as np
import pytest

import sglab

torch = pytest.importorskip(
    "torch", reason="PyTorch is not installed (Debian: apt-get install python3-torch; "
                    "scripts/deps.sh and .ci/run install it)")
import sglab.torch as sgt  # noqa: E402


def test_sglab_imports_without_torch():
    # A fresh interpreter where `import torch` fails: `import sglab` works,
    # `import sglab.torch` says why it cannot.
    code = ("import sys; sys.modules['torch'] = None\n"
            "import sglab; assert 'torch' not in sys.modules or sys.modules['torch'] is None\n"
            "print(sglab.irradiance('hill', 1.0, 0.5))\n"
            "try:\n    import sglab.torch\nexcept ImportError as e:\n    print('ImportError')\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split()[-1] == "ImportError"


@pytest.mark.parametrize("dtype,precision", [(torch.float32, "float"),
                                             (torch.float64, "double")])
def test_forward_is_sglab_irradiance(dtype, precision):
    kappa = torch.logspace(-2, 3, 40, dtype=dtype)
    cosine = torch.linspace(-1, 1, 40, dtype=dtype)
    e = sgt.irradiance("sglab_acc4", kappa, cosine)
    assert e.dtype == dtype
    np.testing.assert_array_equal(
        e.numpy(), sglab.irradiance("sglab_acc4", kappa.numpy(), cosine.numpy(), precision))


@pytest.mark.parametrize("method", ["sglab_acc4", "tokuyoshi2024", "sglab_fast", "wang2009"])
def test_gradcheck_in_double(method):
    g = torch.Generator().manual_seed(7)
    kappa = (10 ** (torch.rand(12, dtype=torch.float64, generator=g) * 3 - 1)).requires_grad_()
    cosine = (torch.rand(12, dtype=torch.float64, generator=g) * 1.8 - 0.9).requires_grad_()
    assert torch.autograd.gradcheck(lambda k, c: sgt.irradiance(method, k, c), (kappa, cosine),
                                    eps=1e-6, atol=1e-8, rtol=1e-5)


def test_gradients_reduce_over_broadcast_dimensions():
    kappa = torch.tensor([4.0], dtype=torch.float64, requires_grad=True)
    cosine = torch.linspace(-0.9, 0.9, 7, dtype=torch.float64, requires_grad=True)
    sgt.irradiance("sglab_acc4", kappa, cosine).sum().backward()
    _, dk, dc = sglab.irradiance_grad("sglab_acc4", 4.0, cosine.detach().numpy())
    assert kappa.grad.shape == (1,)
    np.testing.assert_allclose(kappa.grad.numpy(), [dk.sum()], rtol=1e-14)
    np.testing.assert_array_equal(cosine.grad.numpy(), dc)


def test_float32_gradients():
    kappa = torch.tensor([0.5, 8.0, 60.0], requires_grad=True)
    cosine = torch.tensor([0.3, -0.2, 0.9], requires_grad=True)
    sgt.irradiance("tokuyoshi2024", kappa, cosine).sum().backward()
    assert kappa.grad.dtype == torch.float32
    _, dk, dc = sglab.irradiance_grad("tokuyoshi2024", kappa.detach().numpy(),
                                      cosine.detach().numpy())
    np.testing.assert_array_equal(kappa.grad.numpy(), dk.astype(np.float32))
    np.testing.assert_array_equal(cosine.grad.numpy(), dc.astype(np.float32))


def test_bad_tensors_are_refused():
    with pytest.raises(TypeError, match="kappa: expected a float32 or float64 tensor, got "
                                        "torch.int64"):
        sgt.irradiance("sglab_acc4", torch.tensor([1]), torch.tensor([0.5]))
    with pytest.raises(TypeError, match="one dtype please"):
        sgt.irradiance("sglab_acc4", torch.tensor([1.0]), torch.tensor([0.5],
                                                                        dtype=torch.float64))
    with pytest.raises(sglab.InputError, match=r"cosine must be in \[-1, 1\]"):
        sgt.irradiance("sglab_acc4", torch.tensor([1.0]), torch.tensor([1.5]))


def test_inverse_rendering_recovers_one_sg_light():
    # One SG light (axis v, sharpness kappa, amplitude 1); its exact irradiance
    # at 64 Fibonacci normals (reference engine). From a start 0.5 rad and a
    # factor 2.7 in kappa away, Adam on (unnormalized axis, log kappa) through
    # sglab.torch with sglab_acc4 recovers both.
    normals = torch.from_numpy(sglab.envmap.fibonacci_normals(64))
    true_axis = torch.tensor([0.3, -0.5, 0.81], dtype=torch.float64)
    true_axis = true_axis / true_axis.norm()
    true_kappa = 12.0
    target = torch.from_numpy(
        sglab.reference(true_kappa, (normals @ true_axis).clamp(-1, 1).numpy()))

    axis = torch.tensor([0.7, -0.3, 0.65], dtype=torch.float64, requires_grad=True)
    log_kappa = torch.tensor(np.log(true_kappa / 2.7), dtype=torch.float64, requires_grad=True)
    opt = torch.optim.Adam([axis, log_kappa], lr=0.05)
    for _ in range(400):
        opt.zero_grad()
        cosine = (normals @ (axis / axis.norm())).clamp(-1, 1)
        e = sgt.irradiance("sglab_acc4", log_kappa.exp().expand(64), cosine)
        loss = ((e - target) ** 2).mean()
        loss.backward()
        opt.step()
    found = (axis / axis.norm()).detach()
    angle = torch.arccos((found @ true_axis).clamp(-1, 1)).item()
    assert angle < 1e-3, angle
    assert abs(log_kappa.exp().item() / true_kappa - 1) < 1e-3, log_kappa.exp().item()
