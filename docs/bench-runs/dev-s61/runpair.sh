#!/usr/bin/env bash
# The paired development bench of session 61: seed 6056's cases (stored by cfe3a5b) rerun on the half-step clone,
# in a random order (pair.py --seed 61), one process per core; resumable (development only).
set -u
here="$(cd "$(dirname "$0")" && pwd)"
clone=${CLONE:-/work/dev61}; py=${PY:-/work/venv/bin/python}
store=${STORE:-$here/../gap_bench_s61_seed6056.jsonl}
for i in 0 1; do
  PYTHONPATH=$clone setsid nohup "$py" "$here/pair.py" run "$store" "$here/pair_6056_$i.jsonl" --order random \
      --seed 61 --part "$i/2" >> "$here/pair_6056_$i.log" 2>&1 < /dev/null &
done
