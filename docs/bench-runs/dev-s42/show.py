import json,glob,sys
import numpy as np
for f in sys.argv[1:]:
    for l in open(f):
        r=json.loads(l)
        print(r['seed'],r['truth'],r['noise_kind'],r['role'],r['names'],r['verdict'],r['dropped'],r['sec'])
        for x in r['rec']:
            if x['bar']=='short':
                rb,ra,mv=map(np.array,(x['rb'],x['ra'],x['move']))
                print('  short',x['keys'],'kept',x['kept'],'gain %.3f'%(1-x['rmse_a']/x['rmse_b']),'wmed %.3f'%(1-x['wmed_a']/x['wmed_b']), 'moves(mm)',np.round(np.sort(mv)[::-1]*1e3,2)[:6])
            elif x['bar']=='look':
                print('  look cf',x['cross_fit'],x['scheme'],x['names'],x['verdict'])
                for rr in x['rounds']:
                    print('    round thr',None if rr['thr'] is None else round(rr['thr'],3),'win',rr['winner'],[(k,round(g,3),round(lo,3)) for k,g,lo in rr['top'][:3]])
                for d in x['dropped']: print('    drop',d)
            elif x['bar']=='deepened':
                if x['out']: print('  deepened',x['cross_fit'],[[round(v,1) for v in o] for o in x['out']])
            else:
                print('  worse cf',x['cross_fit'],x['keys'],'kept',x['kept'],'rmse %.4f->%.4f'%(x['rmse_b'],x['rmse_a']),'mz %.1f->%.1f thr %.1f'%(x['mz_b'],x['mz_a'],x['z_thr']))
