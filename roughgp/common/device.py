r"""Where torch computes: the ``device=`` argument of the calls that outgrow a small machine.

Beyond the paper. The same calls that run on the CPU with numpy and scipy run through torch
on another device (a CUDA GPU) when given ``device=``:

* :func:`roughgp.sampling.sample_grid` (and the surfaces of :mod:`roughgp.models.surfaces`): the
  circulant FFTs, the dense Cholesky factorisation and the Lanczos iterations (eq 10);
* :func:`roughgp.inference.posterior.grid_likelihood` and :func:`roughgp.inference.posterior.ground_patch_model`:
  the dense marginal likelihood of a surface patch (eq 12), so maximum-likelihood or MCMC
  fits of eq 18 to patches far beyond :data:`roughgp.inference.posterior.MAX_GRID_POINTS`;
* :func:`roughgp.gp.toeplitz.toeplitz_log_likelihood` and
  :func:`roughgp.inference.fitting.fit_spectral_mixture` (section 3.3): a profile's likelihood and
  gradient by a dense Cholesky factorisation on the device instead of the :math:`O(n^2)`
  recursion on the CPU (the same numbers; on a GPU the faster route for the paper's profile
  lengths, while the optimiser itself stays on the CPU);
* :func:`roughgp.filling.global_fill.fill_gaps`: the FFT products and the batched conjugate
  gradients.

``device=None`` (the default) keeps the numpy path; ``"cpu"`` runs the torch path on the
CPU (what the tests check against the numpy path on a machine without GPU); ``"cuda"`` or
``"cuda:1"`` a GPU. Results always come back as numpy arrays, in float64 unless a call's
``dtype`` says otherwise.

Random draws on a device come from a ``torch.Generator`` on that device, seeded from the
call's numpy ``seed``: the same seed gives the same array on the same kind of device;
numpy, torch-CPU and CUDA streams differ (same distribution, different numbers). Where a
call draws little noise against its work (dense Cholesky and Lanczos draws) the noise is
drawn by numpy as on the CPU, so those draws agree with ``device=None`` to rounding.

torch is imported by the functions here when they need it, not with the module: the numpy
path (``device=None``) never imports it, so a command that draws on the CPU starts without
torch's seconds of import (issue 32).

``benchmarks/device.py`` measures every path side by side; ``tests/test_device.py`` checks
them against numpy (on CUDA too, where torch sees a GPU).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from roughgp.common.memory import host_free_bytes

if TYPE_CHECKING:  # the annotations' torch; the functions import it when they run
    import torch

__all__ = ["resolve", "generator", "free_bytes", "check_memory", "available",
           "synchronize", "gaussian_log_density"]


def resolve(device, name: str = "device") -> torch.device | None:
    """``device`` as a ``torch.device`` (None stays None: the numpy path).

    Raises a ``ValueError`` naming ``name`` for a string torch cannot parse or a device this
    machine does not have (e.g. ``"cuda"`` without a GPU, or ``"cuda:3"`` with two).
    """
    if device is None:
        return None
    import torch

    if not isinstance(device, (str, torch.device)):
        raise ValueError(f"{name} must be None, a string such as 'cpu' or 'cuda', or a "
                         f"torch.device, got {device!r}")
    try:
        device = torch.device(device)
    except RuntimeError:
        raise ValueError(f"{name} must be None, 'cpu', 'cuda' or 'cuda:N', got "
                         f"{device!r}") from None
    if device.type == "cuda":
        count = torch.cuda.device_count() if torch.cuda.is_available() else 0
        if count == 0:
            raise ValueError(f"{name}={str(device)!r} but torch sees no CUDA device (torch "
                             f"{torch.__version__}); leave the device out (numpy) or use 'cpu'")
        index = 0 if device.index is None else device.index
        if index >= count:
            raise ValueError(f"{name}={str(device)!r} but only {count} CUDA device(s) exist "
                             f"(allowed: cuda:0 .. cuda:{count - 1})")
        return torch.device("cuda", index)
    if device.type != "cpu":
        raise ValueError(f"{name} must be None, 'cpu', 'cuda' or 'cuda:N', got "
                         f"{str(device)!r}")
    return device


def generator(rng: np.random.Generator, device: torch.device) -> torch.Generator:
    """A torch generator on ``device`` seeded by one draw of the numpy ``rng`` (so a numpy
    seed fixes the device stream, and a shared ``rng`` still advances)."""
    import torch

    gen = torch.Generator(device=device)
    gen.manual_seed(int(rng.integers(0, 2**63 - 1)))
    return gen


def free_bytes(device: torch.device) -> int:
    """Memory free for new arrays on ``device`` (the CPU: available physical memory)."""
    if device.type == "cuda":
        import torch

        free, _ = torch.cuda.mem_get_info(device)
        return int(free)
    return host_free_bytes()


def check_memory(needed: int, device: torch.device, what: str) -> None:
    """Raise a ``ValueError`` before allocating when ``needed`` bytes exceed 80 % of what is
    free on ``device``; ``what`` names the array in the message."""
    free = free_bytes(device)
    if needed > 0.8 * free:
        raise ValueError(f"{what} needs about {needed / 2**30:.1f} GiB on {device}, but only "
                         f"{free / 2**30:.1f} GiB are free; use a smaller grid or another "
                         f"method")


def available() -> list[str]:
    """The devices this machine can use: ``["cpu"]``, plus ``"cuda"`` where torch sees a GPU."""
    import torch

    return ["cpu"] + (["cuda"] if torch.cuda.is_available() else [])


def gaussian_log_density(covariance: torch.Tensor, y: torch.Tensor) -> torch.Tensor:
    """log N(y | 0, covariance) by a Cholesky factor where the tensors lie (eq 12), as a torch
    scalar (differentiable); ``np.linalg.LinAlgError`` where the covariance is not positive
    definite."""
    import torch

    factor, failed = torch.linalg.cholesky_ex(covariance)
    if int(failed):
        raise np.linalg.LinAlgError("covariance not positive definite (Cholesky failed)")
    alpha = torch.cholesky_solve(y[:, None], factor)[:, 0]
    return (-0.5 * (y @ alpha) - torch.log(factor.diagonal()).sum()
            - 0.5 * y.numel() * math.log(2.0 * math.pi))


def synchronize(device: torch.device | None) -> None:
    """Wait for the device's queued work (for timings; a no-op off CUDA)."""
    if device is not None and device.type == "cuda":
        import torch

        torch.cuda.synchronize(device)
