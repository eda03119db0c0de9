"""Session 27 development table: out-of-library and compound cases, main's default finder against --cross-fit."""
import json, os
from voe.gap.bench_score import misnamed, outside_right
cross = {r['seed']: r for r in map(json.loads, open('/work/eval/s27/cross.jsonl'))}
dflt = {r['seed']: r for r in map(json.loads, open('/work/eval/s27/default.jsonl'))} if os.path.exists('/work/eval/s27/default.jsonl') else {}
cases = json.load(open('/work/eval/s27/cases.json'))
def before(c):
    """Main's default: rerun here for 6685/1078 out-of-library (stored names came from older code), else the stored untouched run."""
    if c['seed'] in dflt: return dflt[c['seed']]
    if c['group'] == 'ool' and c['seed'] // 1000 in (6685, 1078): return None
    names = [] if c['named'] == '-' else c['named'].split(',')
    return dict(truth=c['truth'], names=names, verdict=c['verdict'], located=1 if c['verdict'] == 'unexplained' else 0)
for g in ('ool', 'compound'):
    cs = [c for c in cases if c['group'] == g and c['seed'] in cross and before(c) is not None]
    if g == 'ool':
        b = [before(c) for c in cs]; a = [cross[c['seed']] for c in cs]
        print(f"out-of-library  cases {len(cs)}  misnamed default {sum(map(misnamed, b))} -> cross-fit {sum(map(misnamed, a))};"
              f" right (named correctly or unexplained and located) {sum(map(outside_right, b))} -> {sum(map(outside_right, a))}")
    else:
        ok = lambda r: set(r['truth'].split('+')) <= set(r['names'])
        b = [before(c) for c in cs]; a = [cross[c['seed']] for c in cs]
        extra = lambda r: [n for n in r['names'] if n not in r['truth'].split('+')]
        print(f"compound        cases {len(cs)}  both named default {sum(map(ok, b))} -> cross-fit {sum(map(ok, a))};"
              f" names beyond the truth {sum(len(extra(r)) for r in b)} -> {sum(len(extra(r)) for r in a)}")
    for c, x, y in zip(cs, b, a):
        if (sorted(x['names']), x['verdict']) != (sorted(y['names']), y['verdict']):
            print(f"   {c['seed']} {c['truth']:38s} {','.join(x['names']) or '-':40s} {x['verdict']:12s} -> {','.join(y['names']) or '-':40s} {y['verdict']}")
