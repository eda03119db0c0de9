"""Count r30_locate.txt: the verdict a case that names nothing gets (``unexplained`` when located and the
departure p is below ALPHA = 0.01; with nothing above the first bar, the second bar's windows count as located
when the p is below ALPHA) under the landed test (ten replicates) and the screened one (twenty more where the ten
leave the tail p below SCREEN and the signed-rank p does not decide), by truth and noise kind; out-of-library
cases left ``consistent`` by their untouched runs listed.

    python r30_count.py FILE [SCREEN]
"""
import collections, glob, json, math, sys
screen = float(sys.argv[2]) if len(sys.argv) > 2 else 0.2
stored = {}
for p in glob.glob('/work/main/docs/bench-runs/gap_bench_*.jsonl'):
    for ln in open(p).read().splitlines()[1:]:
        r = json.loads(ln); stored[r['seed']] = r
c = collections.Counter()
for ln in open(sys.argv[1]):
    f = ln.split()
    if len(f) < 14 or f[3] != 'sr':
        continue
    seed, truth, nk = int(f[0]), f[1], f[2]
    sr, t10, t30, loc, rel = float(f[4]), float(f[6]), float(f[8]), int(f[12]), int(f[14])
    dp10 = min(1.0, 2 * min(sr, t10))
    drawn = 2 * sr >= 0.01 and t10 < screen
    dpS = min(1.0, 2 * min(sr, t30 if drawn else t10))
    assert not (drawn and math.isnan(t30))
    v10 = dp10 < 0.01 and (loc > 0 or rel > 0)
    vS = dpS < 0.01 and (loc > 0 or rel > 0)
    kind = 'clean-' + nk if truth == 'none' else truth
    c[kind, 'n'] += 1; c[kind, 'ten'] += v10; c[kind, 'screened'] += vS; c[kind, 'drawn'] += drawn
    if v10 != vS:
        print('changes:', seed, truth, nk, f'sr {sr} t10 {t10} t30 {t30} located {loc} rel {rel}',
              'ten', 'unexplained' if v10 else 'consistent', '-> screened', 'unexplained' if vS else 'consistent',
              '| stored', stored.get(seed, {}).get('verdict', '-'))
    r = stored.get(seed)
    if truth != 'none' and r and r['verdict'] == 'consistent':
        print('stored consistent:', seed, truth, f'sr {sr} t10 {t10} t30 {t30} located {loc} rel {rel}',
              '-> screened', 'unexplained' if vS else 'consistent')
for k in sorted(set(k for k, _ in c)):
    print(k, {m: c[k, m] for kk, m in c if kk == k})
