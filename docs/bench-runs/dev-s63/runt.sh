#!/usr/bin/env bash
# ../dev-s59/trace.py over "SEED TRUTH KIND" lines into trace_SEED.txt, on the run's clone at f67a261, one core at
# autogroup nice 19 (development only: seed 3829 is a development seed since its run ended in session 63)
echo 19 > /proc/self/autogroup
cd "$(dirname "$0")"
while read -r s t k; do
  OMP_NUM_THREADS=1 PYTHONPATH=${CLONE:-/work/fresh62} ${PY:-/work/fresh62/.venv/bin/python} ../dev-s59/trace.py "$s" "$t" "$k" > "trace_$s.txt" 2>&1
done
