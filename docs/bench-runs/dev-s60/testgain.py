"""Test-split RMSE gain (1 - after/before) of right names, clean false names and out-of-library names in the stored
records of the finished untouched runs (development only): would a "no name unless the test error falls" rule
separate them?

    PYTHONPATH=<clone> python testgain.py   (from the repository root)
"""
import json,glob,numpy as np,re

from voe.gap.bench_score import misnamed
rows=[]
for f in sorted(glob.glob('docs/bench-runs/gap_bench_s*_seed*.jsonl')):
    s=int(re.search(r'_s(\d+)_',f).group(1))
    for l in open(f):
        d=json.loads(l)
        if 'truth' not in d: continue
        d['sess']=s; rows.append(d)
def g(r): return 1-r['after']/r['before'] if r['before'] else np.nan
for lab,sel in [('recent s52+',lambda r:r['sess']>=52),('all',lambda r:True)]:
    R=[r for r in rows if sel(r)]
    right=[r for r in R if r['kind']=='single' and r['truth']!='none' and r['found']==r['truth']]
    comp=[r for r in R if r['kind']=='compound' and r['names']]
    fd=[r for r in R if r['truth']=='none' and r['n_effects']>0]
    mis=[r for r in R if r['kind']=='outside' and misnamed(r)]
    outok=[r for r in R if r['kind']=='outside' and r['names'] and not misnamed(r)]
    for nm,L in [('right singles',right),('compounds named',comp),('clean FD named',fd),('OOL misnamed',mis),('OOL named ok',outok)]:
        G=np.array([g(r) for r in L])
        print(lab,nm,len(L),'test gain quantiles 0,1,5,10,50%:',np.round(np.nanpercentile(G,[0,1,5,10,50]),3) if len(G) else '', ' n<0.05:',int((G<0.05).sum()),' n<0:',int((G<0).sum()))
    print('  FD gains:',sorted(np.round([g(r) for r in fd],3)))
    print('  OOL misnamed gains:',sorted((round(g(r),3),r['truth'],r['names'][0]) for r in mis))
    low=[(r['seed'],r['truth'],round(g(r),3)) for r in right if g(r)<0.05]
    print('  right singles gain<5%:',low)
