"""Run bench cases given as SEED:TRUTH:NOISE with this checkout's finder (diagnosis only).
Usage: PYTHONPATH=<checkout> python adhoc.py OUT SEED:TRUTH:NOISE [...] [--jobs 2]"""
import json
import sys
from concurrent.futures import ProcessPoolExecutor

from voe.gap.bench import run_case

if __name__ == "__main__":
    out = sys.argv[1]
    jobs = int(sys.argv[sys.argv.index("--jobs") + 1]) if "--jobs" in sys.argv else 2
    args = [(int(s), t, 1e-3, 3, 12, 3.0, n) for s, t, n in (a.split(":") for a in sys.argv[2:] if a.count(":") == 2)]
    with ProcessPoolExecutor(jobs) as ex, open(out, "a") as fh:
        for r in ex.map(run_case, args):
            fh.write(json.dumps(r) + "\n")
            fh.flush()
            red = 100 * (1 - r["after"] / r["before"]) if r["before"] else float("nan")
            print(r["seed"], r["truth"], r["noise_kind"], r["names"], r["verdict"], f"{red:.1f} %", "dropped", r["dropped"], flush=True)
