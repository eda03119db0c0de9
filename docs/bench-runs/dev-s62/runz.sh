#!/usr/bin/env bash
# testz.py over "SEED TRUTH KIND" lines into testz_SEED.txt (development only; the half-step clone)
cd "$(dirname "$0")"
while read -r s t k; do
  PYTHONPATH=${CLONE:-/work/fresh62} ${PY:-/work/fresh62/.venv/bin/python} testz.py "$s" "$t" "$k" > "testz_$s.txt" 2>&1
done
