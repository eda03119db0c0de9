#!/usr/bin/env bash
# alternate the finder before (wtbase) and after (wt50) the patchless reuse, idle machine
out=/work/dev51/speed_idle.txt; : > $out
for i in 1 2 3; do for v in wtbase wt50; do
  (cd /work/$v && echo "== $v $(git log --oneline -1 | cut -c1-7) $(date -u +%H:%M:%S) load $(cut -d' ' -f1 /proc/loadavg)" && PYTHONPATH=$PWD /work/fresh49/.venv/bin/python bench/gap_speed.py) >> $out 2>&1
done; done
