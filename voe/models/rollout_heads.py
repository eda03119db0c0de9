"""State heads of the interaction networks: how a slot's state at t becomes its predicted mean
and variance at t+1 (torch).

Why two: ``interaction-v2`` (``RolloutHead``) gates a built-in Euler step, ``x + dt v``: with its
gates open, any network of that architecture carries a hidden object at constant velocity,
random weights included, so random v2 networks pass inertia, permanence and continuity without
having learned anything (``voe.controls.random_nets`` draws the gates at random to show it).
``interaction-v3`` (``IntegratorHead``) replaces the gates and the Euler step by a learned linear
map of the whole slot state (a learned linear integrator): no value of its parameters is
privileged, it starts at zero like every output layer, and a random draw of it is a random linear
map, not a physical step. What a trained v3 carries across an occlusion it learned. But a random
linear map still carries a fading memory of a hidden object (spectral radius about 0.5-0.8), and
on hidden splices any consistent memory decides the sign: random v3 networks were off chance on
continuity, inertia, energy, permanence and solidity for some seeds (dev seed 0, docs/models-findings.md).

Both heads start as constants (zero gates or map, outlier weight ~1) and are randomized in full by
``randomize(generator)`` for the random-network controls, each with the reason for its draw.
"""

from __future__ import annotations

import math

import torch
from torch import nn

from voe.models import slot_rollout as sr
from voe.models.state_head import TYPICAL, W0, StateHead, uniform_like


class RolloutHead(StateHead):
    """The v2 head: ten gated features (nine ``CONT`` and ``exist``).

    ``mean_f = c_f + g_f * (guess_f - c_f) + correction`` where ``guess`` is the slot state moved
    one Euler step by its own velocity (for x, y, angle) and the state itself otherwise, and
    ``g = GAIN * theta`` starts at zero: an untrained network predicts the typical state whatever
    it saw. The predicted variance is the network's one-step variance plus the carried variance
    pushed through the gated step (``step_logvar``), so along a hidden rollout the variance
    accumulates with the gates the model learned (a Kalman-style prediction step).

    The gains only speed up learning (a whole-clip step is costly, so there are few of them); they
    change nothing at initialisation, where every gated parameter is zero.
    """

    GAIN = 10.0  # a gate opens in ~50 Adam steps
    LV_GAIN = 20.0  # likewise for the one-step log-variance's per-feature offset
    OUTLIER_GAIN = 5.0  # the outlier weight falls from ~1 in ~70 Adam steps instead of ~350

    def __init__(self) -> None:
        super().__init__()
        self.c = nn.Parameter(torch.tensor((*TYPICAL, 0.0)))
        self.theta = nn.Parameter(torch.zeros(10))
        self.lv_bias = nn.Parameter(torch.zeros(9))  # per-feature log-variance offset, x LV_GAIN
        self.shape_gain = nn.Parameter(torch.zeros(()))  # weight of the remembered shape's logit
        self.presence_screen = nn.Linear(2, 1, bias=False)  # covered / outside at the predicted state
        nn.init.zeros_(self.presence_screen.weight)

    def log_outlier(self) -> tuple[torch.Tensor, torch.Tensor]:
        z = W0 - 20.0 * self.OUTLIER_GAIN * self.outlier_theta
        return nn.functional.logsigmoid(z), nn.functional.logsigmoid(-z)

    def randomize(self, gen: torch.Generator) -> None:
        """Every parameter at random (for random-network controls), each over its natural range:

        * outlier weight and presence bias as ``StateHead.randomize`` (the Gaussian gets about
          half the mixture, so the network's random output matters);
        * the centre ``c`` uniform over the state's clamp range (a typical state could be any);
        * the gates (``_randomize_step``);
        * the log-variance offsets and the shape memory's weight like the bias and weight of a
          one-input linear layer, ``U(-1, 1)``;
        * ``presence_screen`` is a zero linear layer, drawn by ``TorchModel.randomize_outputs``.
        """
        super().randomize(gen)
        with torch.no_grad():
            self.outlier_theta.div_(self.OUTLIER_GAIN)
            lo = torch.cat([sr._RANGE_LO, torch.zeros(1)])
            hi = torch.cat([sr._RANGE_HI, torch.ones(1)])
            self.c.copy_(uniform_like(lo, hi, gen))
            self.lv_bias.copy_(uniform_like(-torch.ones(9), torch.ones(9), gen) / self.LV_GAIN)
            self.shape_gain.copy_(2 * torch.rand((), generator=gen) - 1)
            self._randomize_step(gen)

    def _randomize_step(self, gen: torch.Generator) -> None:
        """Gates uniform over their natural range ``[0, 1]`` (closed to fully open)."""
        self.theta.copy_(torch.rand(self.theta.shape, generator=gen) / self.GAIN)

    def gates(self) -> torch.Tensor:
        return self.GAIN * self.theta  # (10,)

    def step_mean(self, cont: torch.Tensor, exist: torch.Tensor, dt: torch.Tensor) -> torch.Tensor:
        # cont: (B, K, 9), exist: (B, K), dt: (B,) -> (B, K, 10)
        moved = cont[..., 0:3] + dt[:, None, None] * cont[..., 3:6]
        guess = torch.cat([moved, cont[..., 3:], exist[..., None]], -1)
        return self.c + self.gates() * (guess - self.c)

    def step_logvar(self, lv_step: torch.Tensor, lv: torch.Tensor, dt: torch.Tensor) -> torch.Tensor:
        """Log-variance ``(B, K, 9)`` of the prediction: the network's one-step variance plus the
        carried variance pushed through the gated Euler step (``x' = c + g (x + dt v - c)``, so
        ``var x' = g^2 (var x + dt^2 var v)``: a hidden object's position grows uncertain with
        its speed's uncertainty)."""
        lg2 = torch.log(self.gates()[:9] ** 2 + 1e-30)  # (9,)
        ldt2 = 2 * torch.log(dt)[:, None, None]  # (B, 1, 1)
        moved = torch.cat([torch.logaddexp(lv[..., 0:3], ldt2 + lv[..., 3:6]), lv[..., 3:]], -1)
        return torch.logaddexp(lv_step, lg2 + moved).clamp(-14.0, 8.0)

    def shape_logit(self, raw: torch.Tensor, circle: torch.Tensor) -> torch.Tensor:
        """Logit ``(B, K)`` of "circle" at t+1 from the network's ``raw`` and the carried belief."""
        return raw + self.shape_gain * (2 * circle - 1)


