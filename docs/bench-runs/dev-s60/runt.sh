#!/usr/bin/env bash
# ../dev-s59/trace.py over "SEED TRUTH KIND" lines into trace_SEED.txt (development only)
while read -r s t k; do
  PYTHONPATH=/work/main /work/venv/bin/python ../dev-s59/trace.py "$s" "$t" "$k" > "trace_$s.txt" 2>&1
done
