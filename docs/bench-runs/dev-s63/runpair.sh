#!/usr/bin/env bash
# A paired development bench of session 63: seed 3829's out-of-library and compound cases (stored by f67a261) rerun on
# branch s63 (deepened's start refit), two processes (dev-s61's pair.py; development only).
set -u
here="$(cd "$(dirname "$0")" && pwd)"
clone=${CLONE:-/work/fresh63c}; py=${PY:-/work/fresh62/.venv/bin/python}
store=${STORE:-$here/../gap_bench_s63_seed3829.jsonl}
a=3829138,3829140,3829142,3829144,3829146,3829148,3829139,3829141,3829132,3829134,3829136
b=3829143,3829145,3829147,3829149,3829008,3829133,3829135,3829137,3829131,3829130
for i in a b; do
  PYTHONPATH=$clone setsid nohup "$py" "$here/../dev-s61/pair.py" run "$store" "$here/pair_3829_$i.jsonl" --seeds "${!i}" \
      >> "$here/pair_3829_$i.log" 2>&1 < /dev/null &
done
