"""``interaction-v9``: a bounce teaches the velocity mean in proportion to its size, and nothing
else about the model changes.

What must hold (docs/models-findings.md, sessions 16-19): at a step seen on both sides, the mean's
training gradient from a velocity residual r is the likelihood's plus ``r / TEACH_SD^2`` (v3's
floored Gaussian gives exactly 0 at 20 sd, so a bounce taught nothing); a slot hidden at t or t+1
gets no teacher; the value of the training loss and the scored density are v3's; untrained, v9
is the same constant as v3.
"""

from __future__ import annotations

import numpy as np
import pytest

torch = pytest.importorskip("torch")

from voe.models.check import check_model  # noqa: E402


def _frames(vx1: float, seen_before: bool) -> dict[str, torch.Tensor]:
    """One ball, two frames: moving right at 2 units/s, then vx1 (a bounce when negative)."""
    obs = torch.zeros(1, 2, 1, 9)
    obs[..., 0], obs[..., 1], obs[..., 6], obs[..., 7], obs[..., 8] = 5.0, 3.0, 1.0, 1.0, 0.9
    obs[0, 0, 0, 3], obs[0, 1, 0, 3] = 2.0, vx1
    pres = torch.tensor([[[seen_before], [True]]])  # (1, T=2, K=1)
    return {"obs": obs, "present": pres, "circle": torch.ones(1, 2, 1), "dt": torch.full((1, 2), 0.05),
            "statics": torch.zeros(1, 2, 2, 6), "occluders": torch.zeros(1, 2, 2, 5),
            "extent": torch.tensor([[[10.0, 6.0]] * 2])}  # no walls, no screens


def _pull(arch: str, vx1: float, seen_before: bool = True) -> tuple[float, float, float]:
    """Training loss, scored loss, and ``-d loss / d (vx correction)`` of the one predicted frame."""
    return _grad_at(arch, _frames(vx1, seen_before), 1, lambda d: d)


def _grad_at(arch: str, frames: dict[str, torch.Tensor], t: int, scoring) -> tuple[float, float, float]:
    """Training loss at frame ``t``, its scored value (on ``scoring(frames)``), and
    ``-d loss / d (vx correction)``, for an untrained ``arch`` whose head is set as a trained one's."""
    from voe.models.interaction import rollout_nll
    from voe.models.loading import load_model

    net = load_model(arch, {"seed": 0}).net.double()
    d = {k: (v.double() if v.is_floating_point() else v) for k, v in frames.items()}
    with torch.no_grad():
        net.head.outlier_theta.fill_(1.22 / net.head.OUTLIER_GAIN)  # log w ~ -4.4, a trained model's
        net.head.lv_bias.fill_(2 * np.log(0.02) / net.head.LV_GAIN)  # visible sd ~0.02, a trained model's
        net.head.c[3] = 2.0  # the constant prediction goes on at 2 units/s
    bias = net.out[-1].bias
    net.train()
    loss = rollout_nll(net, d)[0, t]
    loss.backward()
    net.eval()
    with torch.no_grad():
        scored = float(rollout_nll(net, scoring(d))[0, t])
    return float(loss.detach()), scored, -float(bias.grad[4])  # out[..., 4]: the vx correction


def test_a_bounce_pulls_the_velocity_mean_in_proportion_to_its_size():
    from voe.models.interaction_teacher import TeacherHead

    sd = TeacherHead.TEACH_SD
    v9 = "voe.models.interaction_teacher:InteractionNetV9"
    for vx1 in (1.6, -2.0, -4.0):  # 20 visible sd, and bounces at 200 and 300
        loss, scored, pull = _pull(v9, vx1)
        assert loss == pytest.approx(scored, abs=1e-9)
        _, _, v3_pull = _pull("interaction-v3", vx1)
        assert pull - v3_pull == pytest.approx((vx1 - 2.0) / sd ** 2, rel=1e-6), vx1
        if vx1 < 0:
            assert abs(v3_pull) < 1e-6  # why v9 exists: v3's mean learns nothing from a bounce
    _, _, hidden = _pull(v9, -2.0, seen_before=False)
    _, _, v3_hidden = _pull("interaction-v3", -2.0, seen_before=False)
    assert hidden == pytest.approx(v3_hidden, abs=1e-9)  # a return after a hidden stretch is no contact


