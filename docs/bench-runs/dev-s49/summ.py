import json, sys
for f in sys.argv[1:]:
    for l in open(f):
        d = json.loads(l)
        t = set(d["truth"].split("+")) - {"none"}
        same = d["names"] == d["stored"] and d["verdict"] == d["stored_verdict"]
        ok = lambda n: t <= set(n) if t else not n
        print(f"{d['case']} {d['truth'][:34]:34s} moved {d['moved']:2d} {'same' if same else 'DIFF'} now {'ok ' if ok(d['names']) else 'BAD'} {d['names']} {d['verdict'][:5]} | stored {'ok ' if ok(d['stored']) else 'BAD'} {d['stored']} {d['stored_verdict'][:5]} {d['sec']}s")
