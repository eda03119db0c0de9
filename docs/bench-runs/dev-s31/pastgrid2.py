"""Development check of ``voe.gap.check.past_grid``, second set (session 31): the default finder
(three-way split) on every earlier stored case (seeds 6685, 1078, 1967; all development) that was
out-of-library or clean, named nothing and dropped a one-parameter effect; each past_grid call logged."""
import json, sys, time
sys.argv = sys.argv[:1]
import pastgrid as pg
from concurrent.futures import ProcessPoolExecutor

CASES = [(1078141, "gust", "white"), (1078143, "gust", "white"), (6685146, "floor_patch", "white"),
         (6685149, "gust", "white"), (1967000, "none", "white"), (1967209, "none", "white"), (1967215, "none", "white"),
         (1967250, "none", "coloured"), (1967264, "none", "coloured"), (1967300, "none", "coloured"),
         (1967319, "none", "white"), (1078152, "none", "coloured"), (1078190, "none", "coloured"),
         (1078219, "none", "white"), (1078221, "none", "white"), (1078223, "none", "white"), (1078225, "none", "white"),
         (6685013, "none", "white"), (6685166, "none", "coloured"), (6685220, "none", "white")]

if __name__ == "__main__":
    jobs = [(s, t, 1e-3, 3, 12, 3.0, nk, False) for s, t, nk in CASES]
    with ProcessPoolExecutor(2) as ex, open("/work/eval/s31/pastgrid2.jsonl", "a") as out:
        for args, new in zip(jobs, ex.map(pg.one, jobs)):
            line = {"seed": args[0], "truth": args[1], "new": new["names"], "new_verdict": new["verdict"],
                    "dropped": new["dropped"], "wall": round(new["wall"])}
            out.write(json.dumps(line) + "\n"); out.flush()
            print(line, flush=True)
