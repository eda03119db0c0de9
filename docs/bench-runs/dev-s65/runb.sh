#!/usr/bin/env bash
# ../dev-s59/trace.py over "SEED TRUTH KIND" lines into b_SEED.txt, on branch s65b (the check reports the search's
# own earlier model: voe.gap.check._earlier), one core (development seeds only)
cd "$(dirname "$0")"
while read -r s t k; do
  OMP_NUM_THREADS=1 PYTHONPATH=${CLONE:-/work/s65b} ${PY:-/work/venv/bin/python} ../dev-s59/trace.py "$s" "$t" "$k" > "b_$s.txt" 2>&1
done
