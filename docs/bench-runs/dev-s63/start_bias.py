"""Is a window's start state biased where a body comes to rest inside the local fit's span? (development only)

For one case's window: the box's (or any body's) start velocity read by ``local_state`` off the recorded poses and
off the noise-free poses (the bench's clean simulation, caught as it is recorded), and where the truth's rollout
from each start leaves each body against the clean poses.

    PYTHONPATH=<clone> python start_bias.py SEED TRUTH NOISE_KIND EPISODE K0 K1
"""
import sys

import numpy as np

import voe.gap.bench as bench
from voe.gap.finder import ALL_EFFECTS
from voe.gap.recordings import Episode
from voe.gap.shooting import Shooter, Window, local_state
from voe.gap.stages import GapConfig, prepare

sys.path.insert(0, "../dev-s62")
from guards_at_truth import truth_model  # noqa: E402

clean = {}
orig = bench._record


def spy(rng, k, t, c, sigma, kind):
    clean[k] = c.copy()
    return orig(rng, k, t, c, sigma, kind)


bench._record = spy
seed, truth, kind, e, k0, k1 = int(sys.argv[1]), sys.argv[2], sys.argv[3], *map(int, sys.argv[4:7])
case = bench.make_case(np.random.default_rng(seed), truth, 1e-3, 12, 3.0, noise_kind=kind)
p = prepare(case.scene, case.episodes, ALL_EFFECTS, GapConfig())
model, _ = truth_model(case, 1)
ep = p.shooter.episodes[e]
ce = Episode(ep.id, ep.t.copy(), clean[ep.id][: len(ep.t)])
w = Window(e, k0, k1)
names = case.scene.names
for label, src in (("recorded", ep), ("clean", ce)):
    pose, vel, _ = local_state(src, k0, p.half, p.substep)
    print(f"{label:9s} start: " + "; ".join(f"{n} v ({1e3 * vel[b, 0]:+.1f}, {1e3 * vel[b, 1]:+.1f}) mm/s" for b, n in enumerate(names)))
sh_clean = Shooter(p.scene, [ce if i == e else x for i, x in enumerate(p.shooter.episodes)], p.substep, p.half)
for label, sh in (("recorded start", p.shooter), ("clean start", sh_clean)):
    for mlabel, eff, prm in (("nominal", None, None), ("truth", model.effect, model.params)):
        sim = sh.simulate(w, eff, prm)  # (n, B, 3)
        d = sim - clean[ep.id][k0:k1 + 1]
        print(f"{label:14s} {mlabel:7s} minus clean: " + "; ".join(
            f"{n} x at end {1e3 * d[-1, b, 0]:+.1f} mm, max |xy| {1e3 * np.abs(d[:, b, :2]).max():.1f} mm"
            for b, n in enumerate(names)))
