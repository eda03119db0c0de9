"""Time one kick (8 windows of the speed case, 2 bodies each) and its parts; best of 7 x 2000 calls."""
import time, sys
import numpy as np
from voe.gap.bench import make_case
from voe.gap.shooting import local_state
from voe.gap.effects import EFFECTS
from voe.gap.rollout import tiled, run_many
from voe.sim import lockstep as L
from voe.sim.scenefile import SimWorld
case = make_case(np.random.default_rng(3), "quadratic_drag", episodes=20, duration=5.0)
starts, times = [], []
for e in case.episodes[:8]:
    pose0, vel0, _ = local_state(e, 100)
    starts.append((pose0, vel0)); times.append(e.t[100:201])
name = sys.argv[1] if len(sys.argv) > 1 else "quadratic_drag"
effs = [EFFECTS.get(n)() for n in name.split("+")]
eff = effs[0] if len(effs) == 1 else sum(effs[1:], effs[0])
p = np.array([0.12, 0.05, 1e-3][:eff.n_params]) if name != "quadratic_drag" else np.array([0.12])
worlds = [SimWorld(case.scene, p0, v0) for p0, v0 in starts]
force = eff.prepare(p, tiled(case.scene, 8))
rows = L._rows(worlds)
bufs = L._buffers(9)
dts = np.full((300, 8), 4e-3)
kick = L._Kick(worlds, force, bufs[8], rows, dts)
def best(fn, n=2000, r=7):
    b = 1e9
    for _ in range(r):
        t0 = time.perf_counter()
        for _ in range(n):
            fn()
        b = min(b, (time.perf_counter() - t0) / n)
    return b * 1e6
print(f"kick {best(lambda: kick(0)):.1f} us; _state {best(kick._state):.1f} us")
raw = kick._state()
st = L.SimState(raw[:, 0:2], raw[:, 3:5], raw[:, 2], raw[:, 5], kick.mass, kick.moment, kick.gravity, kick._contact)
print(f"SimState {best(lambda: L.SimState(raw[:, 0:2], raw[:, 3:5], raw[:, 2], raw[:, 5], kick.mass, kick.moment, kick.gravity, kick._contact)):.1f} us; force {best(lambda: force(st)):.1f} us")
t0 = time.perf_counter(); [run_many(case.scene, starts, times, 1e-3, eff, p) for _ in range(10)]
tm = min((lambda: (lambda t0: (run_many(case.scene, starts, times, 1e-3, eff, p), time.perf_counter() - t0)[1])(time.perf_counter()))() for _ in range(15))
tn = min((lambda: (lambda t0: (run_many(case.scene, starts, times, 1e-3, None, None), time.perf_counter() - t0)[1])(time.perf_counter()))() for _ in range(15))
print(f"run_many 8 windows: {name} {tm*1e3:.2f} ms, nominal {tn*1e3:.2f} ms")
from pymunk._chipmunk import ffi, lib
v_new = (raw[:, 3:5] + 0.0).tolist()
set_v = lib.cpBodySetVelocity
print(f"set_v x{len(kick.ptrs)} {best(lambda: L._drain(map(set_v, kick.ptrs, v_new))):.1f} us; tolist {best(lambda: (raw[:, 3:5] + 0.0).tolist()):.1f} us; count_nonzero {best(lambda: np.count_nonzero(raw)):.2f} us")
SET = ffi.addressof(lib, "pmSpaceBodySetIteratorFuncBatched")
d = ffi.new("pmBatchedData *"); d.fields = L._F.VELOCITY.value; d.floatArray = bufs[8]._float_arr; d.intArray = bufs[8]._int_arr
sp = [w.space._space for w in worlds]
arr = bufs[8]._float_arr
def batch_set():
    arr.num = 0
    for s in sp:
        lib.cpSpaceEachBody(s, SET, d)
print(f"batch set x{len(sp)} {best(batch_set):.1f} us")
z2, z1 = np.zeros((16, 2)), np.zeros(16)
def rl(force):
    ws = [SimWorld(case.scene, p0, v0) for p0, v0 in starts]
    t0 = time.perf_counter(); L.run_lockstep(ws, times, 1e-3, force); return time.perf_counter() - t0
for lab, fc in (("none", None), ("zero force", lambda st: (z2, z1)), ("drag", force)):
    print(f"run_lockstep {lab}: {min(rl(fc) for _ in range(15))*1e3:.2f} ms")
orig_call = L._Kick.__call__
L._Kick.__call__ = lambda self, m: None
print(f"run_lockstep zero force, kick a no-op: {min(rl(lambda st: (z2, z1)) for _ in range(15))*1e3:.2f} ms")
L._Kick.__call__ = orig_call
keys = [(np.ascontiguousarray(t, dtype=float).tobytes(), 1e-3) for t in times]
print("segments nominal", len(L._segments(tuple(keys), 0).segments), "with kicks", len(L._segments(tuple(keys), 4).segments))
cnt = {"all": 0, "some": 0, "none": 0}
def counting(st):
    f, t = force(st)
    nz = np.count_nonzero(f); cnt["all" if nz == f.size else "some" if nz else "none"] += 1
    return f, t
rl(counting); print("drag kicks by path", cnt)
for c in (0.0, 1e-12, 0.12, 1.0):
    fc = eff.prepare(np.array([c]), tiled(case.scene, 8))
    print(f"run_lockstep drag c={c}: {min(rl(fc) for _ in range(15))*1e3:.2f} ms")
