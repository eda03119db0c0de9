import json, sys
from voe.gap.bench import run_case
for line in open(sys.argv[1]):
    s, t = line.split()
    r = run_case((int(s), t, 1e-3, 3, 12, 3.0, "white"))
    print(json.dumps(r), flush=True)
