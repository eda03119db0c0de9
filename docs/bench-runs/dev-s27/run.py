"""Run the picked development cases with the finder on PYTHONPATH; append results to OUT (resumable)."""
import json, sys, time, os
from voe.gap.bench import run_case
from voe.parallel import parallel_map
out = sys.argv[1]
groups = sys.argv[2].split(',') if len(sys.argv) > 2 else ['ool', 'compound']
cases = sorted([c for c in json.load(open('/work/eval/s27/cases.json')) if c['group'] in groups], key=lambda c: groups.index(c['group']))
done = set()
if os.path.exists(out):
    done = {json.loads(l)['seed'] for l in open(out)}
todo = [c for c in cases if c['seed'] not in done]
meta = {c['seed']: c for c in cases}
def one(args):
    t0 = time.process_time(); w0 = time.time()
    r = run_case(args)
    r['cpu'] = time.process_time() - t0; r['wall'] = time.time() - w0
    return r
args = [(c['seed'], c['truth'], 1e-3, 3, 12, 3.0, c['nk'], True) for c in todo]
print(len(todo), 'to run', flush=True)
for r in parallel_map(one, args, 2):
    c = meta[r['seed']]
    r['group'] = c['group']; r['old_named'] = c['named']; r['old_k'] = c['k']; r['old_W'] = c['W']
    with open(out, 'a') as f:
        f.write(json.dumps(r) + '\n')
    print(r['seed'], c['group'], r['truth'], 'old', c['named'], 'new', ','.join(r['names']) or '-', r['verdict'], 'expr', r.get('expressed'), f"{r['wall']:.0f}s", flush=True)
