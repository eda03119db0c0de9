"""Run bench cases by seed as the bench does (run_case with the bench's defaults) and print each record."""
import json, sys
from voe.gap.bench import run_case
for s in map(int, sys.argv[2:]):
    r = run_case((s, sys.argv[1], 1e-3, 3, 12, 3.0, "white"))
    print(json.dumps(r), flush=True)
