"""Object-centric interaction network that rolls hidden objects forward with its own predictions.

Why: physical expectations are about objects, including objects one cannot see. Each slot is
encoded on its own (``voe.models.slot_rollout``), objects exchange messages along all pairs, and
each slot predicts a distribution over its own next state. A visible slot's state is its
observation; a hidden (or never seen) slot's state is the model's own prediction from the frame
before, so a hidden object keeps moving, falls, hits walls and other objects only as far as the
network has learned that it does. Training runs over whole clips of the ordinary training world
(which has screens), and the loss on an object's reappearance back-propagates through every
rolled-out hidden step. The surprise at reappearance is the likelihood of the observed state under
the rolled-out prediction, whose variance grows along the rollout (``RolloutHead``).

How a slot's state becomes its next mean and variance is the head's job
(``voe.models.rollout_heads``): ``interaction-v2`` gates a built-in Euler step ``x + dt v``, which
random networks with open gates already use to carry hidden objects (so random v2 networks are
off chance on hidden splices); ``interaction-v3`` learns a linear integrator of the slot state
instead, with nothing physical at any parameter value. Untrained, both are the same uniform
distribution for every clip (zero output layers, gates or map, outlier weight ~1).

References: Battaglia et al. 2016, "Interaction Networks"; Sanchez-Gonzalez et al. 2020 (learned
simulators rolled out on their own predictions); Piloto et al. 2022 (PLATO, object-centric VoE).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import torch
from torch import nn

from voe.io.batch import Batch
from voe.models import slot_rollout as sr
from voe.models import statelik as sl
from voe.models.rollout_heads import IntegratorHead, RolloutHead
from voe.models.state_head import DELTA_SCALE, bounded_logvar, cell_nll, frame_cost
from voe.models.torchbase import TorchModel

OUT = 18  # presence, 6 mean corrections, 9 log-variances, shape, exist correction


@dataclass(frozen=True)
class InteractionConfig:
    """Width of every MLP and the seed of the initial weights."""

    hidden: int = 96
    seed: int = 0


def mlp(a: int, h: int, b: int) -> nn.Sequential:
    return nn.Sequential(nn.Linear(a, h), nn.SiLU(), nn.Linear(h, h), nn.SiLU(), nn.Linear(h, b))


class InteractionModule(nn.Module):
    def __init__(self, c: InteractionConfig, head: type[RolloutHead] = RolloutHead) -> None:
        super().__init__()
        h = c.hidden
        self.node = mlp(sr.D, h, h)
        # the edge MLP's first layer acts on [h_k, h_j, rel]; it is applied per node and per pair
        # and summed (the same function, K times fewer rows for the node parts)
        self.edge = mlp(2 * h + sr.REL, h, h)
        self.h = h
        self.out = mlp(2 * h + sr.D, h, OUT)
        self.head = head()
        nn.init.zeros_(self.out[-1].weight)  # untrained = the same prediction for every input
        nn.init.zeros_(self.out[-1].bias)

    def forward(self, x: torch.Tensor, rel: torch.Tensor) -> torch.Tensor:
        # x: (B, K, D); rel: (B, K, K, REL) with [k, j] = other j seen from k -> (B, K, OUT)
        B, K, _ = x.shape
        h = self.node(x)  # (B, K, H)
        first, H = self.edge[0], self.h
        w = first.weight  # (H, 2H + REL)
        e = (nn.functional.linear(h, w[:, :H], first.bias)[:, :, None]  # (B, K, 1, H): receiver k
             + nn.functional.linear(h, w[:, H:2 * H])[:, None]  # (B, 1, K, H): sender j
             + nn.functional.linear(rel, w[:, 2 * H:]))  # (B, K, K, H)
        off = 1.0 - torch.eye(K, dtype=x.dtype, device=x.device)[None, :, :, None]
        msg = (self.edge[1:](e) * off).sum(2)  # (B, K, H)
        return self.out(torch.cat([h, msg, x], -1))


def rollout_nll(net: InteractionModule, d: dict[str, torch.Tensor],
                trace: list[tuple[torch.Tensor, ...]] | None = None) -> torch.Tensor:
    """Surprise ``(B, T)`` of every frame given the frames before it (frame 0 set to 0).

    Frame by frame: the slot state is the observation where a slot is visible and the model's own
    prediction elsewhere; the network predicts frame t+1 from the state at t only, so the result is
    causal by construction and each clip is processed on its own. ``trace`` (diagnostics,
    ``bench/hidden_rollout.py``): each step appends the predicted mean and log-variance of frame
    t+1, ``(B, K, 9)`` each, then the presence and shape logits, ``(B, K)`` each (``frame_parts``).
    ``d["fed"]`` ``(B, T, K)`` (training only, ``voe.models.interaction_teacher.stretch_mask``): the
    observations fed to the slot state, default ``present``; the others are rolled out and scored.
    A head with ``TEACH_SD`` adds ``velocity_teacher``'s gradient in training.
    """
    head = net.head
    obs, pres, circ_obs = d["obs"], d["present"], d["circle"]  # (B, T, K, 9), (B, T, K), (B, T, K)
    B, T, K, _ = obs.shape
    dt = d["dt"][:, 0]  # (B,)
    geo = {k: d[k][:, 0] for k in ("statics", "occluders", "extent")}
    scale = obs.new_tensor(DELTA_SCALE)
    f64 = not head.training  # score in float64: an untrained model's equal costs stay equal
    cont = obs.new_zeros(B, K, 9)
    circ = obs.new_full((B, K), 0.5)
    exist = obs.new_zeros(B, K)
    lv = obs.new_full((B, K, 9), sr.LV_NEW)
    frames = [obs.new_zeros(B, dtype=torch.float64 if f64 else obs.dtype)]
    fed_all = d.get("fed", pres)  # (B, T, K): observations fed to the slot state (training may leave some out)
    hidden = head.training and head.TEACH_SD is not None and head.TEACH_HIDDEN  # v9h's teacher only
    since = obs.new_full((B, K), -1.0)  # steps from the last fed state to t; -1 = never fed (v9h only)
    for t in range(T):
        p = fed_all[:, t]  # (B, K)
        if hidden:
            since = torch.where(p, torch.zeros_like(since), torch.where(since >= 0, since + 1, since))
        cont = torch.where(p[..., None], obs[:, t], cont)
        circ = torch.where(p, circ_obs[:, t], circ)
        exist = torch.where(p, torch.ones_like(exist), exist)
        lv = torch.where(p[..., None], torch.full_like(lv, sr.LV_OBS), lv)
        if t == T - 1:
            break
        x, rel = sr.slot_inputs(cont, circ, exist, lv, p, geo)
        out = net(x, rel)  # (B, K, OUT)
        mean = head.step_mean(cont, exist, dt)  # (B, K, 10)
        mean = torch.cat([mean[..., :6] + scale * out[..., 1:7], mean[..., 6:9],
                          mean[..., 9:] + out[..., 17:18]], -1)
        lv_next = head.step_logvar(bounded_logvar(out[..., 7:16] + head.LV_GAIN * head.lv_bias), lv, dt)
        cont_next = sr.clamp_state(mean[..., :9])
        hid, outside = sr.covered(cont_next.detach(), circ.detach(), geo["occluders"], geo["extent"])
        p_logit = (out[..., 0] + head.presence_bias()
                   + head.presence_screen(torch.stack([hid, outside], -1).to(out)).squeeze(-1))
        s_logit = head.shape_logit(out[..., 16], circ)
        if trace is not None:
            trace.append((mean[..., :9].detach(), lv_next.detach(), p_logit.detach(), s_logit.detach()))
        cost = _frame_cost(head, mean[..., :9], lv_next, p_logit, s_logit, obs[:, t + 1], pres[:, t + 1],
                           circ_obs[:, t + 1], f64)
        if head.training and head.TEACH_SD is not None:
            taught = (since >= 0) if hidden else p  # (B, K)
            sd = head.TEACH_SD * torch.sqrt(since.clamp_min(0) + 1) if hidden else head.TEACH_SD  # sqrt(n) after n steps
            cost = cost + velocity_teacher(mean[..., 3:5], obs[:, t + 1, :, 3:5], taught & pres[:, t + 1], sd)
        frames.append(cost)
        # exist is a belief in [0, 1]; unclamped, a learned map can blow it up along a rollout
        cont, lv, exist, circ = cont_next, lv_next, mean[..., 9].clamp(0.0, 1.0), torch.sigmoid(s_logit)
    return torch.stack(frames, 1)  # (B, T)


def velocity_teacher(mean_v: torch.Tensor, obs_v: torch.Tensor, seen: torch.Tensor,
                     sd: float | torch.Tensor) -> torch.Tensor:
    """Training-only term ``(B,)`` whose value is 0 and whose gradient is a fixed-width Gaussian's
    on the predicted velocity of each slot seen at t and t+1.

    Why (sessions 16-18, docs/models-findings.md): the step never turned a visible object round at
    a bounce, because the likelihood's pull on the mean is scaled by the learned visible sd (about
    0.02 units/s): beyond about 8 sd the floored Gaussian gives no gradient, and a bounded (Huber)
    pull is outvoted by the 99 % of steps that go on, so the mean becomes a median that says "goes
    on". A squared loss of *fixed* width learns floor bounces (session 18's supervised check); here
    it is added to the likelihood's gradient, so a contact's pull grows with its size while the
    scored density, and the value of the training loss, stay the mixture's. Only one-step
    predictions from an observed state are taught, unless the head's ``TEACH_HIDDEN`` (v9h) also
    teaches rolled-out steps, at a width that grows as ``sqrt(n)`` with the n steps since the last
    fed state (a rollout's drift is a random walk, not a contact).

    Args:
        mean_v, obs_v: ``(B, K, 2)`` predicted and observed (vx, vy) at t+1; seen: ``(B, K)``
            taught slots (observed at t+1); sd: the width in velocity units, a number or ``(B, K)``.
    """
    sd = torch.as_tensor(sd, dtype=mean_v.dtype)
    z = (obs_v - mean_v) / (sd[..., None] if sd.dim() else sd)
    teach = torch.where(seen[..., None], 0.5 * z * z, torch.zeros_like(z)).sum((-1, -2))  # (B,)
    return teach - teach.detach()


def _frame_cost(head: RolloutHead, mean: torch.Tensor, lv: torch.Tensor, p_logit: torch.Tensor,
                s_logit: torch.Tensor, obs: torch.Tensor, pres: torch.Tensor, circ: torch.Tensor,
                f64: bool) -> torch.Tensor:
    """``-log P(frame)`` ``(B,)`` (``frame_cost``), in float64 when scoring."""
    if f64:
        mean, lv, p_logit, s_logit, obs, circ = (v.double() for v in (mean, lv, p_logit, s_logit, obs, circ))
    return frame_cost(head, mean, lv, p_logit, s_logit, obs, pres, circ)


#: the parts of a frame's surprise ``frame_parts`` separates, in its last axis
PARTS = ("presence", "shape", *sl.CONT)


def frame_parts(net: InteractionModule, d: dict[str, torch.Tensor]) -> torch.Tensor:
    """Each frame's surprise split by slot and part, ``(B, T, K, 11)`` (``PARTS``), float64.

    Why: a matched set is decided by a few nats on a few frames, and *which* part of the
    prediction carries them tells a physical expectation (presence, position, speed of a hidden
    object) from an incidental one (a remembered brightness): ``bench/splice_blame.py`` reads it.
    Summed over slots and parts it is ``rollout_nll`` exactly (frame 0 is 0); absent slots carry
    only their presence cost. Evaluation mode (the scoring path) only.
    """
    if net.training:
        raise ValueError("frame_parts: put the network in evaluation mode first (net.eval())")
    steps: list[tuple[torch.Tensor, ...]] = []
    rollout_nll(net, d, steps)
    obs, pres, circ = d["obs"][:, 1:].double(), d["present"][:, 1:], d["circle"][:, 1:].double()  # (B, T-1, K, ...)
    mean, lv, p_logit, s_logit = (torch.stack([s[i] for s in steps], 1).double() for i in range(4))
    gauss = cell_nll(sr.wrap(obs - mean), lv, obs, net.head)  # (B, T-1, K, 9)
    bce = nn.functional.binary_cross_entropy_with_logits
    presence = bce(p_logit, pres.to(p_logit), reduction="none")  # (B, T-1, K)
    shape = bce(s_logit, circ, reduction="none")
    here = pres[..., None]
    parts = torch.cat([presence[..., None], torch.where(here, shape[..., None], 0.0),
                       torch.where(here, gauss, 0.0)], -1)  # (B, T-1, K, 11)
    return torch.cat([parts.new_zeros(parts[:, :1].shape), parts], 1)  # (B, T, K, 11)


class InteractionNet(TorchModel):
    """Learned object-centric state model (see the module docstring)."""

    Config = InteractionConfig
    observation = "states"
    #: training presets: whole clips per step (window = clip length: hidden rollouts start at the
    #: first frame), learning rate, steps (about 4 min on one idle CPU core)
    presets = {"cpu": {"batch": 64, "window": 10**6, "lr": 3e-3, "steps": 700},
               "cuda": {"batch": 256, "window": 10**6, "lr": 2e-3, "steps": 2000}}
    model_id = "interaction-v2"

    def build(self) -> nn.Module:
        return InteractionModule(self.config)

    def prepare(self, batch: Batch) -> dict[str, torch.Tensor]:
        return sr.prepare(batch)

    def nll(self, d: dict[str, torch.Tensor]) -> torch.Tensor:
        return rollout_nll(self.net, d)

    def batch_layout(self, batch: Batch) -> dict[str, Any]:
        return sr.layout(batch)


class InteractionNetV3(InteractionNet):
    """``interaction-v3``: the same network with a learned linear integrator instead of the gated
    Euler step (``voe.models.rollout_heads.IntegratorHead``): no physical step at any parameter
    value, so random networks of it are random functions."""

    model_id = "interaction-v3"

    def build(self) -> nn.Module:
        return InteractionModule(self.config, IntegratorHead)
