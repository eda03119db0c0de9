"""Pick the session 27 development cases: out-of-library (i = 138-149) and compound (i = 130-137) cases of seeds 6685, 1078, 1967, 2250 (all development)."""
import glob, re, json
rows = {}
for f in sorted(glob.glob('/work/main/docs/bench-runs/gap_bench_s2[2-5]_seed*.txt')):
    for line in open(f):
        m = re.match(r'\s+case (\d+): true (\S+)\s+(\S+)\s+named (\S+)\s+(\S+)', line)
        if m:
            s = int(m.group(1)); rows[s] = dict(seed=s, truth=m.group(2), nk=m.group(3), named=m.group(4), verdict=m.group(5), k=None, W=None)
ool = [r for s, r in sorted(rows.items()) if 138 <= s % 1000 <= 149]
comp = [r for s, r in sorted(rows.items()) if 130 <= s % 1000 <= 137]
out = [dict(r, group=g) for g, rs in (('ool', ool), ('compound', comp)) for r in rs]
json.dump(out, open('/work/eval/s27/cases.json', 'w'), indent=0)
print(len(ool), len(comp))
