"""Development (session 29): location stage on clean cases whose jitter is SCALE ms (clipped at twice
that) instead of the bench's 2 ms; usage: loc_scale.py OUT SCALE_MS SEED ..."""
import sys, json, time, inspect, textwrap, numpy as np
import voe.gap.bench as bench
src = inspect.getsource(bench._clean)
scale = float(sys.argv[2]) * 1e-3
src = src.replace("rng.normal(0, 2e-3,", f"rng.normal(0, {scale!r},").replace("-4e-3, 4e-3", f"{-2 * scale!r}, {2 * scale!r}")
assert repr(scale) in src
exec(src, bench.__dict__)
from voe.gap.stages import GapConfig, prepare, locate_step
from voe.gap.finder import GapFinder
for seed in map(int, sys.argv[3:]):
    case = bench.make_case(np.random.default_rng(seed), "none", noise_kind="jitter")
    cfg = GapConfig()
    p = prepare(case.scene, case.episodes, GapFinder(seed=seed).effects, cfg)
    loc = locate_step(p, cfg, np.random.default_rng(seed))
    r = dict(seed=seed, scale_ms=scale * 1e3, located=len(loc.located), p=loc.departure_p,
             jitter_ms=None if getattr(p, "jitter", None) is None else round(p.jitter.seconds * 1e3, 3))
    with open(sys.argv[1], 'a') as fh: fh.write(json.dumps(r) + '\n')
    print(json.dumps(r), flush=True)
