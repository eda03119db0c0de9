"""2307140 (floor patch), 2307044 (joint_friction) and 2307046 (mass) on the final code (past_grid with
its fold condition), --cross-fit, as the bench runs them."""
import json
from concurrent.futures import ProcessPoolExecutor
from voe.gap.bench import run_case

CASES = [(2307140, "floor_patch"), (2307044, "joint_friction"), (2307046, "mass")]
if __name__ == "__main__":
    with ProcessPoolExecutor(2) as ex:
        for (s, t), r in zip(CASES, ex.map(run_case, [(s, t, 1e-3, 3, 12, 3.0, "white", True) for s, t in CASES])):
            print(s, t, "named", r["names"], r["verdict"], "param_err", r["param_error"], "covered", r["covered"],
                  "dropped", r["dropped"], "located", r["located"], flush=True)
