#!/usr/bin/env bash
# trace1.py (the first look only) over "SEED TRUTH KIND" lines into trace1_SEED.txt, on main, one core
cd "$(dirname "$0")"
while read -r s t k; do
  OMP_NUM_THREADS=1 PYTHONPATH=${CLONE:-/work/main} ${PY:-/work/venv/bin/python} trace1.py "$s" "$t" "$k" > "trace1_$s.txt" 2>&1
done
