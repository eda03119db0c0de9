#!/usr/bin/env bash
# ../dev-s59/trace.py over "SEED TRUTH KIND" lines into trace_SEED.txt, on main (voe/ as at 471f073, the run's code),
# one core (development only: seed 2276 is a development seed since its run ended in session 64)
cd "$(dirname "$0")"
while read -r s t k; do
  OMP_NUM_THREADS=1 PYTHONPATH=${CLONE:-/work/main} ${PY:-/work/venv/bin/python} ../dev-s59/trace.py "$s" "$t" "$k" > "trace_$s.txt" 2>&1
done
