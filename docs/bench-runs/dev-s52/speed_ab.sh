#!/usr/bin/env bash
# alternate main before (fresh51 at bb0e3b6) and after (fresh52: the kick writes selected in C), idle machine,
# the same interpreter (fresh51's CI venv); three runs each
out=/work/dev52/speed_ab.txt;  # copied here as speed_ab.txt
 : > $out
for i in 1 2 3; do for v in fresh51 fresh52; do
  (cd /work/$v && echo "== $v $(git log --oneline -1 | cut -c1-7) $(date -u +%H:%M:%S) load $(cut -d' ' -f1 /proc/loadavg)" && PYTHONPATH=$PWD /work/fresh51/.venv/bin/python bench/gap_speed.py) >> $out 2>&1
done; done
