"""Pick the development cases for the split experiment (session 26). Seeds 6685, 1078, 1967, 2250 are all development now."""
import glob, re, json, numpy as np
rows = {}
for f in sorted(glob.glob('/work/main/docs/bench-runs/gap_bench_s2[2-5]_seed*.txt')):
    for line in open(f):
        m = re.match(r'\s+case (\d+): true (\S+)\s+(\S+)\s+named (\S+)\s+(\S+).*?(?:expressed (\d+)/(\d+))?\s*$', line)
        if m:
            s = int(m.group(1)); rows[s] = dict(seed=s, truth=m.group(2), nk=m.group(3), named=m.group(4), verdict=m.group(5),
                                         k=None if m.group(6) is None else int(m.group(6)), W=None if m.group(7) is None else int(m.group(7)))
cyc = [r for r in rows.values() if r['seed'] % 1000 < 130]
weak = [r for r in cyc if r['k'] is not None and r['k'] < 3]
expr = [r for r in cyc if r['k'] is not None and r['k'] >= 3]
rng = np.random.default_rng(26)
sample = [expr[i] for i in sorted(rng.choice(len(expr), 30, replace=False))]
clean = [rows[s] for s in range(2250150, 2250170)]
out = [dict(r, group=g) for g, rs in (('weak', weak), ('expressed', sample), ('clean', clean)) for r in rs]
json.dump(out, open('/work/eval/s26/cases.json', 'w'), indent=0)
print(len(weak), len(sample), len(clean), sum(r['named'] == r['truth'] for r in sample), [r['nk'] for r in clean][:4])
