"""Offline (session 28, development seeds only): the departure with window-local replicates
(dump_local.py) against main's (episode replicates, dump20.py's first four rows)."""
import json, sys, numpy as np
from voe.gap.departure import _signed_rank_p, tail_p, ALPHA
rows = [json.loads(l) for l in open('/work/eval/s28/local.jsonl')]
def designs(d, e):
    sr = _signed_rank_p(d['zd1'], d['zn1'])
    t05 = tail_p(e['zd05'], e['zn05'][:4])
    out = {'main sr@1+tail@05 R4': min(1, 2 * min(sr, t05))}
    for R in (4, 10, 20):
        tl = tail_p(d['zs1'], d['zl1'][:R])
        out[f'sr+local@1 R{R}'] = min(1, 2 * min(sr, tl))
        out[f'sr+tail@05+local@1 R{R}'] = min(1, 3 * min(sr, t05, tl))
        out[f'local@1 alone R{R}'] = tl
    return out
res = []
for r in rows:
    d = np.load(f"/work/eval/s28/dep_local/{r['seed']}.npz", allow_pickle=False)
    e = np.load(f"/work/eval/s28/dep/{r['seed']}.npz", allow_pickle=False)
    assert np.allclose(d['zd1'], e['zd1'])
    res.append((r, designs(d, e)))
names = list(res[0][1])
groups = [('floor', lambda r: r['truth'] == 'floor_patch'), ('gust', lambda r: r['truth'] == 'gust'),
          ('clean white', lambda r: r['truth'] == 'none' and r['nk'] == 'white'),
          ('clean coloured', lambda r: r['truth'] == 'none' and r['nk'] == 'coloured')]
print(f"{'design (located and p < %g)' % ALPHA:30s} " + "  ".join(f"{g:>14s}" for g, _ in groups))
for n in names:
    cells = []
    for g, sel in groups:
        rs = [(r, ps) for r, ps in res if sel(r)]
        k = sum(r['located'] > 0 and ps[n] < ALPHA for r, ps in rs)
        cells.append(f"{k:>3d}/{len(rs):<3d}".rjust(14))
    print(f"{n:30s} " + "  ".join(cells))
if '-v' in sys.argv:
    print('seed truth noise located | ' + ' | '.join(names))
    for r, ps in res:
        if r['truth'] == 'floor_patch' or any(ps[n] < ALPHA for n in names if 'alone' not in n) and r['truth'] == 'none':
            print(r['seed'], r['truth'], r['nk'], r['located'], ' '.join(f"{ps[n]:.3g}" for n in names))
