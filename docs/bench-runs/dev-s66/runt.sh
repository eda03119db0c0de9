#!/usr/bin/env bash
# Traces of development cases on main (563c322: stand-ins left out) at the lowest autogroup share, so that the
# untouched run beside them keeps the cores (session 66). Development only.
echo 19 > /proc/self/autogroup
cd "$(dirname "$0")"
for c in "5905133 rolling_resistance+mass white" "5905132 constant_acceleration+angular_damping white"; do
  set -- $c
  PYTHONPATH=/work/main nice -n 19 /work/venv/bin/python ../dev-s59/trace.py "$1" "$2" "$3" > "trace_$1.txt" 2>&1
done
