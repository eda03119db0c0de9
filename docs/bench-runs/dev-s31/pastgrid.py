"""Development check of ``voe.gap.check.past_grid`` (session 31): rerun every stored case whose
finder named nothing and dropped a one-parameter effect (only there can ``beyond_grid`` have
fired), on seeds 2307 (cross-fitted, development since session 31 traced it) and 2250 (default
finder), and log each ``past_grid`` call. Cases outside this list cannot change."""
import json, sys, time
from concurrent.futures import ProcessPoolExecutor
import voe.gap.check as check
from voe.gap.bench import run_case

SCALAR = {"angular_damping", "friction", "joint_friction", "joint_damping", "linear_drag", "quadratic_drag",
          "mass[ball]", "mass[box]", "restitution", "rolling_resistance"}
LOG = "/work/eval/s31/pastgrid_calls.jsonl"
_orig = check.past_grid


def logged(fitter, model, bar, bounded, ctx):
    out = _orig(fitter, model, bar, bounded, ctx)
    with open(LOG, "a") as f:
        f.write(json.dumps({"seed": SEED, "at": [float(v[0]) for v in model.fold_params],
                            "out": out if isinstance(out, str) else
                            {"params": [float(v[0]) for v in out[0].fold_params], "lo": out[1].tolist(),
                             "hi": out[2].tolist()}}) + "\n")
    return out


check.past_grid = logged
SEED = None


def one(args):
    global SEED
    SEED = args[0]
    t0 = time.time()
    r = run_case(args)
    r["wall"] = time.time() - t0
    return r


if __name__ == "__main__":
    jobs = []
    for path, cf in (("/work/eval/s30/gap_2307_crossfit.jsonl", True),
                     ("/work/main/docs/bench-runs/gap_bench_s25_seed2250.jsonl", False)):
        rows = [json.loads(l) for l in open(path)][1:]
        for r in rows:
            if not r["names"] and set(r["dropped"]) & SCALAR:
                jobs.append(((r["seed"], r["truth"], 1e-3, 3, 12, 3.0, r["noise_kind"], cf), r))
    print(len(jobs), "cases", flush=True)
    with ProcessPoolExecutor(2) as ex, open("/work/eval/s31/pastgrid.jsonl", "a") as out:
        for (args, old), new in zip(jobs, ex.map(one, [a for a, _ in jobs])):
            line = {"seed": args[0], "truth": args[1], "cross_fit": args[7], "old": old["names"], "old_verdict": old["verdict"],
                    "new": new["names"], "new_verdict": new["verdict"], "dropped": new["dropped"], "wall": round(new["wall"]),
                    "param_error": new["param_error"], "covered": new["covered"]}
            out.write(json.dumps(line) + "\n"); out.flush()
            print(line, flush=True)
