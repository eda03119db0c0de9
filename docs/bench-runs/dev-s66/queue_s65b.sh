#!/usr/bin/env bash
# Start the s65b paired bench (seed 5905's cases whose line drops a name) once the s66 bench has ended.
here="$(cd "$(dirname "$0")" && pwd)"
while pgrep -f "pair_s66_" > /dev/null; do sleep 20; done
S=$(cat "$here/sel_drops.txt")
for i in 0 1; do
  PYTHONPATH=/work/s65b setsid nohup /work/venv/bin/python "$here/../dev-s61/pair.py" run "$here/../gap_bench_s66_seed5905.jsonl" \
      "$here/s65b/pair_s65b_$i.jsonl" --seeds "$S" --part "$i/2" >> "$here/s65b/pair_s65b_$i.log" 2>&1 < /dev/null &
done
