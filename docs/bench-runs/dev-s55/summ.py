import json, sys, collections
V = ["cur", "cp", "both", "both_pooled", "slot_pooled", "cp_pooled", "both_union", "slot_union", "hyb"]
for f in sys.argv[1:]:
    rows = [json.loads(l) for l in open(f) if l.strip()]
    g = [r for r in rows if r["truth"] == "gust" and not r.get("none")]
    s = [r for r in rows if r["truth"] != "gust" and not r.get("none")]
    if g:
        effs = [k for k in g[0] if k not in ("seed", "truth")]
        print(f, "gusts", len(g))
        for v in V:
            per = {e: sum(r[e].get(v) is not None for r in g) for e in effs}
            allc = sum(all(r[e].get(v) is not None for e in effs) for r in g)
            print(f"  {v:12s} all effects caught {allc}/{len(g)}  per effect {per}")
    if s:
        print(f, "truth-at-true cases", len(s))
        for v in V:
            bad = [(r["seed"], r["truth"], r["truth_eff"][v]) for r in s if r["truth_eff"].get(v) is not None]
            print(f"  {v:12s} false drops {len(bad)}/{len(s)}", collections.Counter(b[1] for b in bad))
