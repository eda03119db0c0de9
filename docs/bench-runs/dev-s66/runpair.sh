#!/usr/bin/env bash
# The paired development bench of session 66: branch s65b (6cdc292 + earlier_model.patch, with a dev-only line that
# prints "[earlier fired]" to stderr when the check reports the search's own earlier model) rerun on chosen cases
# of a finished store, one process per core (pair.py --part i/2); resumable. Development only.
#   SEEDS=a,b,c STORE=<store.jsonl> TAG=<name> bash runpair.sh
set -u
here="$(cd "$(dirname "$0")" && pwd)"
clone=${CLONE:-/work/s65b}; py=${PY:-/work/venv/bin/python}
pair=$here/../dev-s61/pair.py
for i in 0 1; do
  PYTHONPATH=$clone setsid nohup "$py" "$pair" run "$STORE" "$here/pair_${TAG}_$i.jsonl" --seeds "$SEEDS" \
      --part "$i/2" >> "$here/pair_${TAG}_$i.log" 2>&1 < /dev/null &
done
