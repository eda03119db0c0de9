"""The Gaussian/Bernoulli output head shared by the learned state models (torch).

Why: the learned state models must put their surprise in the same observation space as the
references (``voe.models.statelik``): per slot, presence, shape, and a diagonal Gaussian over the
nine continuous features. The flat MLP emits ``OUT = 17`` numbers per slot (the interaction
network extends this head, see ``voe.models.interaction.RolloutHead``):

    0      presence logit for t+1
    1-6    mean correction of (x, y, angle, vx, vy, omega)
    7-15   log-variance of the nine features (bounded to [-14, 5])
    16     shape logit (circle)

The mean is ``c + g * (guess - c) + correction`` (see ``StateHead``). The gates ``g`` and the
networks' last layers start at zero, so an *untrained* model predicts the same
distribution for every object whatever it saw: a frame-only scorer, which ties exactly on spliced
matched sets (chance). Whatever a trained model knows, even "things keep moving", it learned. Never-seen slots go through the same head (their inputs are
zero and flagged unknown), so appearing and tracked objects are not treated differently by design.
"""

from __future__ import annotations

import math

import torch
from torch import nn

from voe.models.statelik import QUANTUM, RANGE

OUT = 17
LOG2PI = math.log(2 * math.pi)
DELTA_SCALE = (0.1, 0.1, 0.1, 1.0, 1.0, 1.0)
W0 = 20.0  # outlier-weight logit at initialisation: an untrained model is uniform to ~1e-7 nats
#: Presence logit at initialisation: with it an absent slot costs exactly what a present slot
#: costs under the uniform component (log 2 for the shape plus the log number of cells), so an
#: untrained model is uniform over the whole slot observation space, absence included.
C0 = math.log(2) + sum(math.log((b - a) / q) for (a, b), q in zip(RANGE, QUANTUM, strict=True))
TYPICAL = (5.0, 3.0, 0.0, 0.0, 0.0, 0.0, 0.9, 0.9, 0.8)


class StateHead(nn.Module):
    """Per-feature gates from the remembered state to the predicted mean, starting closed.

    ``mean_f = c_f + g_f * (guess_f - c_f)`` where ``guess`` is the constant-velocity guess for
    the dynamic features and the remembered value for the look, and ``g = GAIN * theta`` with
    ``theta`` zero at initialisation (``GAIN`` lets Adam open a gate in ~100 steps).
    """

    GAIN = 5.0

    def __init__(self) -> None:
        super().__init__()
        self.outlier_theta = nn.Parameter(torch.zeros(()))  # w = sigmoid(W0 - 20 theta)
        self.presence_phi = nn.Parameter(torch.zeros(()))  # presence bias = C0 - 100 phi
        self.c = nn.Parameter(torch.tensor(TYPICAL))
        self.theta = nn.Parameter(torch.zeros(9))
        self.shape_gain = nn.Parameter(torch.zeros(()))

    def randomize(self, gen: torch.Generator) -> None:
        """A random outlier weight and presence bias (for random-network validity controls): the
        Gaussian gets about half the mixture, so the network's random output matters. The gates
        ``theta`` and ``shape_gain`` stay closed: opened, they would route the constant-velocity
        guess and the remembered shape into the prediction, which is knowledge (inertia, shape
        constancy), not a random function."""
        with torch.no_grad():
            self.outlier_theta.copy_(1.0 + 0.05 * torch.randn((), generator=gen))
            self.presence_phi.copy_(0.01 * torch.randn((), generator=gen))

    def presence_bias(self) -> torch.Tensor:
        return C0 - 100.0 * self.presence_phi

    def log_outlier(self) -> tuple[torch.Tensor, torch.Tensor]:
        """``log w`` and ``log(1 - w)`` of the uniform outlier component."""
        z = W0 - 20.0 * self.outlier_theta
        return nn.functional.logsigmoid(z), nn.functional.logsigmoid(-z)

    def mean(self, base: torch.Tensor, mem: torch.Tensor) -> torch.Tensor:
        # base, mem: (B, T, K, 9) -> (B, T, K, 9)
        guess = torch.cat([base[..., :6], mem[..., 6:]], -1)
        c = self.c.to(base.dtype)
        return c + self.GAIN * self.theta.to(base.dtype) * (guess - c)


def bounded_logvar(raw: torch.Tensor) -> torch.Tensor:
    return -4.5 + 9.5 * torch.tanh(raw / 9.5)


def uniform_logp(r: torch.Tensor, obs: torch.Tensor) -> torch.Tensor:
    """Per feature ``log P(cell)`` under ``Uniform(RANGE)`` (twin of ``statelik.uniform_logp``)."""
    lo, hi = r.new_tensor([a for a, _ in RANGE]), r.new_tensor([b for _, b in RANGE])
    v = torch.cat([obs[..., :2], r[..., 2:3], obs[..., 3:]], -1)  # angle: its residual
    inside = (v >= lo) & (v <= hi)
    return torch.where(inside, torch.log(r.new_tensor(QUANTUM) / (hi - lo)), torch.full_like(v, -1e4))


