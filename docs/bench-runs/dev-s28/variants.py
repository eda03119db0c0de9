"""Does the test's rank check tell the window-local replicates from the variants it names?"""
import numpy as np
import voe.gap.departure as D
from voe.gap.shooting import Shooter, Window, ORDER
from voe.gap.recordings import Episode
from voe.gap.synth import pose_noise, null_like
from voe.gap.locate import window_z
from voe.gap.bench import make_case
from voe.gap.stages import GapConfig, locate_step, prepare
from voe.gap.finder import GapFinder
import dump_local

def no_perturb(sh, windows, sigma, phi, rng, n):
    n_fit = max(2 * sh.half + 1, ORDER + 3); seg, wins = [], []
    for i, w in enumerate(windows):
        ep = sh.episodes[w.ep]; lo = min(max(0, w.k0 - n_fit // 2), len(ep.t) - n_fit, w.k0)
        seg.append(Episode(ep.id, ep.t[lo:w.k1 + 1].copy(), ep.pose[lo:w.k1 + 1])); wins.append(Window(i, w.k0 - lo, w.k1 - lo))
    whole = [Window(i, 0, len(e.t) - 1) for i, e in enumerate(seg)]
    base = Shooter(sh.scene, seg, sh.substep, sh.half).simulate_many(whole, None, None)
    out = []
    for _ in range(n):
        eps = [Episode(e.id, e.t, m + pose_noise(m.shape, sigma, phi, rng)) for e, m in zip(seg, base)]
        out.append(window_z(Shooter(sh.scene, eps, sh.substep, sh.half), wins, sigma).max(axis=(1, 2)))
    return np.array(out)

if __name__ == "__main__":
  for seed, truth in ((6685205, 'none'), (6685171, 'none'), (1078026, 'none')):
      case = make_case(np.random.default_rng(seed), truth)
      p = prepare(case.scene, case.episodes, GapFinder(seed=seed).effects, GapConfig())
      loc = locate_step(p, GapConfig(), np.random.default_rng(seed))
      zd = window_z(p.shooter, loc.windows, p.sigma).max(axis=(1, 2))
      for name, fn in (('main', lambda *a: D.local_replicates(*a, n=10)), ('no perturbation', lambda *a: no_perturb(*a, 10)),
                       ('one-sided', lambda *a: dump_local_one_sided(*a))):
          if name == 'one-sided':
              continue
          rng = np.random.default_rng(0); null_like(p.scene, p.episodes, p.sigma, rng, p.substep, p.phi)
          zl = fn(p.shooter, loc.windows, p.sigma, p.phi, rng)
          print(seed, name, 'rank', round(float(np.mean(zl < zd[None])), 3), 'tail p', round(D.tail_p(zd, zl), 4))
