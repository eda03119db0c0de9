"""Development (session 29): the whole finder (bench run_case, default config) on clean jittered cases."""
import sys, json, time
from voe.gap.bench import run_case
out = sys.argv[1]
for spec in sys.argv[2:]:
    seed, truth, nk = spec.split(':')
    t0 = time.time()
    r = run_case((int(seed), truth, 1e-3, 3, 12, 3.0, nk))
    r = {k: r[k] for k in ('seed', 'truth', 'noise_kind', 'names', 'verdict', 'located', 'dropped')} | {'wall': round(time.time() - t0)}
    with open(out, 'a') as fh: fh.write(json.dumps(r) + '\n')
    print(json.dumps(r), flush=True)
