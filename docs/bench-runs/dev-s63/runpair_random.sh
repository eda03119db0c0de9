#!/usr/bin/env bash
# The paired bench's second part: seed 3829's whole plan in a random order (dev-s61's pair.py --order random --seed
# 63), one process per core, on a clone of main with the start refit; resumable; cases already in a pair_*.jsonl
# beside it are skipped (development only).
set -u
here="$(cd "$(dirname "$0")" && pwd)"
clone=${CLONE:-/work/fresh63d}; py=${PY:-/work/fresh62/.venv/bin/python}
store=${STORE:-$here/../gap_bench_s63_seed3829.jsonl}
for i in 0 1; do
  PYTHONPATH=$clone setsid nohup "$py" "$here/../dev-s61/pair.py" run "$store" "$here/pair_3829_r$i.jsonl" --order random \
      --seed 63 --part "$i/2" >> "$here/pair_3829_r$i.log" 2>&1 < /dev/null &
done
