import json, sys
rows = [json.loads(l) for l in open(sys.argv[1])]
same = sum(r["same"] and r["dropped"] == r["old_dropped"] for r in rows)
walked = [r for r in rows if r["n_walks"]]
print(f"{len(rows)} cases: names, verdict and dropped as stored in {same}; cases with a walk {len(walked)}")
for r in rows:
    print(f"  {r['seed']} {r['truth']:12s} {r['nk']:8s} {str(r['names']):22s} {r['verdict']:12s} stored {str(r['old_names']):22s} {r['old_verdict']:12s} walks {r['n_walks']} {r['walks'][:3]}")
