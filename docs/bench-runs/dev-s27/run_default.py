"""Main's default finder on the out-of-library cases of seeds 6685 and 1078 (their stored names came from older code); one process."""
import json, sys, time, os
from voe.gap.bench import run_case
out = sys.argv[1]
cases = [c for c in json.load(open('/work/eval/s27/cases.json')) if c['group'] == 'ool' and c['seed'] // 1000 in (6685, 1078)]
done = {json.loads(l)['seed'] for l in open(out)} if os.path.exists(out) else set()
for c in cases:
    if c['seed'] in done: continue
    w0 = time.time(); r = run_case((c['seed'], c['truth'], 1e-3, 3, 12, 3.0, c['nk']))
    r['wall'] = time.time() - w0; r['group'] = c['group']; r['old_named'] = c['named']
    with open(out, 'a') as f: f.write(json.dumps(r) + '\n')
    print(r['seed'], r['truth'], 'stored', c['named'], 'main default', ','.join(r['names']) or '-', r['verdict'], f"{r['wall']:.0f}s", flush=True)
