#!/usr/bin/env bash
# Traces of development cases on main (563c322) at the lowest autogroup share, so that the untouched run
# beside them keeps the cores (session 67). Development only (seed 5905 is a development seed).
echo 19 > /proc/self/autogroup
cd "$(dirname "$0")"
for c in "$@"; do
  set -- $c
  PYTHONPATH=/work/main nice -n 19 /work/venv/bin/python ../dev-s59/trace.py "$1" "$2" "$3" > "trace_$1.txt" 2>&1
done
