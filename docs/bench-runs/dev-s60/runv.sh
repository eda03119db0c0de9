#!/usr/bin/env bash
# vproj.py over a list of "SEED TRUTH KIND R" lines (development only)
while read -r s t k r; do
  PYTHONPATH=/work/main /work/venv/bin/python vproj.py "$s" "$t" "$k" "$r" > "vproj_$s.txt" 2>&1
done
