#!/usr/bin/env bash
# stand_in.py over development cases, one after another, at nice 19 (session 66).
cd "$(dirname "$0")"
run() { out=$1; shift; PYTHONPATH=${CLONE:-/work/fresh65} nice -n 19 /work/venv/bin/python stand_in.py "$@" > "$out" 2>&1; }
run si_2276115.txt 2276115 rolling_resistance 12 3.0 rolling_resistance all
run si_8587117.txt 8587117 rolling_resistance+mass 12 3.0 rolling_resistance all
CROSS=1 run si_2276072.txt 2276072 mass 12 3.0 "mass[box]" all
run si_2276136.txt 2276136 constant_acceleration+angular_damping 12 3.0 angular_damping all
run si_5025137.txt 5025137 rolling_resistance+mass 12 3.0 "mass[box]" all
run si_2276128.txt 2276128 rolling_resistance 12 3.0 rolling_resistance all
