import json, sys
from collections import Counter
rows=[json.loads(l) for l in open(sys.argv[1]) if l.strip().endswith('}')]
def red(r): return 100*(1-r['after']/r['before']) if r['before'] else 0.0
kinds=Counter(); same=0; dsame=0; rsame=0; ch=[]
for r in rows:
    o=r['stored']; k=r['truth'] if r['seed']<8367150 else 'clean'
    kinds[k]+=1
    s=(o['names'],o['verdict'])==(r['names'],r['verdict']); same+=s
    dsame+= [str(x) for x in o['dropped']]==[str(x) for x in r['dropped']]
    rsame+= abs(red(o)-red(r))<0.1
    if not s: ch.append(r['seed'])
print(f"{len(rows)} cases rerun ({', '.join(f'{k} {v}' for k,v in kinds.items())}): names and verdict unchanged {same}/{len(rows)}, dropped list unchanged {dsame}/{len(rows)}, test RMSE reduction within 0.1 point {rsame}/{len(rows)}; changed: {ch}")
