#!/usr/bin/env bash
# cases.py on the half-step clone (/work/half) for development cases of several stores, one at a time (development only)
set -u
cd "$(dirname "$0")"
run() { PYTHONPATH=/work/half nice -n 5 /work/venv/bin/python cases.py "$@"; }
run ../gap_bench_s58_seed4497.jsonl 4497026 4497167 4497215 4497285 >> half_cases.jsonl 2>> half_cases.log
run ../gap_bench_s52_seed7241.jsonl 7241329 >> half_cases.jsonl 2>> half_cases.log
run ../gap_bench_s53_seed3511.jsonl 3511310 >> half_cases.jsonl 2>> half_cases.log
run ../gap_bench_s54_seed9260.jsonl 9260158 9260277 >> half_cases.jsonl 2>> half_cases.log
run ../gap_bench_s56_seed1829.jsonl 1829321 1829148 >> half_cases.jsonl 2>> half_cases.log
run ../gap_bench_s58_seed4497.jsonl $(seq 4497138 4497149) >> half_cases.jsonl 2>> half_cases.log
run ../gap_bench_s58_seed4497.jsonl $(seq 4497000 4497025) >> half_cases.jsonl 2>> half_cases.log
run ../gap_bench_s58_seed4497.jsonl $(seq 4497130 4497137) >> half_cases.jsonl 2>> half_cases.log
