#!/usr/bin/env bash
# ../dev-s59/trace.py over "SEED TRUTH KIND" lines into trace_SEED.txt, on the clone at cfe3a5b (development only)
cd "$(dirname "$0")"
while read -r s t k; do
  PYTHONPATH=${CLONE:-/work/fresh60} ${PY:-/work/venv/bin/python} ../dev-s59/trace.py "$s" "$t" "$k" > "trace_$s.txt" 2>&1
done
