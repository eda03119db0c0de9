"""Offline: departure p under alternative tail statistics, from the dumped window z matrices."""
import glob, json, numpy as np, sys
from voe.gap.departure import _signed_rank_p, tail_p, ALPHA  # tail_p: the 'sum' statistic, as main computes it

def perm_p(zd, zn, stat, n_perm=2000, seed=0):
    zd = np.nan_to_num(np.asarray(zd, float), nan=0.0, posinf=1e300); zn = np.nan_to_num(np.atleast_2d(zn), nan=0.0, posinf=1e300)
    v = np.log(np.maximum(np.vstack([zd[None], zn]), 1e-6)); n_rows, w = v.shape
    order = np.sort(v, axis=0); top1, top2 = order[-1], order[-2]
    def ex(ch):
        rest = np.where(ch >= top1[None], top2[None], top1[None]); return stat(np.maximum(0.0, ch - rest))
    t_obs = float(ex(v[:1])[0])
    if t_obs <= 0: return 1.0
    pick = np.random.default_rng(seed).integers(0, n_rows, size=(n_perm, w))
    t = ex(v[pick, np.arange(w)[None]])
    return float((1 + np.sum(t >= t_obs * (1 - 1e-12))) / (n_perm + 1))

STATS = {
  'sum': lambda e: e.sum(axis=1),
  'sum>log2': lambda e: np.maximum(0, e - np.log(2)).sum(axis=1),
  'top3': lambda e: np.sort(e, axis=1)[:, -3:].sum(axis=1),
  'top5': lambda e: np.sort(e, axis=1)[:, -5:].sum(axis=1),
}
rows = [json.loads(l) for l in open('/work/eval/s27/dep.jsonl')]
seeds = set(map(int, sys.argv[1].split(','))) if len(sys.argv) > 1 else None
res = {}
for r in rows:
    if seeds and r['seed'] // 1000 not in seeds: continue
    d = np.load(f"/work/eval/s27/dep/{r['seed']}.npz", allow_pickle=False)
    sr = _signed_rank_p(d['zd1'], d['zn1'][0])
    ps = {}
    for name, st in STATS.items():
        for win in ('05', '1'):
            ps[f'{name}@{win}'] = (tail_p if name == 'sum' else lambda a, b: perm_p(a, b, st))(d['zd' + win], d['zn' + win])
    res[r['seed']] = (r, sr, ps)
combos = {'main(sr+sum@05)': ('sum@05',), 'sr+sum@05+sum@1': ('sum@05', 'sum@1'), 'sr+top3@05': ('top3@05',), 'sr+top3@1': ('top3@1',),
          'sr+top3@05+top3@1': ('top3@05', 'top3@1'), 'sr+sum>log2@05': ('sum>log2@05',), 'sr+sum>log2@1': ('sum>log2@1',), 'sr+top5@05': ('top5@05',),
          'sr+sum@05+top3@1': ('sum@05', 'top3@1')}
for cname, parts in combos.items():
    line = {}
    for grp in ('floor_patch', 'gust', 'none'):
        rs = [(r, sr, ps) for r, sr, ps in res.values() if r['truth'] == grp]
        k = 0
        for r, sr, ps in rs:
            p = min(1.0, (1 + len(parts)) * min([sr] + [ps[x] for x in parts]))
            k += (r['located'] > 0 and p < ALPHA)
        line[grp] = f"{k}/{len(rs)}"
    print(f"{cname:22s} unexplained-able: floor {line['floor_patch']:7s} gust {line['gust']:7s} clean {line['none']}")
