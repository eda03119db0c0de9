"""Per-case departure p-values of every design tried (development seeds only), from the dumps
(dep/*.npz: dump20.py, dep_local/*.npz: dump_local.py), written as one JSON line per case."""
import json, numpy as np
from voe.gap.departure import _signed_rank_p, tail_p
rows = [json.loads(l) for l in open('/work/eval/s28/local.jsonl')]
with open('/work/eval/s28/pvalues.jsonl', 'w') as fh:
    for r in rows:
        d = np.load(f"/work/eval/s28/dep_local/{r['seed']}.npz", allow_pickle=False)
        e = np.load(f"/work/eval/s28/dep/{r['seed']}.npz", allow_pickle=False)
        sr = _signed_rank_p(d['zd1'], d['zn1'])
        out = dict(seed=r['seed'], truth=r['truth'], noise=r['nk'], located=r['located'], signed_rank=sr,
                   main_tail05_ep4=tail_p(e['zd05'], e['zn05'][:4]))
        for R in (4, 10, 20):
            out[f'tail1_ep{R}'] = tail_p(e['zd1'], e['zn1'][:R])
            out[f'tail05_ep{R}'] = tail_p(e['zd05'], e['zn05'][:R])
            out[f'tail1_local{R}'] = tail_p(d['zd1'], d['zl1'][:R])
        fh.write(json.dumps(out) + '\n')
