#!/usr/bin/env bash
# guards_at_truth.py over the cycle cases of the last five untouched runs (development only; the half-step clone)
cd "$(dirname "$0")"
for st in s53_seed3511 s54_seed9260 s56_seed1829 s58_seed4497 s61_seed6056; do
  PYTHONPATH=${CLONE:-/work/fresh62} ${PY:-/work/fresh62/.venv/bin/python} guards_at_truth.py ../gap_bench_$st.jsonl \
      > "gt_$st.jsonl" 2> "gt_$st.log"
done
