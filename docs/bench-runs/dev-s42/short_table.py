"""The second look's short_on_test records: gain on all test windows, the largest move of a test window's
prediction (mm), and the gain on the windows the law moves by more than 1 mm (the noise sigma)."""
import json, sys
import numpy as np
for f in sys.argv[1:]:
    for l in open(f):
        r = json.loads(l)
        for x in r["rec"]:
            if x["bar"] != "short":
                continue
            rb, ra, mv, n = map(np.array, (x["rb"], x["ra"], x["move"], x["size"]))
            sel = mv > 1e-3
            g_all = 1 - x["rmse_a"] / x["rmse_b"]
            if sel.any():
                b = np.sqrt(np.sum(rb[sel] ** 2 * n[sel]) / n[sel].sum()); a = np.sqrt(np.sum(ra[sel] ** 2 * n[sel]) / n[sel].sum())
                g_sel = f"{100 * (1 - a / b):6.1f} % on {sel.sum()}"
            else:
                g_sel = "not testable"
            print(f"{r['seed']} {r['truth']:<22} {r['noise_kind']:<8} {','.join(x['keys']):<28} kept {x['kept']!s:<5} "
                  f"gain {100 * g_all:6.1f} %  max move {1e3 * mv.max():6.2f} mm  {g_sel}  final {r['names']} {r['verdict']}")
