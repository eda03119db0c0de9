#!/usr/bin/env bash
# deep_tails.py over "SEED TRUTH KIND" lines (catches.txt) into tails_SEED.txt, on the run's clone at f67a261, one
# core (autogroup nice $NICE if set; development only)
[ -n "$NICE" ] && echo "$NICE" > /proc/self/autogroup
cd "$(dirname "$0")"
while read -r s t k; do
  OMP_NUM_THREADS=1 PYTHONPATH=${CLONE:-/work/fresh62} ${PY:-/work/fresh62/.venv/bin/python} deep_tails.py "$s" "$t" "$k" > "tails_$s.txt" 2>&1
done
