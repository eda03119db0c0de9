import numpy as np, sys
sys.path.insert(0, '/work/dev29')
from jit import jitter_stats
from voe.gap.recordings import load_recordings
from voe.gap.scene import load_scene
from voe.gap.shooting import noise_model
d = '/work/main/data/real/single-pendulum/'
spec, _, _ = load_scene(d + 'scene.json')
eps = load_recordings(d + 'recordings.csv', spec)
print(len(eps), [len(e.t) for e in eps], [float(np.std(np.diff(e.t))) for e in eps][:3], float(np.median(np.diff(eps[0].t))))
s, ph = noise_model(eps); print(s, ph)
print(jitter_stats(eps, s))