def cell_nll(r: torch.Tensor, logvar: torch.Tensor, obs: torch.Tensor, head: StateHead) -> torch.Tensor:
    """``-log P(cell)`` per feature under ``(1 - w) N(mu, exp(logvar)) + w Uniform(RANGE)``.

    In training mode the value is the same, but the Gaussian's parameters get the gradient of
    the Gaussian's own likelihood and only ``w`` gets the mixture's: with the mixture's gradient,
    rare and informative residuals (contacts, bounces) would be written off as outliers and teach
    the Gaussian nothing, and at initialisation (``w`` close to 1) the Gaussian would learn nothing.
    """
    narrow = _cell_logp(r, torch.exp(0.5 * logvar))  # (..., 9)
    unif = uniform_logp(r, obs)
    log_w, log_1w = head.log_outlier()
    mix = torch.logaddexp(log_1w + narrow, log_w + unif)
    if head.training:
        pure = torch.logaddexp(math.log1p(-1e-8) + narrow, math.log(1e-8) + unif)
        mix_w = torch.logaddexp(log_1w + narrow.detach(), log_w + unif)
        mix = pure + (mix_w - pure.detach())
    return -torch.clamp(mix, max=0.0)


def _cell_logp(r: torch.Tensor, sd: torch.Tensor) -> torch.Tensor:
    q = r.new_tensor(QUANTUM)
    logvar = 2 * torch.log(sd)
    # far tails (|z| > 40) are uniform-dominated anyway; the clamp keeps log_ndtr's gradient finite
    lo, hi = ((r - q / 2) / sd).clamp(-40, 40), ((r + q / 2) / sd).clamp(-40, 40)
    flip = lo > 0
    lo, hi = torch.where(flip, -hi, lo), torch.where(flip, -lo, hi)
    lh, ll = torch.special.log_ndtr(hi), torch.special.log_ndtr(lo)
    d = torch.clamp(ll - lh, max=-1e-6)
    exact = lh + torch.log(-torch.expm1(d))
    dens = -0.5 * (r * r * torch.exp(-logvar) + logvar + LOG2PI) + torch.log(q)
    return torch.clamp(torch.where(ll - lh > -1e-6, dens, exact), max=0.0)


def state_nll(out: torch.Tensor, head: StateHead, d: dict[str, torch.Tensor]) -> torch.Tensor:
    """Surprise of frame t+1 given the head output at t.

    Args:
        out: ``(B, T-1, K, OUT)`` network output from inputs at t = 0..T-2.
        d: tensors from ``voe.models.features.slot_features`` (as torch), length T.

    Returns:
        ``(B, T)`` with frame 0 set to 0 (the caller masks warm-up).
    """
    if not head.training:  # score in float64: an untrained model's equal costs stay equal
        out = out.double()
        d = {k: v.double() if v.is_floating_point() else v for k, v in d.items()}
    known, pres = d["known"][:, :-1], d["present"][:, 1:]  # (B, T-1, K) at t and t+1
    base, mem, obs = d["base"][:, :-1], d["mem"][:, :-1], d["obs"][:, 1:]  # (B, T-1, K, 9)
    scale = out.new_tensor(DELTA_SCALE)
    mean = head.mean(base, mem)
    mean = torch.cat([mean[..., :6] + scale * out[..., 1:7], mean[..., 6:]], -1)
    logvar = bounded_logvar(out[..., 7:16])
    r = obs - mean
    r = torch.cat([r[..., :2], torch.remainder(r[..., 2:3] + math.pi, 2 * math.pi) - math.pi, r[..., 3:]], -1)
    gauss = cell_nll(r, logvar, obs, head).sum(-1)  # (B, T-1, K)
    circ_mem = d["circle"][:, :-1].to(out.dtype) * known.to(out.dtype)
    shape_logit = out[..., 16] + head.shape_gain * (2 * circ_mem - 1) * known.to(out.dtype)
    shape = nn.functional.binary_cross_entropy_with_logits(shape_logit, d["circle"][:, 1:].to(out.dtype),
                                                           reduction="none")
    presence = nn.functional.binary_cross_entropy_with_logits(out[..., 0] + head.presence_bias(),
                                                              pres.to(out.dtype), reduction="none")
    per_slot = presence + torch.where(pres, gauss + shape, torch.zeros_like(gauss))
    frame = per_slot.sum(-1)  # (B, T-1)
    return torch.cat([torch.zeros_like(frame[:, :1]), frame], 1)  # (B, T)