def test_v9_untrained_is_v3s_constant_and_keeps_the_model_contract(tiny_batch):
    from voe.controls.random_nets import random_network
    from voe.models.loading import load_model

    ref = "voe.models.interaction_teacher:InteractionNetV9"
    m = load_model(ref, {"seed": 0})
    nll = m.frame_nll(tiny_batch)[:, m.warmup:]
    assert np.ptp(nll) < 1e-5
    np.testing.assert_allclose(nll, load_model("interaction-v3", {"seed": 0}).frame_nll(tiny_batch)[:, m.warmup:])
    r = random_network(ref, 3)
    np.testing.assert_allclose(r.frame_nll(tiny_batch), random_network("interaction-v3", 3).frame_nll(tiny_batch))
    check_model(r, tiny_batch)


def test_stretch_mask_leaves_out_one_stretch_after_first_sight_and_scoring_feeds_everything(tiny_batch):
    """Masked stretches (v9m's training): a left-out frame is a present frame after the slot's first
    sight, at most one stretch of 3-15 frames per slot, for about half of the slots; in evaluation
    v9m scores exactly as v9 (every observation fed)."""
    from voe.controls.random_nets import random_network
    from voe.models.interaction_teacher import stretch_mask

    torch.manual_seed(0)
    pres = torch.ones(400, 40, 3, dtype=torch.bool)
    pres[:, :5, 0] = False  # slot 0 first seen at frame 5
    fed = stretch_mask(pres)
    out = pres & ~fed  # (B, T, K)
    assert not (fed & ~pres).any()
    assert not out[:, :6, 0].any() and not out[:, 0].any()  # never the first sight
    n = out.sum(1)  # (B, K)
    hit = n > 0
    assert 0.4 < float(hit.float().mean()) < 0.6
    assert int(n[hit].min()) >= 1 and int(n.max()) <= 15
    starts = (out[:, 1:] & ~out[:, :-1]).sum(1)
    assert int(starts.max()) <= 1  # one contiguous stretch
    v9m = random_network("voe.models.interaction_teacher:InteractionNetV9m", 3)  # not a constant
    v9 = random_network("voe.models.interaction_teacher:InteractionNetV9", 3)
    np.testing.assert_array_equal(v9m.frame_nll(tiny_batch), v9.frame_nll(tiny_batch))


def _hidden_pull(arch: str, vx2: float, screened: bool, seen0: bool = True) -> tuple[float, float, float]:
    """As ``_pull``, for the third frame of a ball fed at frame 0 (if ``seen0``), not fed at frame 1
    (behind a screen if ``screened``, else present but left out as in a masked stretch) and seen
    at frame 2 moving at ``vx2``: that prediction is 2 steps from the last fed state. The scored
    value is returned for the screened case (a masked frame is fed when scoring)."""
    d = {k: (torch.cat([v, v[:, 1:]], 1) if v.dim() > 1 and v.shape[1] == 2 else v)
         for k, v in _frames(2.0, seen0).items()}  # (1, T=3, ...)
    d["obs"][0, 2, 0, 3] = vx2
    d["present"][0, 1, 0] = not screened
    d["fed"] = d["present"].clone()
    d["fed"][0, 1, 0] = False
    return _grad_at(arch, d, 2, lambda x: {k: v for k, v in x.items() if k != "fed"})


def test_v9h_teaches_a_rolled_out_step_at_a_width_that_grows_with_the_steps_hidden():
    """v9h (session 20): the step two frames after the last fed state is taught at width
    ``TEACH_SD * sqrt(2)``, whether the frame between was left out (masked stretch) or screened;
    v9 teaches neither, and a slot never fed is never taught."""
    from voe.models.interaction_teacher import HiddenTeacherHead

    sd = HiddenTeacherHead.TEACH_SD
    v9 = "voe.models.interaction_teacher:InteractionNetV9"
    v9h = "voe.models.interaction_teacher:InteractionNetV9h"
    for screened in (False, True):
        for vx2 in (1.0, -3.0):
            loss, scored, pull = _hidden_pull(v9h, vx2, screened)
            _, _, v9_pull = _hidden_pull(v9, vx2, screened)
            assert pull - v9_pull == pytest.approx((vx2 - 2.0) / (2 * sd ** 2), rel=1e-6), (screened, vx2)
            if screened:
                assert loss == pytest.approx(scored, abs=1e-9)  # the teacher's value is 0
    _, _, never = _hidden_pull(v9h, -3.0, False, seen0=False)
    _, _, v9_never = _hidden_pull(v9, -3.0, False, seen0=False)
    assert never == pytest.approx(v9_never, abs=1e-9)
