#!/usr/bin/env bash
# dev-s59's trace.py over "SEED TRUTH KIND" lines into new_SEED.txt, on branch s63 (deepened asks start_noise;
# development only)
cd "$(dirname "$0")"
while read -r s t k; do
  OMP_NUM_THREADS=1 PYTHONPATH=${CLONE:-/work/main} ${PY:-/work/fresh62/.venv/bin/python} ../dev-s59/trace.py "$s" "$t" "$k" > "new_$s.txt" 2>&1
done
