#!/usr/bin/env bash
# second_look_probe.py over "SEED TRUTH KIND" lines into sl_SEED.txt, on main, one core (development seeds only)
cd "$(dirname "$0")"
while read -r s t k; do
  OMP_NUM_THREADS=1 PYTHONPATH=${CLONE:-/work/main} ${PY:-/work/venv/bin/python} second_look_probe.py "$s" "$t" "$k" > "sl_$s.txt" 2>&1
done
