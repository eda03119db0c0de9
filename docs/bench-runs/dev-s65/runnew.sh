#!/usr/bin/env bash
# ../dev-s59/trace.py over "SEED TRUTH KIND" lines into new_SEED.txt, on main with session 65's change to
# short_on_test (working tree), one core (development seeds only)
cd "$(dirname "$0")"
while read -r s t k; do
  OMP_NUM_THREADS=1 PYTHONPATH=${CLONE:-/work/main} ${PY:-/work/venv/bin/python} ../dev-s59/trace.py "$s" "$t" "$k" > "new_$s.txt" 2>&1
done
