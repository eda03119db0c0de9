"""Summary of fdrift2.py's output files: gusts caught per variant, false drops of the truth, and
(gust, effect) pairs gained and lost against "hyb"."""
import collections
import json
import sys

V = ["hyb", "hyb_s2", "hyb_s1", "hyb_s2f2"]
for f in sys.argv[1:]:
    rows = [json.loads(line) for line in open(f) if line.strip()]
    g = [r for r in rows if r["truth"] == "gust" and not r.get("none")]
    s = [r for r in rows if r["truth"] != "gust" and not r.get("none")]
    if g:
        effs = [k for k in g[0] if k not in ("seed", "truth")]
        print(f, "gusts", len(g))
        for v in V:
            pairs = sum(r[e][v] is not None for r in g for e in effs)
            allc = sum(all(r[e][v] is not None for e in effs) for r in g)
            lost = [(r["seed"], e) for r in g for e in effs if r[e]["hyb"] is not None and r[e][v] is None]
            gained = sum(r[e]["hyb"] is None and r[e][v] is not None for r in g for e in effs)
            print(f"  {v:7s} every effect caught {allc}/{len(g)}  pairs {pairs}/{len(g) * len(effs)}"
                  f"  gained {gained} lost {len(lost)} {lost}")
    if s:
        print(f, "truth-at-true cases", len(s))
        for v in V:
            bad = [(r["seed"], r["truth"], r["truth_eff"][v]) for r in s if r["truth_eff"][v] is not None]
            print(f"  {v:7s} false drops {len(bad)}/{len(s)}", collections.Counter(b[1] for b in bad), bad)
