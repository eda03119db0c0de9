"""Count rel_locate.txt: under the current rule (located and departure p < ALPHA) and a relative-location rule
(departure p < ALPHA and (located or a relative window)), clean and out-of-library cases, by noise kind;
out-of-library cases' stored verdicts from the untouched stores."""
import collections, glob, json
stored = {}
for p in glob.glob('/work/main/docs/bench-runs/gap_bench_*.jsonl'):
    for ln in open(p).read().splitlines()[1:]:
        r = json.loads(ln); stored[r['seed']] = r
c = collections.Counter()
for ln in open('rel_locate.txt'):
    f = ln.split()
    if len(f) < 11 or f[3] != 'dep_p':
        continue
    seed, truth, nk, dp, loc, rel = int(f[0]), f[1], f[2], float(f[4]), int(f[8]), int(f[10])
    now = loc > 0 and dp < 0.01
    new = dp < 0.01 and (loc > 0 or rel > 0)
    kind = 'clean-' + nk if truth == 'none' else truth
    c[kind, 'n'] += 1; c[kind, 'now'] += now; c[kind, 'new'] += new
    if truth != 'none':
        r = stored.get(seed)
        if r and r['verdict'] == 'consistent':
            c[kind, 'stored consistent'] += 1
            c[kind, 'stored consistent -> unexplained (new rule)'] += new
            print('consistent in store:', seed, truth, 'dep_p', dp, 'located', loc, 'rel', rel, '->', 'unexplained' if new else 'consistent')
    elif new and not now:
        print('clean, new rule fires:', seed, nk, 'dep_p', dp, 'located', loc, 'rel', rel)
for k in sorted(set(k for k, _ in c)):
    print(k, {m: c[k, m] for kk, m in c if kk == k})
