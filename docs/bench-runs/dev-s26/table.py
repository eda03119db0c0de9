import json
rs=[json.loads(l) for l in open('/work/eval/s26/cross.jsonl')]
print("group      cases  right before  right after  changes")
for g in ('weak','expressed','clean'):
    x=[r for r in rs if r['group']==g]
    if g=='clean':
        print(f"clean      {len(x):5d}   0 false names   {sum(bool(r['names']) for r in x)} false names"); continue
    gain=[r['seed'] for r in x if r['old_named']!=r['truth'] and r['found']==r['truth']]
    lost=[r['seed'] for r in x if r['old_named']==r['truth'] and r['found']!=r['truth']]
    extra=[f"{r['seed']} {'+'.join(r['names'][1:])}" for r in x if len(r['names'])>1]
    print(f"{g:<10} {len(x):5d} {sum(r['old_named']==r['truth'] for r in x):13d} {sum(r['found']==r['truth'] for r in x):12d}  "
          f"gained {' '.join(map(str,gain)) or 'none'}; lost {' '.join(map(str,lost)) or 'none'}; a name beside the truth: {', '.join(extra) or 'none'}")
