"""Offline (session 28, development seeds only): departure designs from the R = 20 dumps."""
import json, sys, numpy as np
from voe.gap.departure import _signed_rank_p, tail_p, ALPHA
rows = [json.loads(l) for l in open(sys.argv[1] if len(sys.argv) > 1 else '/work/eval/s28/dump.jsonl')]
def designs(d):
    sr = _signed_rank_p(d['zd1'], d['zn1'][0])
    out = {'main sr@1+tail@05 R4': min(1, 2 * min(sr, tail_p(d['zd05'], d['zn05'][:4])))}
    for R in (4, 8, 10, 20):
        t05, t1 = tail_p(d['zd05'], d['zn05'][:R]), tail_p(d['zd1'], d['zn1'][:R])
        out[f'sr@1+tail@05 R{R}'] = min(1, 2 * min(sr, t05))
        out[f'sr@1+tail@1 R{R}'] = min(1, 2 * min(sr, t1))
        out[f'sr@1+tail@05+tail@1 R{R}'] = min(1, 3 * min(sr, t05, t1))
    return out
res = []
for r in rows:
    d = np.load(f"/work/eval/s28/dep/{r['seed']}.npz", allow_pickle=False)
    res.append((r, designs(d)))
names = list(res[0][1])
groups = [('floor', lambda r: r['truth'] == 'floor_patch'), ('gust', lambda r: r['truth'] == 'gust'),
          ('clean white', lambda r: r['truth'] == 'none' and r['nk'] == 'white'),
          ('clean coloured', lambda r: r['truth'] == 'none' and r['nk'] == 'coloured')]
print(f"{'design':28s} " + "  ".join(f"{g:>14s}" for g, _ in groups))
for n in names:
    cells = []
    for g, sel in groups:
        rs = [(r, ps) for r, ps in res if sel(r)]
        k = sum(r['located'] > 0 and ps[n] < ALPHA for r, ps in rs)
        cells.append(f"{k:>3d}/{len(rs):<3d}".rjust(14))
    print(f"{n:28s} " + "  ".join(cells))
if '-v' in sys.argv:
    for r, ps in res:
        if r['truth'] != 'none' or any(ps[n] < ALPHA for n in names):
            print(r['seed'], r['truth'], r['nk'], 'located', r['located'], ' '.join(f"{ps[n]:.3g}" for n in names))
