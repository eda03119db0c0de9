#!/usr/bin/env bash
# dev-s62's guards_at_truth.py over seed 3829's cycle cases, then reps_at_truth.py where `deepened` drops the truth
# (development only; the run's clone at f67a261; one core at autogroup nice 19)
echo 19 > /proc/self/autogroup
cd "$(dirname "$0")"
export PYTHONPATH=${CLONE:-/work/fresh62}:../dev-s62 OMP_NUM_THREADS=1
PY=${PY:-/work/fresh62/.venv/bin/python}
$PY ../dev-s62/guards_at_truth.py ../gap_bench_s63_seed3829.jsonl > gt_s63_seed3829.jsonl 2> gt_s63_seed3829.log
python3 ../dev-s62/gt_score.py gt_s63_seed3829.jsonl > gt_score.txt
seeds=$(python3 -c "import json; print(' '.join(str(r['seed']) for r in map(json.loads, open('gt_s63_seed3829.jsonl')) if 'itself a departure' in r['why']))")
[ -n "$seeds" ] && $PY ../dev-s62/reps_at_truth.py ../gap_bench_s63_seed3829.jsonl $seeds > reps_at_truth.txt 2>&1
