"""Development probe (session 42): run bench cases on main's finder and record, for every model that reaches
the test bars (worse_on_test, deepened, short_on_test), the test windows' per-window numbers. Diagnosis only."""
import json, sys, time
import numpy as np
import voe.gap.finder as F
import voe.gap.carry_over as C
from voe.gap.check import heldout_pairs
from voe.gap.verify import _residuals_at
from voe.gap.bench import run_case

REC = []

def windows_info(c, p, config):
    pairs = heldout_pairs(p, c.model, config)[0]
    wins = [w for w, _ in pairs]
    before = p.shooter.residuals(wins, None, None)
    after = _residuals_at(p.shooter, pairs, c.model.effect)
    rb = [float(np.sqrt(np.mean(r ** 2))) for r in before]
    ra = [float(np.sqrt(np.mean(r ** 2))) for r in after]
    mv = [float(np.sqrt(np.mean((a - b) ** 2))) for a, b in zip(after, before)]
    n = [int(r.size) for r in before]
    return {"rb": rb, "ra": ra, "move": mv, "size": n}

orig_short, orig_worse, orig_deep = C.short_on_test, C.worse_on_test, C.deepened

def short(c, p, config, z_thr):
    out = orig_short(c, p, config, z_thr)
    if c.model is not None:
        v = c.verification
        REC.append({"bar": "short", "keys": list(c.keys), "kept": out.model is not None, "rmse_b": v.rmse_before,
                    "rmse_a": v.rmse_after, "wmed_b": v.window_median_before, "wmed_a": v.window_median_after,
                    "zb": list(v.z_before), "za": list(v.z_after), "z_thr": z_thr, **windows_info(c, p, config)})
    return out

def worse(c, p, config, z_thr, null_episodes=None, seed=0):
    out = orig_worse(c, p, config, z_thr, null_episodes, seed)
    if c.model is not None:
        v = c.verification
        REC.append({"bar": "worse", "cross_fit": config.cross_fit, "keys": list(c.keys), "kept": out.model is not None,
                    "rmse_b": v.rmse_before, "rmse_a": v.rmse_after, "zb": list(v.z_before), "za": list(v.z_after),
                    "mz_b": v.median_z_before, "mz_a": v.median_z_after, "z_thr": z_thr})
    return out

def deep(p, model, config, z_thr, null_episodes, ver=None, seed=0):
    out = orig_deep(p, model, config, z_thr, null_episodes, ver, seed)
    REC.append({"bar": "deepened", "cross_fit": config.cross_fit, "out": out})
    return out

F.short_on_test, F.worse_on_test, C.deepened = short, worse, deep

orig_look = F.GapFinder._look

def look(self, scene, recordings, config, note, total):
    out = orig_look(self, scene, recordings, config, note, total)
    rounds = []
    for r in self.rounds_:
        top = sorted(r.gains.items(), key=lambda kv: -(kv[1] if np.isfinite(kv[1]) else -9))[:4]
        rounds.append({"before": r.before, "thr": r.threshold, "winner": r.winner, "group": list(r.group),
                       "top": [(k, float(g), float(r.lower.get(k, float("nan")))) for k, g in top]})
    REC.append({"bar": "look", "cross_fit": config.cross_fit, "scheme": self.problem_.split.scheme,
                "rounds": rounds, "names": [e["name"] for e in self.effects_], "verdict": self.verdict_,
                "dropped": [d["effect"] + ": " + d["reason"][:160] for d in self.checked_.dropped]})
    return out

F.GapFinder._look = look

for line in sys.stdin:
    s, t, nk, role = line.split("\t")[:4]
    REC.clear()
    t0 = time.time()
    r = run_case((int(s), t, 1e-3, 3, 12, 3.0, nk))
    print(json.dumps({"seed": int(s), "truth": t, "noise_kind": nk, "role": role, "names": r["names"],
                      "verdict": r["verdict"], "dropped": r["dropped"], "sec": round(time.time() - t0),
                      "rec": REC}), flush=True)
