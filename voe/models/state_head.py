"""The Gaussian/Bernoulli output head shared by the learned state models (torch).

Why: the learned state models must put their surprise in the same observation space as the
references (``voe.models.statelik``): per slot, presence, shape, and a diagonal Gaussian over the
nine continuous features, mixed with a uniform outlier component. What predicts the mean and the
variance differs per model (``voe.models.rollout_heads`` for the interaction networks,
``voe.models.mlp`` for the flat window model); the outlier weight, the presence bias, the cell
likelihood and its training-mode gradient are shared here.

The networks' last layers start at zero and the outlier weight at ~1, so an *untrained* model
predicts the same distribution for every object whatever it saw: a constant, which ties exactly
on matched sets. The random-network controls (``voe.controls.random_nets``) draw every such
parameter at random instead.
"""

from __future__ import annotations

import math

import torch
from torch import nn

from voe.models.slot_rollout import wrap
from voe.models.statelik import QUANTUM, RANGE

LOG2PI = math.log(2 * math.pi)
DELTA_SCALE = (0.1, 0.1, 0.1, 1.0, 1.0, 1.0)
W0 = 20.0  # outlier-weight logit at initialisation: an untrained model is uniform to ~1e-7 nats
#: Presence logit at initialisation: with it an absent slot costs exactly what a present slot
#: costs under the uniform component (log 2 for the shape plus the log number of cells), so an
#: untrained model is uniform over the whole slot observation space, absence included.
C0 = math.log(2) + sum(math.log((b - a) / q) for (a, b), q in zip(RANGE, QUANTUM, strict=True))
TYPICAL = (5.0, 3.0, 0.0, 0.0, 0.0, 0.0, 0.9, 0.9, 0.8)


class StateHead(nn.Module):
    """The outlier weight and presence bias every learned state model's surprise goes through.

    The outlier weight starts at ``w ~ 1`` (``W0``) and the presence bias at ``C0``: an untrained
    model is uniform over the slot observation space whatever its network computes.
    """

    #: ``None``, or the fixed width (velocity units) of the training-only teacher of the velocity
    #: mean (``voe.models.interaction.velocity_teacher``)
    TEACH_SD: float | None = None
    #: teach also the steps of a rolled-out (not fed) slot whose next frame is observed, at width
    #: ``TEACH_SD * sqrt(n)`` after n steps from its last fed state (``interaction_teacher``, v9h)
    TEACH_HIDDEN: bool = False

    def __init__(self) -> None:
        super().__init__()
        self.outlier_theta = nn.Parameter(torch.zeros(()))  # w = sigmoid(W0 - 20 theta)
        self.presence_phi = nn.Parameter(torch.zeros(()))  # presence bias = C0 - 100 phi

    def randomize(self, gen: torch.Generator) -> None:
        """A random outlier weight and presence bias (for random-network validity controls): the
        Gaussian gets about half the mixture, so the network's random output matters."""
        with torch.no_grad():
            self.outlier_theta.copy_(1.0 + 0.05 * torch.randn((), generator=gen))
            self.presence_phi.copy_(0.01 * torch.randn((), generator=gen))

    def presence_bias(self) -> torch.Tensor:
        return C0 - 100.0 * self.presence_phi

    def log_outlier(self) -> tuple[torch.Tensor, torch.Tensor]:
        """``log w`` and ``log(1 - w)`` of the uniform outlier component."""
        z = W0 - 20.0 * self.outlier_theta
        return nn.functional.logsigmoid(z), nn.functional.logsigmoid(-z)


def uniform_like(lo: torch.Tensor, hi: torch.Tensor, gen: torch.Generator) -> torch.Tensor:
    """``U(lo, hi)`` elementwise (the random-network controls' draw of a bounded parameter)."""
    return lo + (hi - lo) * torch.rand(lo.shape, generator=gen, dtype=lo.dtype)


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


def frame_cost(head: StateHead, mean: torch.Tensor, logvar: torch.Tensor, p_logit: torch.Tensor,
               s_logit: torch.Tensor, obs: torch.Tensor, pres: torch.Tensor, circ: torch.Tensor) -> torch.Tensor:
    """``-log P(frame)``: per slot, presence, and shape and the nine cells where present, summed
    over slots.

    Why here: every learned state model (the interaction networks' rollout and the flat window
    model) scores a frame the same way; only how it predicts ``mean`` and ``logvar`` differs.

    Args:
        mean, logvar, obs: ``(..., K, 9)``; p_logit, s_logit, pres, circ: ``(..., K)``.

    Returns:
        ``(...)``.
    """
    gauss = cell_nll(wrap(obs - mean), logvar, obs, head).sum(-1)  # (..., K)
    shape = nn.functional.binary_cross_entropy_with_logits(s_logit, circ, reduction="none")
    presence = nn.functional.binary_cross_entropy_with_logits(p_logit, pres.to(p_logit), reduction="none")
    return (presence + torch.where(pres, gauss + shape, torch.zeros_like(gauss))).sum(-1)

