#!/usr/bin/env bash
# start_bias.py on the three windows where the truth itself departs (development only; the run's clone at f67a261)
echo 19 > /proc/self/autogroup
cd "$(dirname "$0")"
export PYTHONPATH=${CLONE:-/work/fresh62} OMP_NUM_THREADS=1
PY=${PY:-/work/fresh62/.venv/bin/python}
{
  echo "== 3829037 rolling_resistance, test window 1 (episode 11, samples 12-112)"
  $PY start_bias.py 3829037 rolling_resistance white 11 12 112
  echo "== 6056094 friction, test window 0 (episode 10, samples 23-123)"
  $PY start_bias.py 6056094 friction white 10 23 123
  echo "== 3829008 point_attractor, test window 0 (episode 10, samples 5-105; the case's start fit is +-5 samples)"
  $PY start_bias.py 3829008 point_attractor white 10 5 105
} > start_bias.txt 2>&1
PYTHONPATH=$PYTHONPATH:../dev-s62 $PY window_probe.py 3829037 rolling_resistance white 1 > window_probe_3829037.txt 2>&1
