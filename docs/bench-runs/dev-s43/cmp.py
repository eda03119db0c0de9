import json, sys
import numpy as np
base = {json.loads(l)['id']: json.loads(l) for l in open(sys.argv[1])}
var = [json.loads(l) for l in open(sys.argv[2])]
def err(r, key):
    t = np.array([x if x is not None else np.nan for x in r['true']], float); p = np.array(r[key], float)
    ok = np.isfinite(t)
    return float(np.max(np.abs(p[ok] - t[ok]) / np.maximum(np.abs(t[ok]), 1e-9))) if ok.any() else np.nan
n = 0; tally = dict(better=0, worse=0)
print(f"{'id':8s} {'truth':20s} {'gain main':>9s} {'gain var':>9s} {'oracle':>7s}  perr main -> var   cpu main -> var")
for r in var:
    b = base.get(r['id'])
    if b is None: continue
    n += 1
    d = r['gain'] - b['gain']
    if d > 0.005: tally['better'] += 1
    if d < -0.005: tally['worse'] += 1
    flag = "  <" if abs(d) > 0.005 else ""
    print(f"{r['id']} {r['truth']:20s} {b['gain']:9.3f} {r['gain']:9.3f} {b['o_gain']:7.3f}  {err(b,'raw_params'):.3f} -> {err(r,'raw_params'):.3f}   {b['cpu_fit']:.1f} -> {r['cpu_fit']:.1f}{flag}")
print(n, tally)
gm = [base[r['id']]['gain'] for r in var if r['id'] in base]; gv = [r['gain'] for r in var if r['id'] in base]
print("median perr main", np.median([err(base[r['id']],'raw_params') for r in var if r['id'] in base]), "var", np.median([err(r,'raw_params') for r in var if r['id'] in base]))
print("cpu main", sum(base[r['id']]['cpu_fit'] for r in var if r['id'] in base), "var", sum(r['cpu_fit'] for r in var if r['id'] in base))
