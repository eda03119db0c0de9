"""restart.py with the half-step correction on (argv[1]: the substep, or none) on a clone with halfstep.patch applied
(development only): PYTHONPATH=<patched clone> python halfstep_restart.py 0.001 SEED TRUTH KIND EPISODE"""
import sys
import voe.gap.shooting as S
S.HALF_STEP = float(sys.argv[1]) if sys.argv[1] != "none" else None
sys.argv = ["restart.py"] + sys.argv[2:]
exec(open('/work/main/docs/bench-runs/dev-s60/restart.py').read().split('"""', 2)[2])