class IntegratorHead(RolloutHead):
    """The v3 head: a learned linear integrator of the slot state, no built-in step.

    ``mean = c + W u + correction`` with ``u = [cont - c, exist - c_exist, dt * (vx, vy, omega)]``
    ``(13,)`` and ``W = GAIN * theta`` ``(10, 13)``, zero at initialisation (an untrained network
    predicts the constant ``c``). Velocities enter also multiplied by the clip's observed ``dt``
    (an input of the harness), so that *if* training finds that position follows velocity, the
    coefficient is 1 in any world's units; which coefficients matter, and their values, is learned.
    The carried variance goes through the same map: ``var x'_i = sum_j W_ij^2 var u_j``.
    """

    N_IN = 13

    def __init__(self) -> None:
        super().__init__()
        self.theta = nn.Parameter(torch.zeros(10, self.N_IN))

    def _randomize_step(self, gen: torch.Generator) -> None:
        """``W`` drawn as any linear layer of ``N_IN`` inputs is (PyTorch's default,
        ``U(-1/sqrt(13), 1/sqrt(13))``): a random linear map. A near-identity draw would not be
        random; it would be the prior "objects persist", which is part of what the probes test."""
        b = 1.0 / math.sqrt(self.N_IN)
        self.theta.copy_((2 * torch.rand(self.theta.shape, generator=gen) - 1) * b / self.GAIN)

    def gates(self) -> torch.Tensor:
        return self.GAIN * self.theta  # (10, 13)

    def _inputs(self, cont: torch.Tensor, exist: torch.Tensor, dt: torch.Tensor) -> torch.Tensor:
        return torch.cat([cont - self.c[:9], exist[..., None] - self.c[9:],
                          dt[:, None, None] * cont[..., 3:6]], -1)  # (B, K, 13)

    def step_mean(self, cont: torch.Tensor, exist: torch.Tensor, dt: torch.Tensor) -> torch.Tensor:
        # cont: (B, K, 9), exist: (B, K), dt: (B,) -> (B, K, 10)
        return self.c + self._inputs(cont, exist, dt) @ self.gates().T

    def step_logvar(self, lv_step: torch.Tensor, lv: torch.Tensor, dt: torch.Tensor) -> torch.Tensor:
        """Log-variance ``(B, K, 9)``: the network's one-step variance plus the carried variance
        through the linear map (``exist`` carries none)."""
        ldt2 = 2 * torch.log(dt)[:, None, None]  # (B, 1, 1)
        lv_u = torch.cat([lv, torch.full_like(lv[..., :1], -60.0), ldt2 + lv[..., 3:6]], -1)  # (B, K, 13)
        lw2 = torch.log(self.gates()[:9] ** 2 + 1e-30)  # (9, 13)
        carried = torch.logsumexp(lw2 + lv_u[..., None, :], -1)  # (B, K, 9)
        return torch.logaddexp(lv_step, carried).clamp(-14.0, 8.0)
