"""sglab's irradiance methods as a PyTorch autograd function (CPU tensors,
float32 and float64): the forward pass is sglab.irradiance (float32 tensors:
the runtime's float path; float64: its double path), the backward pass the
exact derivatives of sglab.irradiance_grad (the double template), so an
SG-lighting optimizer gets sglab_acc4's or tokuyoshi2024's true gradient.
Importing sglab does not import torch; importing sglab.torch does."""

import torch as _torch

from . import irradiance as _irradiance, irradiance_grad as _irradiance_grad

_PRECISION = {_torch.float32: "float", _torch.float64: "double"}


def _check(t, name):
    if not isinstance(t, _torch.Tensor):
        raise TypeError(f"{name}: expected a torch.Tensor, got {type(t).__name__}")
    if t.device.type != "cpu":
        raise ValueError(f"{name}: sglab.torch runs on CPU tensors; got one on {t.device}")
    if t.dtype not in _PRECISION:
        raise TypeError(f"{name}: expected a float32 or float64 tensor, got {t.dtype}")


class Irradiance(_torch.autograd.Function):
    """E(kappa, cosine) of one method; see irradiance()."""

    @staticmethod
    def forward(ctx, method, kappa, cosine):
        _check(kappa, "kappa")
        _check(cosine, "cosine")
        if kappa.dtype != cosine.dtype:
            raise TypeError(f"kappa and cosine: one dtype please, got {kappa.dtype} and "
                            f"{cosine.dtype}")
        precision = _PRECISION[kappa.dtype]
        value = _irradiance(method, kappa.detach().numpy(), cosine.detach().numpy(), precision)
        ctx.method = method
        ctx.save_for_backward(kappa, cosine)
        return _torch.as_tensor(value, dtype=kappa.dtype)

    @staticmethod
    def backward(ctx, grad):
        kappa, cosine = ctx.saved_tensors
        _, d_kappa, d_cosine = _irradiance_grad(ctx.method, kappa.detach().numpy(),
                                                cosine.detach().numpy())
        g_kappa = g_cosine = None
        if ctx.needs_input_grad[1]:
            g_kappa = (grad * _torch.as_tensor(d_kappa, dtype=grad.dtype)).sum_to_size(kappa.shape)
        if ctx.needs_input_grad[2]:
            g_cosine = (grad * _torch.as_tensor(d_cosine, dtype=grad.dtype)).sum_to_size(
                cosine.shape)
        return None, g_kappa, g_cosine


def irradiance(method, kappa, cosine):
    """sglab.irradiance(method, kappa, cosine) on tensors, differentiable in
    kappa and cosine (broadcast against each other). A cosine computed as a dot
    product of unit vectors may round just outside [-1, 1], which is refused:
    clamp it (cosine.clamp(-1, 1))."""
    return Irradiance.apply(method, kappa, cosine)
